#include "joint/joint_phase.hpp"

namespace dsdem {

JointPhaseTotals add_joint_forces(Nodes& nodes, Joints& joints,
                                  const std::vector<JointProperties>& properties, double time,
                                  bool damage_enabled, double thickness) {
  JointPhaseTotals tot;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (joints.broken[j]) continue;  // contact takes over (DESIGN.md §3)
    const auto& nd = joints.nodes[j];
    const JointNodePositions x{nodes.x(nd[0]), nodes.x(nd[1]), nodes.x(nd[2]), nodes.x(nd[3])};
    // Separations from displacements: the two faces coincide in the reference.
    const JointSeparations delta{
        (nodes.X[nd[2]] - nodes.X[nd[0]]) + (nodes.u[nd[2]] - nodes.u[nd[0]]),
        (nodes.X[nd[3]] - nodes.X[nd[1]]) + (nodes.u[nd[3]] - nodes.u[nd[1]])};
    const JointForceResult r = joint_force(x, delta, joints.length0[j],
                                           properties[joints.property[j]], joints.state[j],
                                           damage_enabled);
    joints.state[j] = r.state;
    joints.damage[j] = 0.5 * (r.state[0].damage + r.state[1].damage);
    joints.dissipated[j] += thickness * r.dissipation;
    tot.dissipation += thickness * r.dissipation;
    if (r.failed_now) {
      // Both ends carry no tension or cohesion any more: drop the joint, keep the
      // energy it still stores as dissipated so the balance closes.
      joints.broken[j] = 1;
      joints.break_time[j] = time;
      joints.break_position[j] = 0.25 * (x[0] + x[1] + x[2] + x[3]);
      joints.break_mode[j] = r.mode;
      joints.dissipated[j] += thickness * r.energy;
      tot.dissipation += thickness * r.energy;
      ++tot.broken_now;
      continue;
    }
    for (int k = 0; k < 4; ++k) nodes.f[nd[k]] += thickness * r.f[k];
    tot.energy += thickness * r.energy;
  }
  return tot;
}

}  // namespace dsdem
