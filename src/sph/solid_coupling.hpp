#pragma once
// Two-way coupling of SPH water with a deforming solid (docs/theory.md §11): boundary particles
// ride the solid's exposed edges, placed from the edge's two nodes through the linear shape
// functions (1 - s, s), and the water's force on them goes back to the same two nodes
// through the same functions (as contact does, paper eq. 5). The solid is seen only as node
// positions: this unit knows nothing of the solver.
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "model/types.hpp"
#include "sph/fluid.hpp"
#include "sph/particles.hpp"

namespace dsdem::sph {

// An edge the water may meet: nodes a -> b with the solid on its left, so that the fluid's
// side is on its right and the unit normal into the fluid is (t_y, -t_x), t = (b - a) / |b - a|:
// the outward normal of a counter-clockwise triangle's edge.
// A face of a triangle that may separate from its neighbours (a discrete element) names
// the triangle's third node c: its particles stay inside that triangle, so that a fragment
// carries its own wall when its joints open, and none pokes out of it.
struct SolidEdge {
  Index a = kNoIndex, b = kNoIndex;
  Index c = kNoIndex;  // the owning triangle's third node; kNoIndex: a face of a continuous solid
};

// Where a boundary particle riding an edge sits: (1 - s) a + s b - d n, n the edge's unit
// normal into the fluid, d the depth behind the face.
inline Vec2 edge_normal(const Vec2& a, const Vec2& b) {
  const Vec2 t = (b - a).normalized();
  return Vec2(t.y(), -t.x());
}

// Lays boundary particles behind the edges, whose nodes are at x (indexed by node): stations
// spaced about dp along each run of continuous edges (a chain turning by under 30 degrees;
// an edge alone: n = max(1, round(L / dp)) stations at s = (i + 1/2) / n, its run's spacing
// L_run / round(L_run / dp) otherwise, whatever the edges' own lengths) and `layers` rows at
// depths (k + 1/2) dp behind the face (the face halfway between the fluid's first row and the
// walls' first, as sph::add_tank_walls). A particle behind two edges (a convex corner) is
// kept by the nearer face only (the lower edge index on a tie), so a corner is covered once.
// A fragment's faces (edges naming their triangle's third node) keep their particles inside
// their triangle and compete only with its other faces. A triangle those rows leave with
// under half its share (area / dp^2, at least one: an inradius under about dp) instead has
// each face fill its part of it (nearer that face than the others) with rows parallel to
// it, about one particle per dp^2 however small the triangle, one at its incentre when it is
// under about dp^2: the grains of a granular slide, a few dp across, do not let water through.
// Each particle's edge is its index in `edges`. Densities hydrostatic below `surface`.
void lay_edge_particles(BoundaryParticles& walls, std::span<const SolidEdge> edges, std::span<const Vec2> x,
                        int layers, const FluidParameters& par, double surface);

class SolidCoupling {
 public:
  // The coupled edges (the `edge` of the fluid's boundary particles indexes them) and their
  // nodes' positions now (x by node), the positions the particles were laid at (the fluid's
  // cell lists hold them until its next step). Turns on the fluid's boundary-force
  // recording and maps the current forces to the nodes (forces()). Throws
  // std::invalid_argument if a boundary particle names an edge out of range.
  SolidCoupling(std::vector<SolidEdge> edges, Fluid& fluid, std::span<const Vec2> x);

  // The solid nodes the water pushes, sorted and unique; the arrays below are in this order.
  std::span<const Index> nodes() const { return nodes_; }
  // Where the nodes are at the end of the coming step: the caller fills it before advance().
  std::span<Vec2> next_positions() { return x_next_; }
  // The water's force on each node (N/m) for the solid step just advanced: the mean of the
  // sub-steps' forces at their ends. Each sub-step's end force kicks the fluid for one
  // sub-step in all (half before, half after that instant), as the mean kicks the solid for
  // one solid step: over the run the impulses are equal and opposite (momentum conserved).
  std::span<const Vec2> forces() const { return force_; }
  // Their sum over the coupled boundary particles before the mapping to nodes (the check
  // that the mapping conserves the force).
  Vec2 particle_force_sum() const { return particle_sum_; }

  // Advances the fluid by dt in sub-steps no longer than its stable step while the nodes
  // move at constant velocity from their last positions to next_positions(): before each
  // sub-step the riding particles are placed at the sub-step's end, their velocities the
  // nodes' (x_next - x_last) / dt through the shape functions (the velocity conjugate to
  // the force mapping: the power the water receives is the power the nodes give). Returns
  // the number of sub-steps. Serial loops in fixed order: the same bits for any thread
  // count; nothing allocates.
  int advance(Fluid& fluid, double dt);

  // Called after each sub-step (tests: the momentum balance at every force evaluation).
  void set_substep_observer(std::function<void(const Fluid&)> f) { observer_ = std::move(f); }

  // What the next advance() reads from the last (a checkpoint; fluid_state.cpp), per node
  // in nodes() order: the positions at the last step's end and the ones set for the next,
  // the last step's forces and their particle sum.
  struct State {
    std::vector<Vec2> x_last, x_next, force;
    Vec2 particle_sum = Vec2::Zero();
  };
  State state() const { return {x_last_, x_next_, force_, particle_sum_}; }
  // Throws std::invalid_argument unless the state has one entry per coupled node.
  void restore(const State& s);

 private:
  // Places the riding particles with the nodes at x (local order) moving at v.
  void place(Fluid& fluid, std::span<const Vec2> x, std::span<const Vec2> v) const;
  // Adds the fluid's recorded forces of the riding particles to the nodes' sums.
  void gather(const Fluid& fluid, std::vector<Vec2>& sum, Vec2& particle_sum) const;

  struct LocalEdge {
    std::size_t a, b;  // into nodes_
  };
  std::vector<LocalEdge> edges_;
  std::vector<Index> nodes_;
  std::vector<std::size_t> riding_;  // the fluid's boundary particles on an edge, in index order
  std::vector<Vec2> x_last_, x_next_, x_sub_, v_, force_;
  Vec2 particle_sum_ = Vec2::Zero();
  std::function<void(const Fluid&)> observer_;
};

}  // namespace dsdem::sph
