#pragma once
// Step 4 of the time step (docs/theory.md §1): forces of every intact joint added to the
// node forces, histories updated, joints that meet the failure criterion broken for
// good with their time, position and mode recorded.
#include <cstddef>
#include <vector>

#include "joint/joint_force.hpp"
#include "model/model.hpp"

namespace dsdem {

struct JointPhaseTotals {
  double energy = 0.0;       // elastic energy stored in all intact joints, J/m
  double dissipation = 0.0;  // dissipated in this call, J/m
  Index broken_now = 0;      // joints that broke in this call
};

// Reads the current positions X + u of nodes, adds the joint forces to force (one per
// node, N). damage_enabled = false (gravity stage) freezes the joint histories: no
// damage, no break. Serial: the scatter into force is in joint order, so results are
// bit-identical run to run. thickness (m) scales forces and energies (plane stress);
// plane strain is per unit thickness.
JointPhaseTotals add_joint_forces(const Nodes& nodes, std::vector<Vec2>& force, Joints& joints,
                                  const std::vector<JointProperties>& properties, double time,
                                  bool damage_enabled = true, double thickness = 1.0);

// Joints per block of evaluate_joints: the unit of its work sharing and of its partial
// energy sums (fixed, so the sums do not depend on the thread count). 64: small enough
// that a thousand joints split evenly over the threads even when a crack's softening
// joints, several times dearer than elastic ones, gather in a few blocks. (Blocks are not
// handed out dynamically: triangles would then read joint forces another thread wrote.)
constexpr std::size_t kJointBlock = 64;

// Results of evaluate_joints for a deterministic parallel gather: per joint
// the forces on its face-a nodes a0, a1 (b0, b1 get their negatives; zero for a broken
// joint), per block of kJointBlock joints the elastic energy and the dissipation of
// this call summed in joint order (not per joint: memory per element).
struct JointPhaseBuffers {
  std::vector<std::array<Vec2, 2>> force;  // N on a0, a1 (b0, b1: minus these), times the thickness
  std::vector<double> block_energy;        // J/m, per block
  std::vector<double> block_dissipation;   // J/m, per block
  std::vector<JointLawConstants> law;      // per joint property, law_constants(p)
  // Sizes the buffers for the joints, reserves their break records (so that breaking
  // allocates nothing in the time loop) and computes the law constants of the
  // properties (call again if the properties change).
  void prepare(Joints& joints, const std::vector<JointProperties>& properties);
  // The sums over all joints of the last evaluate_joints (block sums added in order).
  double energy() const;
  double dissipation() const;
};

// Blocks of kJointBlock joints that cover n joints.
inline std::size_t joint_blocks(std::size_t n) { return (n + kJointBlock - 1) / kJointBlock; }

// The joint loop of add_joint_forces without the scatter, on blocks [block_begin,
// block_end) (all: 0, joint_blocks(joints.size())): every joint independent, so threads
// may take disjoint block ranges at once (the solver's are tuned from their measured
// times: a crack's softening joints, several times dearer than elastic ones, gather in
// a few blocks).
// Histories are updated as in add_joint_forces; a joint that breaks is marked
// broken[j] = Joints::kBreakPending: call record_new_breaks() after the loop (serial)
// when broken_now grew. The caller adds buf.force to the nodes (in a fixed order) and
// reads buf.energy() / buf.dissipation(); broken_now is returned through *broken_now
// (added to with an atomic, exact for any thread count). The law constants come from
// buf.law (buf.prepare() first).
void evaluate_joints(const Nodes& nodes, Joints& joints, bool damage_enabled, double thickness, JointPhaseBuffers& buf,
                     Index& broken_now, std::size_t block_begin, std::size_t block_end);

// Records the joints marked kBreakPending (in joint order) as broken at `time`, at their
// current mid-point (positions X + u), and marks them broken (1).
void record_new_breaks(const Nodes& nodes, Joints& joints, double time);

}  // namespace dsdem
