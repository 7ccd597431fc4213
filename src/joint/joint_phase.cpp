#include "joint/joint_phase.hpp"

namespace dsdem {

namespace {

// One intact joint: its forces on face a's two nodes (times thickness; face b gets
// their negatives, joint_force makes them so exactly), energy and dissipation; breaks it
// when it fails. Returns true when it broke now.
inline bool joint_step(const Nodes& nodes, Joints& joints, const std::vector<JointLawConstants>& law, std::size_t j, double time,
                       bool damage_enabled, double thickness,
                       std::array<Vec2, 2>& f, double& energy, double& dissipation) {
  const auto& nd = joints.nodes[j];
  const JointNodePositions x{nodes.x(nd[0]), nodes.x(nd[1]), nodes.x(nd[2]), nodes.x(nd[3])};
  // Separations from displacements: the two faces coincide in the reference.
  const JointSeparations delta{(nodes.X[nd[2]] - nodes.X[nd[0]]) + (nodes.u[nd[2]] - nodes.u[nd[0]]),
                               (nodes.X[nd[3]] - nodes.X[nd[1]]) + (nodes.u[nd[3]] - nodes.u[nd[1]])};
  // A penalty joint's stiffness follows its local element size (DESIGN.md §3).
  const JointLawConstants& k = law[joints.property[j]];
  const double s = joints.stiffness_scale[j];
  const JointForceResult r = s == 1.0 ? joint_force(x, delta, joints.length0[j], k, joints.state[j], damage_enabled)
                                      : joint_force(x, delta, joints.length0[j], scaled(k, s), joints.state[j], damage_enabled);
  joints.state[j] = r.state;
  joints.damage[j] = 0.5 * (r.state[0].damage + r.state[1].damage);
  joints.dissipated[j] += thickness * r.dissipation;
  dissipation = thickness * r.dissipation;
  if (r.failed_now) {
    // Both ends carry no tension or cohesion any more: drop the joint, keep the
    // energy it still stores as dissipated so the balance closes.
    joints.broken[j] = 1;
    joints.break_time[j] = time;
    joints.break_position[j] = 0.25 * (x[0] + x[1] + x[2] + x[3]);
    joints.break_mode[j] = r.mode;
    joints.dissipated[j] += thickness * r.energy;
    dissipation += thickness * r.energy;
    f = {Vec2::Zero(), Vec2::Zero()};
    energy = 0.0;
    return true;
  }
  for (int k = 0; k < 2; ++k) f[k] = thickness * r.f[k];
  energy = thickness * r.energy;
  return false;
}

}  // namespace

JointPhaseTotals add_joint_forces(Nodes& nodes, Joints& joints,
                                  const std::vector<JointProperties>& properties, double time,
                                  bool damage_enabled, double thickness) {
  JointPhaseTotals tot;
  std::vector<JointLawConstants> law(properties.size());
  for (std::size_t k = 0; k < properties.size(); ++k) law[k] = law_constants(properties[k]);
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (joints.broken[j]) continue;  // contact takes over (DESIGN.md §3)
    std::array<Vec2, 2> f;
    double energy = 0.0, dissipation = 0.0;
    const bool broke = joint_step(nodes, joints, law, j, time, damage_enabled, thickness, f, energy, dissipation);
    tot.dissipation += dissipation;
    if (broke) {
      ++tot.broken_now;
      continue;
    }
    const auto& nd = joints.nodes[j];
    for (int k = 0; k < 2; ++k) {
      nodes.f[nd[k]] += f[k];
      nodes.f[nd[2 + k]] -= f[k];  // == += (-f[k]) bit for bit
    }
    tot.energy += energy;
  }
  return tot;
}

void JointPhaseBuffers::prepare(std::size_t n, const std::vector<JointProperties>& properties) {
  resize(n);
  law.resize(properties.size());
  for (std::size_t k = 0; k < properties.size(); ++k) law[k] = law_constants(properties[k]);
}

void JointPhaseBuffers::resize(std::size_t n) {
  if (force.size() == n) return;
  force.assign(n, {Vec2::Zero(), Vec2::Zero()});
  energy.assign(n, 0.0);
  dissipation.assign(n, 0.0);
}

void evaluate_joints(const Nodes& nodes, Joints& joints, double time, bool damage_enabled, double thickness, JointPhaseBuffers& buf,
                     Index& broken_now) {
  const std::ptrdiff_t nj = static_cast<std::ptrdiff_t>(joints.size());
  Index broke = 0;
#pragma omp for schedule(static) nowait
  for (std::ptrdiff_t j = 0; j < nj; ++j) {
    if (joints.broken[j]) {  // contact takes over (DESIGN.md §3); its force slot stays zero
      buf.dissipation[j] = 0.0;
      continue;
    }
    if (joint_step(nodes, joints, buf.law, static_cast<std::size_t>(j), time, damage_enabled, thickness,
                   buf.force[j], buf.energy[j], buf.dissipation[j]))
      ++broke;
  }
  if (broke) {
#pragma omp atomic
    broken_now += broke;
  }
}

}  // namespace dsdem
