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

}  // namespace dsdem
