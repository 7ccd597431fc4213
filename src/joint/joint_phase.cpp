#include "joint/joint_phase.hpp"

#include <algorithm>

namespace dsdem {

namespace {

// One intact joint: its forces on face a's two nodes (times thickness; face b gets
// their negatives), energy and dissipation; marks it kBreakPending when it fails.
// Returns true when it broke now.
[[gnu::always_inline]] inline bool joint_step(const Nodes& nodes, Joints& joints, const std::vector<JointLawConstants>& law, std::size_t j,
                       bool damage_enabled, double thickness, std::array<Vec2, 2>& f, double& energy,
                       double& dissipation) {
  const auto& nd = joints.nodes[j];
  const JointNodePositions x{nodes.x(nd[0]), nodes.x(nd[1]), nodes.x(nd[2]), nodes.x(nd[3])};
  // Separations from displacements: the two faces coincide in the reference.
  const JointSeparations delta{(nodes.X[nd[2]] - nodes.X[nd[0]]) + (nodes.u[nd[2]] - nodes.u[nd[0]]),
                               (nodes.X[nd[3]] - nodes.X[nd[1]]) + (nodes.u[nd[3]] - nodes.u[nd[1]])};
  // A penalty joint's stiffness follows its local element size (docs/theory.md §3); a scale
  // of 1 leaves the constants' bits as they are (x * 1.0 == x).
  const JointLawConstants k = scaled(law[joints.property[j]], joints.stiffness_scale[j]);
  const JointUpdate r = joint_update(x, delta, joints.length0[j], k, joints.state[j], joints.end_mode[j], damage_enabled);
  dissipation = thickness * r.dissipation;
  if (r.failed_now) [[unlikely]] {
    // Both ends carry no tension or cohesion any more: drop the joint, keep the
    // energy it still stores as dissipated so the balance closes.
    joints.broken[j] = Joints::kBreakPending;
    dissipation += thickness * r.energy;
    f = {Vec2::Zero(), Vec2::Zero()};
    energy = 0.0;
    return true;
  }
  for (int k = 0; k < 2; ++k) f[k] = thickness * r.fa[k];
  energy = thickness * r.energy;
  return false;
}

}  // namespace

JointPhaseTotals add_joint_forces(const Nodes& nodes, std::vector<Vec2>& force, Joints& joints,
                                  const std::vector<JointProperties>& properties, double time,
                                  bool damage_enabled, double thickness) {
  JointPhaseTotals tot;
  std::vector<JointLawConstants> law(properties.size());
  for (std::size_t k = 0; k < properties.size(); ++k) law[k] = law_constants(properties[k]);
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (joints.broken[j]) continue;  // contact takes over (docs/theory.md §3)
    std::array<Vec2, 2> f;
    double energy = 0.0, dissipation = 0.0;
    const bool broke = joint_step(nodes, joints, law, j, damage_enabled, thickness, f, energy, dissipation);
    tot.dissipation += dissipation;
    if (broke) {
      ++tot.broken_now;
      continue;
    }
    const auto& nd = joints.nodes[j];
    for (int k = 0; k < 2; ++k) {
      force[nd[k]] += f[k];
      force[nd[2 + k]] -= f[k];  // == += (-f[k]) bit for bit
    }
    tot.energy += energy;
  }
  if (tot.broken_now) record_new_breaks(nodes, joints, time);
  return tot;
}

void JointPhaseBuffers::prepare(Joints& joints, const std::vector<JointProperties>& properties) {
  const std::size_t n = joints.size();
  if (force.size() != n) force.assign(n, {Vec2::Zero(), Vec2::Zero()});
  const std::size_t blocks = joint_blocks(n);
  block_energy.assign(blocks, 0.0);
  block_dissipation.assign(blocks, 0.0);
  // Address space for every joint's record; pages become resident only as joints break.
  joints.breaks.reserve(n);
  law.resize(properties.size());
  for (std::size_t k = 0; k < properties.size(); ++k) law[k] = law_constants(properties[k]);
}

double JointPhaseBuffers::energy() const {
  double total = 0.0;
  for (double e : block_energy) total += e;
  return total;
}

double JointPhaseBuffers::dissipation() const {
  double total = 0.0;
  for (double d : block_dissipation) total += d;
  return total;
}

void evaluate_joints(const Nodes& nodes, Joints& joints, bool damage_enabled, double thickness, JointPhaseBuffers& buf,
                     Index& broken_now, std::size_t block_begin, std::size_t block_end) {
  const std::size_t nj = joints.size();
  Index broke = 0;
  const std::size_t b_end = std::min(block_end, joint_blocks(nj));
  for (std::size_t b = block_begin; b < b_end; ++b) {
    const std::size_t begin = b * kJointBlock;
    const std::size_t end = std::min(begin + kJointBlock, nj);
    // Broken joints add nothing (their per-joint terms were +0, which left the sums' bits alone).
    double energy = 0.0, dissipation = 0.0;
    for (std::size_t j = begin; j < end; ++j) {
      if (joints.broken[j]) continue;  // contact takes over (docs/theory.md §3); its force slot stays zero
      double e, d;
      if (joint_step(nodes, joints, buf.law, j, damage_enabled, thickness, buf.force[j], e, d)) ++broke;
      energy += e;
      dissipation += d;
    }
    buf.block_energy[b] = energy;
    buf.block_dissipation[b] = dissipation;
  }
  if (broke) {
#pragma omp atomic
    broken_now += broke;
  }
}

void record_new_breaks(const Nodes& nodes, Joints& joints, double time) {
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (joints.broken[j] != Joints::kBreakPending) continue;
    const auto& nd = joints.nodes[j];
    const Vec2 mid = 0.25 * (nodes.x(nd[0]) + nodes.x(nd[1]) + nodes.x(nd[2]) + nodes.x(nd[3]));
    joints.breaks.push_back({static_cast<Index>(j), time, mid});
    joints.broken[j] = 1;
  }
}

}  // namespace dsdem
