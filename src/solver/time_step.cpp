#include "solver/time_step.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "fem/cst.hpp"
#include "joint/joint_force.hpp"

namespace dsdem::solver {

StableStep triangle_step_limit(const Model& model, double beta) {
  StableStep best;
  best.dt = std::numeric_limits<double>::infinity();
  const auto& tri = model.triangles;
  for (std::size_t t = 0; t < tri.size(); ++t) {
    const auto& c = tri.conn[t];
    const Vec2 x0 = model.nodes.x(c[0]), x1 = model.nodes.x(c[1]), x2 = model.nodes.x(c[2]);
    const double h = fem::characteristic_length(x0, x1, x2);
    const Material& mat = model.materials[tri.material[t]];
    const double cp = mat.cp();
    const double dt = fem::critical_time_step(h, cp, beta);
    if (dt < best.dt) {
      best.dt = dt;
      best.element = static_cast<Index>(t);
      best.position = (x0 + x1 + x2) / 3.0;
      const std::string group = tri.group[t] >= 0 ? model.groups[tri.group[t]].name : "?";
      best.controlled_by = fmt::format("triangle {} (group {}, material {}) at ({:.4g}, {:.4g}) m: h = {:.4g} m, cp = {:.5g} m/s",
                                       t, group, mat.name, best.position.x(), best.position.y(), h, cp);
    }
  }
  return best;
}

std::vector<JointStepLimit> joint_step_limits(const Model& model, bool intact_only) {
  // Joints: 2 sqrt(m/k) of the two node masses across each end (docs/theory.md §6).
  const auto& J = model.joints;
  std::vector<JointStepLimit> limits;
  for (std::size_t j = 0; j < J.size(); ++j) {
    if (intact_only && J.broken[j]) continue;
    const JointProperties& p = model.joint_properties[J.property[j]];
    const double k = joint_end_stiffness(p, J.length0[j], J.stiffness_scale[j]) * model.thickness;
    JointStepLimit l{std::numeric_limits<double>::infinity(), static_cast<Index>(j), 0};
    for (int e = 0; e < 2; ++e) {
      const double dt = joint_stable_dt(model.nodes.m[J.nodes[j][e]], model.nodes.m[J.nodes[j][2 + e]], k);
      if (dt < l.dt) l.dt = dt, l.end = e;
    }
    limits.push_back(l);
  }
  std::sort(limits.begin(), limits.end(), [](const JointStepLimit& a, const JointStepLimit& b) {
    return a.dt < b.dt || (a.dt == b.dt && a.joint < b.joint);
  });
  return limits;
}

StableStep describe_joint_limit(const Model& model, const JointStepLimit& limit) {
  const auto& J = model.joints;
  const Index j = limit.joint;
  const Index a = J.nodes[j][limit.end], b = J.nodes[j][2 + limit.end];
  const JointProperties& p = model.joint_properties[J.property[j]];
  const double k = joint_end_stiffness(p, J.length0[j], J.stiffness_scale[j]) * model.thickness;
  StableStep s;
  s.dt = limit.dt;
  s.element = j;
  s.position = model.nodes.x(a);
  s.controlled_by = fmt::format("joint {} ({}) at ({:.4g}, {:.4g}) m: k = {:.4g} N/m per end, node masses {:.4g} and {:.4g} kg",
                                j, p.name, s.position.x(), s.position.y(), k, model.nodes.m[a], model.nodes.m[b]);
  return s;
}

StableStep contact_step_limit(const Model& model) {
  // Contact springs: 2 sqrt(m/k) with the reduced mass of two of the lightest nodes.
  StableStep best;
  best.dt = std::numeric_limits<double>::infinity();
  if (!model.contact.enabled || !(model.contact.max_kn > 0.0)) return best;
  const auto& tri = model.triangles;
  for (std::size_t t = 0; t < tri.size(); ++t) {
    if (!model.contact.active[t]) continue;
    double m = std::numeric_limits<double>::infinity();
    for (Index nd : tri.conn[t]) m = std::min(m, model.nodes.m[nd]);
    const double dt = 2.0 * std::sqrt(0.5 * m / model.contact.max_kn);
    if (dt < best.dt) {
      best.dt = dt;
      best.element = static_cast<Index>(t);
      best.position = model.nodes.x(tri.conn[t][0]);
      best.controlled_by = fmt::format("contact at triangle {} ({:.4g}, {:.4g}) m: kn = {:.4g} Pa, node mass {:.4g} kg",
                                       t, best.position.x(), best.position.y(), model.contact.max_kn, m);
    }
  }
  return best;
}

StableStep stable_time_step(const Model& model, double beta) {
  StableStep best = triangle_step_limit(model, beta);
  const std::vector<JointStepLimit> joints = joint_step_limits(model);
  if (!joints.empty() && joints.front().dt < best.dt) best = describe_joint_limit(model, joints.front());
  StableStep contact = contact_step_limit(model);
  if (contact.dt < best.dt) best = std::move(contact);
  return best;
}

void TimeStepControl::set_rule(const Model& model, double safety, double fixed_limit, long broken_joints) {
  if (!(safety > 0.0 && safety <= 1.0) || !(fixed_limit > 0.0))
    throw std::invalid_argument(fmt::format("time-step rule: safety {} must be in (0, 1] and the fixed limit {} s > 0",
                                            safety, fixed_limit));
  safety_ = safety;
  fixed_limit_ = fixed_limit;
  joint_limits_ = joint_step_limits(model, false);  // all: a restore may mend some
  restart(model, broken_joints);
}

void TimeStepControl::restart(const Model& model, long broken_joints) {
  if (!has_rule()) return;
  first_intact_ = 0;
  take(model, broken_joints);
}

void TimeStepControl::take(const Model& model, long broken_joints) {
  // Joints only break: the first intact joint in ascending order never moves back.
  const auto& broken = model.joints.broken;
  while (first_intact_ < joint_limits_.size() && broken[joint_limits_[first_intact_].joint]) ++first_intact_;
  const double joint = first_intact_ < joint_limits_.size() ? joint_limits_[first_intact_].dt
                                                            : std::numeric_limits<double>::infinity();
  // The same operands as the first dt (safety x stable_time_step): while no joint has
  // broken, the same step bit for bit.
  dt_ = safety_ * std::min(fixed_limit_, joint);
  taken_at_broken_ = broken_joints;
}

const JointStepLimit* TimeStepControl::controlling_joint() const {
  if (!has_rule() || first_intact_ >= joint_limits_.size()) return nullptr;
  const JointStepLimit& l = joint_limits_[first_intact_];
  return l.dt < fixed_limit_ ? &l : nullptr;
}

}  // namespace dsdem::solver
