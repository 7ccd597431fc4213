#pragma once
// Velocity Verlet with lumped masses (docs/theory.md §1, phases 1 and 8), on node ranges so the
// execution layer may run them on any thread's nodes. Phase 1 also restarts the force sum
// at gravity (phase 2) in the same node loop: once the kick has read the acceleration,
// the array that held it (Nodes::a) starts the step's force sum.
#include <cstddef>
#include <span>

#include "model/model.hpp"
#include "solver/constraints.hpp"
#include "solver/node_forces.hpp"

namespace dsdem::solver {

// The first half of a step for nodes of dimension D (2 or 3): one integrator for both.
template <int D>
struct KickDriftD {
  using Vec = VecD<D>;
  double dt = 0.0;                   // s
  Vec gravity = Vec::Zero();         // m/s^2
  double t_half = 0.0, t_end = 0.0;  // s: the step's middle and end
  // When damping is booked: the displacements before the drift (out) and the damping
  // forces to clear; null otherwise.
  Vec* u_prev = nullptr;
  Vec* damping_force = nullptr;
};
using KickDrift = KickDriftD<2>;

// The prescribed velocities (and the drift redone with them) and displacements of the nodes
// in [begin, end) after the kick and drift, in list order (a later dof on the same node and
// direction wins): kick_and_drift's end, on its own for a caller that kicks in parallel
// chunks and prescribes once.
template <int D>
inline void prescribe_drift(NodeArrays<D>& n, const KickDriftD<D>& k, std::span<const PrescribedDof> constraints,
                            std::size_t begin, std::size_t end) {
  const double dt = k.dt;
  auto mine = [begin, end](const PrescribedDof& d) {
    return static_cast<std::size_t>(d.node) >= begin && static_cast<std::size_t>(d.node) < end;
  };
  // The drift redone with the prescribed velocity: the same expression u_prev + dt v as
  // kick_and_drift's drift, so bit-identical to prescribing before the drift.
  for (const auto& d : constraints)
    if (mine(d)) n.v[d.node][d.dir] = prescribed_velocity(d, k.t_half);
  for (const auto& d : constraints)
    if (mine(d)) n.u[d.node][d.dir] = d.u_prev + dt * n.v[d.node][d.dir];
  for (const auto& d : constraints)
    if (mine(d) && d.kind == PrescribedDof::Displacement) n.u[d.node][d.dir] = d.u_start + d.history->at(k.t_end - d.t_start);
}

// v(n+1/2) = v(n) + dt/2 a(n); x(n+1) = x(n) + dt v(n+1/2); force sum = m g; then the
// prescribed velocities (and their drift redone with them) and displacements of the
// nodes in [begin, end), in list order (a later dof on the same node and direction wins).
template <int D>
inline void kick_and_drift(NodeArrays<D>& n, const KickDriftD<D>& k, std::span<const PrescribedDof> constraints,
                           std::size_t begin, std::size_t end) {
  const double dt = k.dt;
  using Vec = VecD<D>;
  const Vec g = k.gravity;
  // Raw pointers and the damping test out of the loop: the stores through them cannot
  // move the arrays, so nothing is reloaded per node.
  Vec* const v = n.v.data();
  Vec* const u = n.u.data();
  Vec* const a = n.a.data();
  const double* const m = n.m.data();
  if (Vec* const u_prev = k.u_prev) {
    Vec* const damping = k.damping_force;
    for (std::size_t i = begin; i < end; ++i) {
      v[i] += 0.5 * dt * a[i];
      u_prev[i] = u[i];
      damping[i].setZero();
      u[i] += dt * v[i];
      a[i] = m[i] * g;
    }
  } else {
    for (std::size_t i = begin; i < end; ++i) {
      v[i] += 0.5 * dt * a[i];
      u[i] += dt * v[i];
      a[i] = m[i] * g;
    }
  }
  prescribe_drift(n, k, constraints, begin, end);
}

// finish_kick's end: the prescribed velocities at t_end of the nodes in [begin, end).
template <int D>
inline void prescribe_velocity_end(NodeArrays<D>& n, double t_end, std::span<const PrescribedDof> constraints,
                                   std::size_t begin, std::size_t end) {
  for (const auto& d : constraints)
    if (static_cast<std::size_t>(d.node) >= begin && static_cast<std::size_t>(d.node) < end)
      n.v[d.node][d.dir] = prescribed_velocity(d, t_end);
}

// a(n+1) = f / m in place (Nodes::a held the force sum); v(n+1) = v(n+1/2) + dt/2 a(n+1);
// then the prescribed velocities at t_end, of the nodes in [begin, end).
template <int D>
inline void finish_kick(NodeArrays<D>& n, double dt, double t_end, std::span<const PrescribedDof> constraints,
                        std::size_t begin, std::size_t end) {
  using Vec = VecD<D>;
  Vec* const v = n.v.data();
  Vec* const a = n.a.data();
  const double* const m = n.m.data();
  for (std::size_t i = begin; i < end; ++i) {
    a[i] = m[i] > 0.0 ? Vec(a[i] / m[i]) : Vec(Vec::Zero());
    v[i] += 0.5 * dt * a[i];
  }
  prescribe_velocity_end(n, t_end, constraints, begin, end);
}

// The reactions at the prescribed dofs, at the step's end (t): each makes its node follow its
// prescribed acceleration; their work as velocity Verlet applies it (drift_work) is added to
// `work`, dof by dof, in list order.
template <int D>
inline void add_reactions(NodeArrays<D>& n, NodeForcesD<D>& forces, std::span<PrescribedDof> dofs, double t,
                          double& work) {
  for (auto& d : dofs) {
    const double reaction = n.m[d.node] * prescribed_acceleration(d, t) - forces.at(d.node)[d.dir];
    forces.add_at(d.node, d.dir, reaction);
    work += drift_work(d.reaction_prev, reaction, n.u[d.node][d.dir] - d.u_prev);
    d.reaction_prev = reaction;
  }
}

}  // namespace dsdem::solver
