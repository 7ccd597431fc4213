#pragma once
// Forces of one 4-node zero-thickness joint (docs/theory.md §3, paper eq. 10): separations
// in the joint's current frame, the cohesive law at the two end points (Lobatto /
// nodal integration, weight L0/2 each), equal and opposite nodal forces on the faces.
#include <algorithm>
#include <array>
#include <cmath>

#include "joint/cohesive_law.hpp"

namespace dsdem {

// Node order everywhere in this header: (a0, a1, b0, b1) as in Joints::nodes.
using JointNodePositions = std::array<Vec2, 4>;

// Current local frame and separations. The tangent follows the mid-line of the two
// faces (so it rotates with the joint); the normal is the tangent turned clockwise,
// i.e. the outward normal of tri_a, pointing from face a to face b.
struct JointKinematics {
  Vec2 t = Vec2::UnitX();  // unit tangent, a0 -> a1
  Vec2 n = -Vec2::UnitY(); // unit normal, from face a to face b
  std::array<double, 2> dn{0.0, 0.0};  // opening (x_b - x_a).n at end points 0, 1, m
  std::array<double, 2> ds{0.0, 0.0};  // slip (x_b - x_a).t at end points 0, 1, m
  double length = 0.0;                 // current mid-line length, m
};
// A collapsed mid-line (length below 1e-12 of the face lengths) falls back to the
// direction of the longer face; if all four nodes coincide the frame stays (x, -y).
//
// delta[i] = x_b_i - x_a_i, the separation vector at end point i. Separations are
// tiny next to coordinates (1e-8 m against 1e3 m), so differencing positions loses
// digits: the solver passes delta from displacements, (X_b - X_a) + (u_b - u_a) with
// X_b - X_a = 0, and the positions only set the frame. The overloads without delta
// difference the positions.
using JointSeparations = std::array<Vec2, 2>;
[[gnu::always_inline]] inline JointKinematics joint_kinematics(const JointNodePositions& x, const JointSeparations& delta);
JointKinematics joint_kinematics(const JointNodePositions& x);

// One joint evaluated, histories updated in place: the hot path of the joint phase.
struct JointUpdate {
  JointKinematics kin;
  std::array<Vec2, 2> fa;  // forces on a0, a1, N per unit thickness (b0, b1: minus these)
  std::array<double, 2> sn{0.0, 0.0};  // tractions at the end points, Pa
  std::array<double, 2> ss{0.0, 0.0};
  double energy = 0.0;       // elastic energy stored in the joint, J/m (L0/2 * sum)
  double dissipation = 0.0;  // dissipated since the last evaluation, J/m
  bool failed_now = false;   // both end points have now failed (the joint breaks)
  BreakMode mode = BreakMode::None;  // when failed_now: both ends' mode if equal, else Mixed
};

struct JointForceResult {
  std::array<Vec2, 4> f;  // forces on (a0, a1, b0, b1), N per unit thickness
  JointKinematics kin;
  std::array<double, 2> sn{0.0, 0.0};  // tractions at the end points, Pa
  std::array<double, 2> ss{0.0, 0.0};
  std::array<JointPointState, 2> state;  // updated end-point histories
  JointEndModes end_mode{BreakMode::None, BreakMode::None};  // updated: how each end failed
  double energy = 0.0;       // elastic energy stored in the joint, J/m (L0/2 * sum)
  double dissipation = 0.0;  // dissipated since the last evaluation, J/m
  bool failed_now = false;   // both end points have now failed (the joint breaks)
  BreakMode mode = BreakMode::None;  // when failed_now: both ends' mode if equal, else Mixed
};

// One intact joint. length0: reference length (tractions are per reference length).
// The joint breaks (failed_now) when both end points have failed: a failed end point
// carries no tension and no cohesion, so breaking then removes no finite force. A damaged
// joint also breaks once the separation at an end point exceeds length0 (see joint_update). The
// caller sets the break time and position and stops evaluating a broken joint.
// modes: how the end points failed so far (an end that failed earlier keeps its mode).
JointForceResult joint_force(const JointNodePositions& x, const JointSeparations& delta,
                             double length0, const JointProperties& p,
                             const std::array<JointPointState, 2>& state,
                             bool damage_enabled = true, const JointEndModes& modes = {});
JointForceResult joint_force(const JointNodePositions& x, const JointSeparations& delta,
                             double length0, const JointLawConstants& k,
                             const std::array<JointPointState, 2>& state,
                             bool damage_enabled = true, const JointEndModes& modes = {});
JointForceResult joint_force(const JointNodePositions& x, double length0,
                             const JointProperties& p,
                             const std::array<JointPointState, 2>& state,
                             bool damage_enabled = true, const JointEndModes& modes = {});
// Hot path of the joint phase: the same numbers as joint_force, with the histories and
// the end modes updated in place and only face a's forces returned.
[[gnu::always_inline]] inline JointUpdate joint_update(const JointNodePositions& x, const JointSeparations& delta, double length0,
                                const JointLawConstants& k, std::array<JointPointState, 2>& state,
                                JointEndModes& modes, bool damage_enabled = true);

// Spring stiffness (N/m per unit thickness) that one end point of the joint puts
// between its two nodes: max(kn, ks) * L0/2, with kn (and ks unless given) times the
// joint's stiffness_scale.
double joint_end_stiffness(const JointProperties& p, double length0, double stiffness_scale = 1.0);

// Critical time step of two masses joined by a spring k: 2*sqrt(m/k) with m the
// reduced mass m_a*m_b/(m_a + m_b) (exact for that two-body system). The solver
// passes for k the sum of the joint end stiffnesses acting on the lighter node.
double joint_stable_dt(double m_a, double m_b, double k);

[[gnu::always_inline]] inline JointKinematics joint_kinematics(const JointNodePositions& x, const JointSeparations& delta) {
  JointKinematics k;
  const Vec2 m0 = 0.5 * (x[0] + x[2]);
  const Vec2 m1 = 0.5 * (x[1] + x[3]);
  Vec2 d = m1 - m0;
  const Vec2 ea = x[1] - x[0];
  const Vec2 eb = x[3] - x[2];
  k.length = d.norm();
  // The face lengths are at most their L1 norms: a mid-line longer than 2e-12 of those
  // cannot be collapsed, which spares two square roots in the common case.
  const double l1 = std::max(std::abs(ea.x()) + std::abs(ea.y()), std::abs(eb.x()) + std::abs(eb.y()));
  double len = k.length;
  if (!(k.length > 2e-12 * l1)) [[unlikely]] {
    const double scale = std::max(ea.norm(), eb.norm());
    if (k.length <= 1e-12 * scale) {  // faces crossed
      d = ea.norm() >= eb.norm() ? ea : eb;
      len = d.norm();
    }
  }
  if (len > 0.0) [[likely]] {
    k.t = d / len;
    k.n = Vec2(k.t.y(), -k.t.x());  // clockwise turn: outward of tri_a (CCW along a0->a1)
  }
  for (int i = 0; i < 2; ++i) {
    k.dn[i] = delta[i].dot(k.n);
    k.ds[i] = delta[i].dot(k.t);
  }
  return k;
}

[[gnu::always_inline]] inline JointUpdate joint_update(const JointNodePositions& x, const JointSeparations& delta, double length0,
                                const JointLawConstants& k, std::array<JointPointState, 2>& state,
                                JointEndModes& modes, bool damage_enabled) {
  JointUpdate r;
  r.kin = joint_kinematics(x, delta);
  const double w = 0.5 * length0;  // Lobatto weight of each end point
  bool any_failed_now = false;
#pragma GCC unroll 2
  for (int i = 0; i < 2; ++i) {
    const CohesivePoint c = cohesive_update(r.kin.dn[i], r.kin.ds[i], k, state[i], damage_enabled);
    r.sn[i] = c.sn;
    r.ss[i] = c.ss;
    r.energy += w * c.energy;
    r.dissipation += w * c.dissipation;
    if (c.failed_now) [[unlikely]] {
      any_failed_now = true;
      modes[i] = c.mode;
    }
    // Traction pulls face a toward face b in tension and along the slip in shear.
    r.fa[i] = w * (c.sn * r.kin.n + c.ss * r.kin.t);
  }
  r.failed_now = any_failed_now && state[0].damage >= 1.0 && state[1].damage >= 1.0;
  // A damaged joint whose faces have moved apart by more than its reference length no
  // longer joins the two edges it was made for: their ends now face other edges, and the
  // equal and opposite end forces, that far apart, exert a couple that no potential gives
  // (the law's frame is the mid-line's, exact for separations small next to L0 only).
  // It breaks, whatever strength a ductile law has left; contact takes over (docs/theory.md §3).
  if (!r.failed_now && (state[0].damage > 0.0 || state[1].damage > 0.0)) [[unlikely]] {
    const double l2 = length0 * length0;
    if (delta[0].squaredNorm() > l2 || delta[1].squaredNorm() > l2) {
      for (int i = 0; i < 2; ++i)
        if (state[i].damage < 1.0) {
          state[i].damage = 1.0;
          modes[i] = std::abs(r.kin.ds[i]) >= std::abs(r.kin.dn[i]) ? BreakMode::Shear : BreakMode::Tension;
        }
      r.failed_now = true;
    }
  }
  if (r.failed_now) r.mode = modes[0] == modes[1] ? modes[0] : BreakMode::Mixed;
  return r;
}

}  // namespace dsdem
