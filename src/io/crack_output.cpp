#include "io/crack_output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>

#include "io/atomic_file.hpp"
#include "io/vtu_writer.hpp"

namespace dsdem::io {

void write_cracks_vtu(const std::filesystem::path& path, const Model& model, double time_s) {
  const Joints& J = model.joints;
  const Nodes& n = model.nodes;
  std::vector<std::array<Vec2, 2>> segments(J.size());
  std::vector<std::int32_t> state(J.size()), mode(J.size());
  std::vector<double> damage(J.size()), opening(J.size()), slip(J.size());
  const std::vector<double> time_broken = J.break_times();
  for (std::size_t j = 0; j < J.size(); ++j) {
    const auto& nd = J.nodes[j];
    segments[j] = {0.5 * (n.x(nd[0]) + n.x(nd[2])), 0.5 * (n.x(nd[1]) + n.x(nd[3]))};
    state[j] = J.broken[j] ? 1 : 0;
    mode[j] = static_cast<std::int32_t>(J.break_mode(j));
    damage[j] = J.broken[j] ? 1.0 : J.damage(j);
    opening[j] = 0.5 * (J.state[j][0].dn + J.state[j][1].dn);
    slip[j] = 0.5 * (J.state[j][0].ds + J.state[j][1].ds);
  }
  FieldSet fields{scalar_field("state", "", std::span<const std::int32_t>(state)),
                  scalar_field("damage", "", std::span<const double>(damage)),
                  scalar_field("opening", "m", std::span<const double>(opening)),
                  scalar_field("slip", "m", std::span<const double>(slip)),
                  scalar_field("mode", "", std::span<const std::int32_t>(mode)),
                  scalar_field("time_broken", "s", std::span<const double>(time_broken))};
  VtuOptions o;
  o.time_s = time_s;
  write_segments_vtu(path, segments, fields, o);
}

void write_crack_log_csv(const std::filesystem::path& path, const Model& model) {
  const Joints& J = model.joints;
  // By break time, ties by joint index.
  std::vector<const BreakRecord*> order;
  for (const BreakRecord& b : J.breaks) order.push_back(&b);
  std::sort(order.begin(), order.end(), [](const BreakRecord* a, const BreakRecord* b) {
    return a->time < b->time || (a->time == b->time && a->joint < b->joint);
  });
  std::string text = "joint,time_s,x_m,y_m,mode,property,curve\n";
  for (const BreakRecord* b : order) {
    const std::size_t j = static_cast<std::size_t>(b->joint);
    const Index curve = J.curve_group[j];
    text += fmt::format("{},{},{},{},{},{},{}\n", j, b->time, b->position.x(), b->position.y(),
                        to_string(J.break_mode(j)), model.joint_properties[J.property[j]].name,
                        curve == kNoIndex ? "" : model.groups[curve].name);
  }
  write_file_atomically(path, text);
}

}  // namespace dsdem::io
