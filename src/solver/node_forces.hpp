#pragma once
// The node-force assembler (docs/theory.md §1 phases 2-7; docs/developer-guide.md §2): the one way a phase's forces
// reach the nodes' force sum (Nodes::a holds it during the step; finish_kick turns it into
// accelerations), and the one rule that books the work of a force.
//
// Each kind of force has one deterministic route into the sum, the same bits for any
// thread count:
//   force per node (gravity, Rayleigh mass damping, body forces)  add_per_node: node-local
//   forces on listed nodes (supports, viscous boundary)           add_at: in list order, one thread
//   items with fixed nodes (triangles, their water, joints)       scatter(): exec::NodeScatter
//                                                                 through exec::ElementRegion
//   items found each step (contact pairs)                         scatter(): per-node-range sums
//                                                                 of the pair records, in record
//                                                                 order (exec::PartitionedRegion)
// Gravity restarts the sum in the integrator's kick (integrator.hpp, the one declared fusion).
//
// How each force's work reaches the energy ledger (docs/theory.md §7):
//   conservative internal forces (strain, joint and contact springs): their stored energy;
//   dissipative laws (fracture, friction, dashpots, plastic flow): their dissipation as the
//     law applies it;
//   gravity: its potential, -m g . u;
//   every other force (boundary, supports, Rayleigh damping, water, new loads): drift_work.
#include <cstddef>
#include <vector>

#include "exec/team.hpp"
#include "model/types.hpp"

namespace dsdem::solver {

// The work a force does over one step as velocity Verlet applies it: F(n) and F(n+1) each
// kick half a step around the drift du = u(n+1) - u(n) = dt v(n+1/2) (docs/theory.md §1, §7).
inline double drift_work(const Vec2& f_prev, const Vec2& f, const Vec2& du) { return 0.5 * (f_prev + f).dot(du); }
inline double drift_work(const Vec3& f_prev, const Vec3& f, const Vec3& du) { return 0.5 * (f_prev + f).dot(du); }
// The same for one direction of a node (a prescribed dof's reaction).
inline double drift_work(double f_prev, double f, double du) { return 0.5 * (f_prev + f) * du; }

// For nodes of dimension D (2 or 3).
template <int D>
class NodeForcesD {
 public:
  using Vec = VecD<D>;
  explicit NodeForcesD(std::vector<Vec>& sum) : sum_(sum) {}

  // sum[i] += f(i) for every node: node-local, on the team's threads.
  template <class F>
  void add_per_node(const exec::Team& team, F&& f) {
    std::vector<Vec>& s = sum_;
    exec::parallel_for(team, s.size(), [&](std::size_t i) { s[i] += f(i); });
  }
  // One listed node's force (call in the list's order).
  void add_at(Index node, const Vec& f) { sum_[node] += f; }
  // One direction of a listed node (a prescribed dof's reaction).
  void add_at(Index node, int dir, double f) { sum_[node][dir] += f; }
  // The sum at a node so far (a reaction balances it).
  const Vec& at(Index node) const { return sum_[node]; }
  // The sum for the scatters of the element region and of the contact phase.
  std::vector<Vec>& scatter() { return sum_; }

 private:
  std::vector<Vec>& sum_;
};
using NodeForces = NodeForcesD<2>;

}  // namespace dsdem::solver
