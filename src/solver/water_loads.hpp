#pragma once
// Water at rest on the model (docs/theory.md §8): which triangle edges the water loads, and
// each triangle's water forces of the last step for their work. The element kernels add
// a triangle's water forces to its internal force (the total stress of §8 item 1 and
// the tractions of items 2-3 on its own edges), so they reach the nodes through the
// element scatter with the same bits for any thread count.
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "model/model.hpp"
#include "solver/node_forces.hpp"
#include "water/hydrostatic.hpp"

namespace dsdem::solver {

// The water of a stage.
struct WaterSetup {
  water::PiezometricLine line;
  double density = 1000.0;       // kg/m^3
  double gravity = 9.81;         // m/s^2, the magnitude of the model's gravity
  // true: pore pressure in the whole saturated solid (elements, every joint face, exposed
  // edges); false: only in the named discontinuities (joints on named curves), broken
  // joints and on exposed edges, the intact matrix and its joints dry.
  bool pore_pressure_in_matrix = true;
  // Water in a crack up to a level (m), by curve group of the model; it replaces the
  // line's pressure on the faces of that curve's joints.
  std::vector<std::pair<Index, double>> crack_levels;
  // A pore-pressure ratio ru (Bishop & Morgenstern): the line is then the ground surface
  // and each material's unit weight, ru rho g, scales the pressure below it (by material
  // index; empty: rho_w g everywhere).
  double ru = 0.0;
  std::vector<double> material_unit_weight;
  // Moving water (docs/theory.md §11) over x in [moving_x_min, moving_x_max] replaces the line's
  // pressure on exposed edges whose midpoint lies over that span (NaN: none).
  double moving_x_min = std::numeric_limits<double>::quiet_NaN();
  double moving_x_max = std::numeric_limits<double>::quiet_NaN();
  bool under_moving_water(const Vec2& a, const Vec2& b) const {
    const double xm = 0.5 * (a.x() + b.x());
    return xm >= moving_x_min && xm <= moving_x_max;  // false with NaN
  }
  double unit_weight() const { return density * gravity; }
  double unit_weight(Index material) const {
    return material_unit_weight.empty() ? unit_weight() : material_unit_weight[material];
  }
};

class WaterLoads {
 public:
  // The stage's water (sizes the per-triangle arrays on first use). Throws
  // std::invalid_argument if a crack level names no curve group of the model.
  void set(const Model& m, WaterSetup w);
  // No water from now: the forces fall to zero (the next step books the last half of
  // their work).
  void clear();
  // Water forces act or still have work to book.
  bool active() const { return active_; }
  bool has_water() const { return has_water_; }
  const WaterSetup& setup() const { return setup_; }

  // Triangle t's water forces at its current corners x (counter-clockwise, as conn), added
  // to force; its work over the step, trapezoidal on the corners' displacement increments
  // dt v (the drift's own, v the half-step velocities), kept in work(t) unless `book` is off
  // (the initial forces: no step taken).
  [[gnu::always_inline]] void add(std::size_t t, const std::array<Vec2, 3>& x, const std::array<Index, 3>& c,
                                  Index material, const Nodes& n, const Joints& J, double dt, bool book,
                                  std::array<Vec2, 3>& force) {
    const std::array<Vec2, 3> f = has_water_ ? water::triangle_forces(input(t, x, n, J), setup_.line,
                                                                      setup_.unit_weight(material))
                                             : std::array<Vec2, 3>{};
    double w = 0.0;
    if (book)
      for (int k = 0; k < 3; ++k) w += drift_work(previous_[t][k], f[k], dt * n.v[c[k]]);
    work_[t] = w;
    previous_[t] = f;
    for (int k = 0; k < 3; ++k) force[k] += f[k];
  }
  double work(std::size_t t) const { return work_[t]; }
  std::size_t size() const { return work_.size(); }

  // Pore pressure at a point of a material, Pa (0 without water).
  double pressure(Vec2 x, Index material) const {
    return has_water_ ? water::pressure(setup_.line, setup_.unit_weight(material), x) : 0.0;
  }

  // The checkpoint's part: the last forces per triangle (their work's first half).
  const std::vector<std::array<Vec2, 3>>& previous_forces() const { return previous_; }
  void restore_previous_forces(std::vector<std::array<Vec2, 3>> f) { previous_ = std::move(f); }

 private:
  water::TriangleWater input(std::size_t t, const std::array<Vec2, 3>& x, const Nodes& n, const Joints& J) const {
    water::TriangleWater in;
    in.x = x;
    in.pore_pressure = setup_.pore_pressure_in_matrix;
    in.level_unit_weight = unit_weight_;
    for (int k = 0; k < 3; ++k) {
      if (!(exposed_[t] & (1u << k))) continue;
      const Index j = edge_joint_[t][k];
      const double level = j == kNoIndex ? kNoLevel : crack_level_of_curve(J.curve_group[j]);
      if (!std::isnan(level)) {
        if (!holds_water(j, n, J)) continue;
        in.edge[k] = water::EdgeWater::level;
        in.level[k] = level;
      } else if (setup_.pore_pressure_in_matrix || j == kNoIndex || J.broken[j] || J.curve_group[j] != kNoIndex) {
        if (setup_.under_moving_water(x[k], x[(k + 1) % 3])) continue;
        in.edge[k] = water::EdgeWater::line;
      }
    }
    return in;
  }
  // A crack holds its water while its faces stay within the joint's own length of each
  // other; opened farther (the block behind it has slid away) the water has drained.
  static bool holds_water(Index j, const Nodes& n, const Joints& J) {
    const auto& jn = J.nodes[j];
    const double l2 = J.length0[j] * J.length0[j];
    return (n.x(jn[0]) - n.x(jn[2])).squaredNorm() <= l2 && (n.x(jn[1]) - n.x(jn[3])).squaredNorm() <= l2;
  }
  double crack_level_of_curve(Index g) const {
    return g == kNoIndex || static_cast<std::size_t>(g) >= crack_level_.size() ? kNoLevel : crack_level_[g];
  }
  void build_edges(const Model& m);

  static constexpr double kNoLevel = std::numeric_limits<double>::quiet_NaN();
  WaterSetup setup_;
  double unit_weight_ = 0.0;
  bool active_ = false;
  bool has_water_ = false;
  // Per triangle: bit k when edge k (corner k -> k + 1) is on no other triangle (the
  // model's surface, a joint face), and the joint on that edge (or kNoIndex).
  std::vector<std::uint8_t> exposed_;
  std::vector<std::array<Index, 3>> edge_joint_;
  std::vector<double> crack_level_;  // per model group, NaN where none
  std::vector<std::array<Vec2, 3>> previous_;
  std::vector<double> work_;
};

}  // namespace dsdem::solver
