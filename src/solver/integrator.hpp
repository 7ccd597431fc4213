#pragma once
// Velocity Verlet with lumped masses (docs/theory.md §1, phases 1 and 8), on node ranges so the
// execution layer may run them on any thread's nodes. Phase 1 also restarts the force sum
// at gravity (phase 2) in the same node loop: once the kick has read the acceleration,
// the array that held it (Nodes::a) starts the step's force sum.
#include <cstddef>
#include <span>

#include "model/model.hpp"
#include "solver/constraints.hpp"

namespace dsdem::solver {

struct KickDrift {
  double dt = 0.0;                   // s
  Vec2 gravity = Vec2::Zero();       // m/s^2
  double t_half = 0.0, t_end = 0.0;  // s: the step's middle and end
  // When damping is booked: the displacements before the drift (out) and the damping
  // forces to clear; null otherwise.
  Vec2* u_prev = nullptr;
  Vec2* damping_force = nullptr;
};

// v(n+1/2) = v(n) + dt/2 a(n); x(n+1) = x(n) + dt v(n+1/2); force sum = m g; then the
// prescribed velocities (and their drift redone with them) and displacements of the
// nodes in [begin, end), in list order (a later dof on the same node and direction wins).
inline void kick_and_drift(Nodes& n, const KickDrift& k, std::span<const PrescribedDof> constraints,
                           std::size_t begin, std::size_t end) {
  const double dt = k.dt;
  const Vec2 g = k.gravity;
  // Raw pointers and the damping test out of the loop: the stores through them cannot
  // move the arrays, so nothing is reloaded per node.
  Vec2* const v = n.v.data();
  Vec2* const u = n.u.data();
  Vec2* const a = n.a.data();
  const double* const m = n.m.data();
  if (Vec2* const u_prev = k.u_prev) {
    Vec2* const damping = k.damping_force;
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
  auto mine = [begin, end](const PrescribedDof& d) {
    return static_cast<std::size_t>(d.node) >= begin && static_cast<std::size_t>(d.node) < end;
  };
  // The drift redone with the prescribed velocity: the same expression u_prev + dt v as
  // above, so bit-identical to prescribing before the drift.
  for (const auto& d : constraints)
    if (mine(d)) n.v[d.node][d.dir] = prescribed_velocity(d, k.t_half);
  for (const auto& d : constraints)
    if (mine(d)) n.u[d.node][d.dir] = d.u_prev + dt * n.v[d.node][d.dir];
  for (const auto& d : constraints)
    if (mine(d) && d.kind == PrescribedDof::Displacement) n.u[d.node][d.dir] = d.u_start + d.history->at(k.t_end - d.t_start);
}

// a(n+1) = f / m in place (Nodes::a held the force sum); v(n+1) = v(n+1/2) + dt/2 a(n+1);
// then the prescribed velocities at t_end, of the nodes in [begin, end).
inline void finish_kick(Nodes& n, double dt, double t_end, std::span<const PrescribedDof> constraints,
                        std::size_t begin, std::size_t end) {
  Vec2* const v = n.v.data();
  Vec2* const a = n.a.data();
  const double* const m = n.m.data();
  for (std::size_t i = begin; i < end; ++i) {
    a[i] = m[i] > 0.0 ? Vec2(a[i] / m[i]) : Vec2(Vec2::Zero());
    v[i] += 0.5 * dt * a[i];
  }
  for (const auto& d : constraints)
    if (static_cast<std::size_t>(d.node) >= begin && static_cast<std::size_t>(d.node) < end)
      n.v[d.node][d.dir] = prescribed_velocity(d, t_end);
}

}  // namespace dsdem::solver
