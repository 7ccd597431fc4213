#include "model/joints.hpp"

#include <cmath>
#include <sstream>

namespace dsdem {

std::string validate(const JointProperties& p) {
  std::ostringstream err;
  auto positive = [&](const char* key, double v) {
    if (!(v > 0.0) || !std::isfinite(v)) err << key << " must be > 0 (got " << v << "); ";
  };
  positive("kn", p.kn);
  positive("ks", p.ks);
  positive("ft", p.ft);
  positive("c", p.c);
  positive("GI", p.GI);
  positive("GII", p.GII);
  if (!(p.phi >= 0.0 && p.phi < 0.5 * kPi))
    err << "phi must be in [0, pi/2) rad (got " << p.phi << "); ";
  else if (p.c > 0.0 && p.ft > 0.0 && !(p.c - p.ft * std::tan(p.phi) > 0.0))
    err << "c - ft*tan(phi) must be > 0 (shear strength at the tension cut-off, eq. 8; got "
        << p.c - p.ft * std::tan(p.phi) << " Pa); ";
  std::string s = err.str();
  if (!s.empty()) s = "joint properties '" + p.name + "': " + s.substr(0, s.size() - 2);
  return s;
}

const char* to_string(BreakMode m) {
  switch (m) {
    case BreakMode::None: return "none";
    case BreakMode::Tension: return "tension";
    case BreakMode::Shear: return "shear";
    case BreakMode::Mixed: return "mixed";
    case BreakMode::Initial: return "initial";
  }
  return "unknown";
}

void Joints::set_initially_broken(std::size_t j, const Vec2& xa0, const Vec2& xa1) {
  for (auto& s : state[j]) s.damage = 1.0;
  end_mode[j] = {BreakMode::Initial, BreakMode::Initial};
  broken[j] = 1;
  breaks.push_back({static_cast<Index>(j), 0.0, 0.5 * (xa0 + xa1)});
}

const BreakRecord* Joints::find_break(std::size_t j) const {
  for (const BreakRecord& b : breaks)
    if (static_cast<std::size_t>(b.joint) == j) return &b;
  return nullptr;
}

std::vector<double> Joints::break_times() const {
  std::vector<double> t(size(), std::numeric_limits<double>::quiet_NaN());
  for (const BreakRecord& b : breaks) t[static_cast<std::size_t>(b.joint)] = b.time;
  return t;
}

double joint_local_size(const Joints& joints, std::size_t j, const std::vector<double>& area0) {
  auto size = [&](Index t) { return std::sqrt(2.0 * area0[static_cast<std::size_t>(t)]); };
  return 0.5 * (size(joints.tri_a[j]) + size(joints.tri_b[j]));
}

void set_local_penalty_scales(Joints& joints, const std::vector<JointProperties>& properties,
                              const std::vector<double>& area0) {
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Index p = joints.property[j];
    const double h_ref = p == kNoIndex ? 0.0 : properties.at(static_cast<std::size_t>(p)).penalty_h;
    joints.stiffness_scale[j] = h_ref > 0.0 ? h_ref / joint_local_size(joints, j, area0) : 1.0;
  }
}

void mark_initially_broken(Joints& joints, const std::vector<JointProperties>& properties,
                           const std::vector<Vec2>& X) {
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Index p = joints.property[j];
    if (p == kNoIndex || joints.broken[j] || !properties.at(p).initially_broken) continue;
    joints.set_initially_broken(j, X[joints.nodes[j][0]], X[joints.nodes[j][1]]);
  }
}

}  // namespace dsdem
