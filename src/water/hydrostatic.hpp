#pragma once
// Water at rest (docs/theory.md §8): the hydrostatic pressure below a piezometric line and
// the nodal forces it puts on a saturated solid in total stress (tension positive):
// -p I in the elements, -p n on exposed edges and joint faces.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "model/types.hpp"

namespace dsdem::water {

// A piezometric line z_w(x): a polyline with increasing x (the pool level in open water,
// the water table in the slope), held at its end values outside its x range.
class PiezometricLine {
 public:
  PiezometricLine() = default;
  // Throws std::invalid_argument unless there are >= 1 points with strictly increasing x.
  explicit PiezometricLine(std::vector<Vec2> points);
  // A horizontal line at elevation z.
  static PiezometricLine level(double z) { return PiezometricLine({Vec2(0.0, z)}); }

  double elevation(double x) const;
  double highest() const { return highest_; }  // the largest z_w on the line
  std::span<const Vec2> points() const { return points_; }
  bool empty() const { return points_.empty(); }

 private:
  std::vector<Vec2> points_;
  double highest_ = 0.0;
};

// Hydrostatic pressure p = rho_w g (z_w(x) - z) where positive, else 0 (Pa).
// `unit_weight` is rho_w g (N/m^3).
inline double pressure(const PiezometricLine& line, double unit_weight, Vec2 x) {
  const double p = unit_weight * (line.elevation(x.x()) - x.y());
  return p > 0.0 ? p : 0.0;
}

// Consistent nodal forces of the water on the edge a -> b of a solid lying on its left
// (a counter-clockwise triangle's edge): the traction -p n with n the outward normal,
// integrated exactly with the linear shape functions. p along the edge is piecewise
// linear (kinks under the line's vertices and where it reaches 0), so the edge is cut
// there and each piece integrated by Simpson's rule, exact for its quadratic integrand.
std::array<Vec2, 2> edge_forces(const PiezometricLine& line, double unit_weight, Vec2 a, Vec2 b);

// Same for a pressure that is linear in z only: p = unit_weight (level - z) where positive
// (the water in a crack filled up to `level`).
std::array<Vec2, 2> edge_forces_to_level(double level, double unit_weight, Vec2 a, Vec2 b);

// The pore-pressure part of a triangle's internal force in total stress, -p I: at
// corner k, p A grad N_k in the current configuration (p at the centroid; exact for the
// CST with p linear). Corners counter-clockwise.
std::array<Vec2, 3> element_pore_forces(const std::array<Vec2, 3>& x, double p);

// What loads one edge of a triangle: nothing (an edge inside a continuous mesh, or a
// joint face kept dry), the piezometric line, or the water in a crack up to a level.
enum class EdgeWater : std::uint8_t { dry, line, level };

struct TriangleWater {
  std::array<Vec2, 3> x;            // current corners, counter-clockwise (edge k: corner k -> k + 1)
  bool pore_pressure = true;        // -p I in the element (saturated matrix)
  std::array<EdgeWater, 3> edge{EdgeWater::dry, EdgeWater::dry, EdgeWater::dry};
  std::array<double, 3> level{};    // m, for EdgeWater::level
  double level_unit_weight = 0.0;   // rho_w g of the water in cracks (EdgeWater::level), N/m^3
};

// All the water's nodal forces on one triangle (docs/theory.md §8, items 1-3): its pore
// pressure and the traction on its loaded edges; unit_weight scales the line's pressure. For p linear over a triangle whose three
// edges are loaded by the line, the sum is the corner's share of the buoyancy,
// rho_w g A / 3 upward each.
std::array<Vec2, 3> triangle_forces(const TriangleWater& in, const PiezometricLine& line, double unit_weight);

}  // namespace dsdem::water
