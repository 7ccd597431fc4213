#pragma once
// The time step (docs/theory.md §6): dt = safety x min(h_e / cp_e over triangles, 2 sqrt(m/k)
// over joints and contacts). TimeStepControl is the one owner of a solver's dt: a fixed
// step, or the rule that takes the step again as the stiffest joints break, and what
// controls it.
#include <string>
#include <vector>

#include "model/model.hpp"

namespace dsdem::solver {

// What controls the stable time step.
struct StableStep {
  double dt = 0.0;           // critical step (before the safety factor), s
  std::string controlled_by; // e.g. "triangle 12 (group rock) h = 0.1 m, cp = 3000 m/s"
  Index element = kNoIndex;
  Vec2 position = Vec2::Zero();
};
StableStep stable_time_step(const Model& model, double beta);
// Its parts (stable_time_step is the least of them, ties to the earlier part): the
// triangles' bulk limit, the contact springs' limit, and each intact joint's limit (the
// lesser of its two ends) in ascending order (ties by joint index; broken joints left
// out unless intact_only is false).
StableStep triangle_step_limit(const Model& model, double beta);
StableStep contact_step_limit(const Model& model);
struct JointStepLimit {
  double dt = 0.0;  // s
  Index joint = kNoIndex;
  int end = 0;      // the end (0 or 1) that sets it
};
std::vector<JointStepLimit> joint_step_limits(const Model& model, bool intact_only = true);
StableStep describe_joint_limit(const Model& model, const JointStepLimit& limit);

class TimeStepControl {
 public:
  // A fixed step (no rule), s; a rule set before keeps deciding.
  void set_fixed(double dt) {
    fixed_dt_ = dt;
    if (!has_rule()) dt_ = dt;
  }
  // The rule (docs/theory.md §6: dt = safety x the stable step of the model as it is): each step
  // starts with dt = safety x min(fixed_limit, the limit of the stiffest intact joint),
  // taken again whenever joints broke. fixed_limit holds the triangles' and contact
  // springs' limits. Joints only break, so dt only grows, and a state gives one dt
  // whatever came before: a restart and any thread count take the same steps.
  // Throws std::invalid_argument for safety outside (0, 1] or fixed_limit <= 0.
  void set_rule(const Model& model, double safety, double fixed_limit, long broken_joints);
  bool has_rule() const { return safety_ > 0.0; }
  // Before a step: the rule's dt when joints broke since it was last taken.
  void update(const Model& model, long broken_joints) {
    if (has_rule() && broken_joints != taken_at_broken_) take(model, broken_joints);
  }
  // After a restore: the rule's walk starts over (the restored state may have fewer
  // joints broken than seen so far).
  void restart(const Model& model, long broken_joints);
  double dt() const { return dt_; }
  // The intact joint that sets dt under the rule; null when the fixed limit does, or no rule.
  const JointStepLimit* controlling_joint() const;

 private:
  void take(const Model& model, long broken_joints);
  double dt_ = 0.0, fixed_dt_ = 0.0;
  double safety_ = 0.0;       // 0: no rule
  double fixed_limit_ = 0.0;  // s
  std::vector<JointStepLimit> joint_limits_;  // all joints, ascending limit
  std::size_t first_intact_ = 0;
  long taken_at_broken_ = -1;
};

}  // namespace dsdem::solver
