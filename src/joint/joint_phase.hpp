#pragma once
// Step 4 of the time step (DESIGN.md §1): forces of every intact joint added to the
// node forces, histories updated, joints that meet the failure criterion broken for
// good with their time, position and mode recorded.
#include <vector>

#include "joint/joint_force.hpp"
#include "model/model.hpp"

namespace dsdem {

struct JointPhaseTotals {
  double energy = 0.0;       // elastic energy stored in all intact joints, J/m
  double dissipation = 0.0;  // dissipated in this call, J/m
  Index broken_now = 0;      // joints that broke in this call
};

// Reads the current positions X + u of nodes, adds the joint forces to nodes.f.
// damage_enabled = false (gravity stage) freezes the joint histories: no damage, no
// break. Serial: the scatter into nodes.f is in joint order, so results are
// bit-identical run to run. thickness (m) scales forces and energies (plane stress);
// plane strain is per unit thickness.
JointPhaseTotals add_joint_forces(Nodes& nodes, Joints& joints,
                                  const std::vector<JointProperties>& properties, double time,
                                  bool damage_enabled = true, double thickness = 1.0);

// Per-joint results of evaluate_joints, for a deterministic parallel gather (issue 7):
// the forces on the joint's face-a nodes a0, a1 (b0, b1 get their negatives: half the
// buffer, issue 7 memory; zero for a broken joint), its elastic energy
// and the energy it dissipated in this call. Sized by evaluate_joints (no allocation
// once sized).
struct JointPhaseBuffers {
  std::vector<std::array<Vec2, 2>> force;  // N on a0, a1 (b0, b1: minus these), times the thickness
  std::vector<double> energy;              // J/m
  std::vector<double> dissipation;         // J/m
  std::vector<JointLawConstants> law;      // per joint property, law_constants(p)
  void resize(std::size_t n);
  // Sizes the buffers for n joints and computes the law constants of the properties
  // (call again if the properties change).
  void prepare(std::size_t n, const std::vector<JointProperties>& properties);
};

// The joint loop of add_joint_forces without the scatter: every joint independent, so
// the loop is an orphaned `omp for` (static schedule) — call it from inside a parallel
// region to share the joints among the threads, or from serial code. Histories and
// breaks are updated as in add_joint_forces. The caller adds buf.force to the nodes
// (in a fixed order) and sums buf.energy / buf.dissipation; broken_now is returned
// through *broken_now (added to with an atomic, exact for any thread count). The law
// constants come from buf.law (buf.prepare() first).
void evaluate_joints(const Nodes& nodes, Joints& joints, double time, bool damage_enabled, double thickness, JointPhaseBuffers& buf,
                     Index& broken_now);

}  // namespace dsdem
