#include "joint/joint_force.hpp"

#include <algorithm>
#include <cmath>

namespace dsdem {

JointKinematics joint_kinematics(const JointNodePositions& x, const JointSeparations& delta) {
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
  if (!(k.length > 2e-12 * l1)) {
    const double scale = std::max(ea.norm(), eb.norm());
    if (k.length <= 1e-12 * scale) {  // faces crossed
      d = ea.norm() >= eb.norm() ? ea : eb;
      len = d.norm();
    }
  }
  if (len > 0.0) {
    k.t = d / len;
    k.n = Vec2(k.t.y(), -k.t.x());  // clockwise turn: outward of tri_a (CCW along a0->a1)
  }
  for (int i = 0; i < 2; ++i) {
    k.dn[i] = delta[i].dot(k.n);
    k.ds[i] = delta[i].dot(k.t);
  }
  return k;
}

JointKinematics joint_kinematics(const JointNodePositions& x) {
  return joint_kinematics(x, {x[2] - x[0], x[3] - x[1]});
}

JointForceResult joint_force(const JointNodePositions& x, double length0,
                             const JointProperties& p,
                             const std::array<JointPointState, 2>& state,
                             bool damage_enabled) {
  return joint_force(x, {x[2] - x[0], x[3] - x[1]}, length0, p, state, damage_enabled);
}

JointForceResult joint_force(const JointNodePositions& x, const JointSeparations& delta,
                             double length0, const JointProperties& p,
                             const std::array<JointPointState, 2>& state,
                             bool damage_enabled) {
  return joint_force(x, delta, length0, law_constants(p), state, damage_enabled);
}

JointForceResult joint_force(const JointNodePositions& x, const JointSeparations& delta,
                             double length0, const JointLawConstants& p,
                             const std::array<JointPointState, 2>& state,
                             bool damage_enabled) {
  JointForceResult r;
  r.kin = joint_kinematics(x, delta);
  const double w = 0.5 * length0;  // Lobatto weight of each end point
  bool any_failed_now = false;
  for (int i = 0; i < 2; ++i) {
    const CohesiveResponse c = cohesive_law(r.kin.dn[i], r.kin.ds[i], p, state[i], damage_enabled);
    r.sn[i] = c.sn;
    r.ss[i] = c.ss;
    r.state[i] = c.state;
    r.energy += w * c.energy;
    r.dissipation += w * c.dissipation;
    any_failed_now = any_failed_now || c.failed_now;
    // Traction pulls face a toward face b in tension and along the slip in shear.
    const Vec2 fa = w * (c.sn * r.kin.n + c.ss * r.kin.t);
    r.f[i] = fa;
    r.f[2 + i] = -fa;
  }
  r.failed_now = any_failed_now && r.state[0].damage >= 1.0 && r.state[1].damage >= 1.0;
  if (r.failed_now) {
    const BreakMode m0 = r.state[0].mode, m1 = r.state[1].mode;
    r.mode = m0 == m1 ? m0 : BreakMode::Mixed;
  }
  return r;
}

double joint_end_stiffness(const JointProperties& p, double length0, double stiffness_scale) {
  const JointLawConstants k = scaled(law_constants(p), stiffness_scale);  // the law's own rule for kn, ks
  return std::max(k.kn, k.ks) * 0.5 * length0;
}

double joint_stable_dt(double m_a, double m_b, double k) {
  const double m = m_a * m_b / (m_a + m_b);
  return 2.0 * std::sqrt(m / k);
}

}  // namespace dsdem
