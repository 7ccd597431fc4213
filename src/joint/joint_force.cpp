#include "joint/joint_force.hpp"

#include <algorithm>
#include <cmath>

namespace dsdem {

JointKinematics joint_kinematics(const JointNodePositions& x) {
  return joint_kinematics(x, {x[2] - x[0], x[3] - x[1]});
}

JointForceResult joint_force(const JointNodePositions& x, double length0,
                             const JointProperties& p,
                             const std::array<JointPointState, 2>& state,
                             bool damage_enabled, const JointEndModes& modes) {
  return joint_force(x, {x[2] - x[0], x[3] - x[1]}, length0, p, state, damage_enabled, modes);
}

JointForceResult joint_force(const JointNodePositions& x, const JointSeparations& delta,
                             double length0, const JointProperties& p,
                             const std::array<JointPointState, 2>& state,
                             bool damage_enabled, const JointEndModes& modes) {
  return joint_force(x, delta, length0, law_constants(p), state, damage_enabled, modes);
}

JointForceResult joint_force(const JointNodePositions& x, const JointSeparations& delta,
                             double length0, const JointLawConstants& p,
                             const std::array<JointPointState, 2>& state,
                             bool damage_enabled, const JointEndModes& modes) {
  JointForceResult r;
  r.state = state;
  r.end_mode = modes;
  const JointUpdate u = joint_update(x, delta, length0, p, r.state, r.end_mode, damage_enabled);
  for (int i = 0; i < 2; ++i) {
    r.f[i] = u.fa[i];
    r.f[2 + i] = -u.fa[i];
  }
  r.kin = u.kin;
  r.sn = u.sn;
  r.ss = u.ss;
  r.energy = u.energy;
  r.dissipation = u.dissipation;
  r.failed_now = u.failed_now;
  r.mode = u.mode;
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
