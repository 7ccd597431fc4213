#include "io/scenario.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "io/scenario_sections.hpp"
#include "io/schema.hpp"

namespace dsdem::io {

namespace {

std::string join_lines(const std::vector<std::string>& lines) {
  std::string s = fmt::format("the scenario has {} error{}:", lines.size(), lines.size() == 1 ? "" : "s");
  for (const auto& l : lines) s += "\n  " + l;
  return s;
}

}  // namespace

JointSpec JointSpec::merged(const JointSpec& over) const {
  JointSpec j = *this;
  auto take = [](auto& mine, const auto& theirs) {
    if (theirs) mine = theirs;
  };
  take(j.law, over.law);
  j.params = params.merged(over.params);
  take(j.broken, over.broken);
  j.where = over.where;
  return j;
}

ScenarioError::ScenarioError(const std::vector<std::string>& errors)
    : std::runtime_error(join_lines(errors)), errors_(errors) {}

std::string SourceLocation::describe(const std::string& message) const {
  if (line >= 0) return fmt::format("{}:{}:{}: {}: {}", file, line + 1, column + 1, key, message);
  return fmt::format("{}: {}: {}", file, key, message);
}

double TimeHistory::at(double time) const {
  if (t.empty()) return 0.0;
  if (time <= t.front()) return value.front();
  if (time >= t.back()) return value.back();
  const auto it = std::upper_bound(t.begin(), t.end(), time);
  const std::size_t k = static_cast<std::size_t>(it - t.begin());
  const double s = (time - t[k - 1]) / (t[k] - t[k - 1]);
  return value[k - 1] + s * (value[k] - value[k - 1]);
}

double TimeHistory::rate_at(double time) const {
  if (t.size() < 2 || time < t.front() || time >= t.back()) return 0.0;
  const auto it = std::upper_bound(t.begin(), t.end(), time);
  const std::size_t k = static_cast<std::size_t>(it - t.begin());
  return (value[k] - value[k - 1]) / (t[k] - t[k - 1]);
}

double Scenario::end_time() const {
  double t = 0.0;
  for (const auto& s : stages) t += s.duration;
  return t;
}

std::string Scenario::resolve(const std::string& path) const {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return p.string();
  return (std::filesystem::path(directory) / p).lexically_normal().string();
}

void apply_override(YAML::Node& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ScenarioError({fmt::format("--set {}: expected key.path=value", assignment)});
  const std::string key = assignment.substr(0, eq);
  const std::string value = assignment.substr(eq + 1);
  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  // Walk with plain Node handles; yaml-cpp nodes are references into the tree.
  std::vector<YAML::Node> chain{root};
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node cur = chain.back();
    const std::string& part = parts[i];
    if (cur.IsSequence()) {
      std::size_t idx = 0;
      try {
        idx = std::stoul(part);
      } catch (...) {
        throw ScenarioError({fmt::format("--set {}: '{}' is a list; use an index", key, part)});
      }
      if (idx >= cur.size())
        throw ScenarioError({fmt::format("--set {}: index {} beyond the {} entries", key, idx, cur.size())});
      chain.push_back(cur[idx]);
    } else if (cur.IsMap() || !cur.IsDefined() || cur.IsNull()) {
      chain.push_back(cur[part]);
    } else {
      // A scalar on the way: yaml-cpp would throw BadSubscript (found by fuzzing).
      throw ScenarioError({fmt::format("--set {}: '{}' is a value, not a section with keys",
                                       key, fmt::join(parts.begin(), parts.begin() + static_cast<long>(i) + 1, "."))});
    }
  }
  YAML::Node leaf = chain.back();
  if (!leaf.IsSequence() && !leaf.IsMap() && leaf.IsDefined() && !leaf.IsNull())
    throw ScenarioError({fmt::format("--set {}: '{}' is a value, not a section with keys", key,
                                     fmt::join(parts.begin(), parts.end() - 1, "."))});
  YAML::Node v;
  try {
    v = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw ScenarioError({fmt::format("--set {}: value '{}' is not valid YAML: {}", key, value, e.msg)});
  }
  if (leaf.IsSequence()) {
    std::size_t idx = 0;
    try {
      idx = std::stoul(parts.back());
    } catch (...) {
      throw ScenarioError({fmt::format("--set {}: '{}' is a list; use an index", key, parts.back())});
    }
    if (idx >= leaf.size()) throw ScenarioError({fmt::format("--set {}: index {} beyond the list", key, idx)});
    leaf[idx] = v;
  } else {
    leaf[parts.back()] = v;
  }
}

Scenario load_scenario(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw ScenarioError({fmt::format("{}: cannot open the scenario file", path)});
  std::stringstream buf;
  buf << in.rdbuf();
  Scenario s = parse_scenario(buf.str(), path, overrides);
  s.overrides = overrides;
  return s;
}

Scenario parse_scenario(const std::string& yaml_text, const std::string& file_name,
                        const std::vector<std::string>& overrides) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw ScenarioError({fmt::format("{}:{}:{}: YAML syntax error: {}", file_name, e.mark.line + 1, e.mark.column + 1, e.msg)});
  }
  if (!root.IsMap()) throw ScenarioError({fmt::format("{}: the scenario must be a YAML map of sections (mesh, materials, ...)", file_name)});
  for (const auto& o : overrides) {
    try {
      apply_override(root, o);
    } catch (const YAML::Exception& e) {
      throw ScenarioError({fmt::format("--set {}: {}", o, e.msg)});
    }
  }

  SchemaReader r(file_name);
  r.set_overrides(overrides);
  Scenario sc;
  sc.file = file_name;
  sc.directory = std::filesystem::path(file_name).parent_path().string();
  if (sc.directory.empty()) sc.directory = ".";
  const KeyPath top{"", ""};
  r.check_keys(root, top);
  sc.title = r.string(root, top, "title").value_or("");

  detail::read_mesh(r, root, sc);
  detail::read_materials(r, root, sc);
  detail::read_regions(r, root, sc);
  detail::read_time_and_stages(r, root, sc);
  detail::read_joints(r, root, sc);
  detail::read_contact(r, root, sc);
  detail::read_earthquake(r, root, sc);
  bool any_discrete = false;
  for (const auto& reg : sc.regions) any_discrete = any_discrete || reg.zone == Zone::Discrete;
  if (any_discrete && !sc.joints.present)
    r.error(root, "joints", "a discrete (breakable) zone needs joint properties: add joints.default with ft, c, phi, GI, GII");

  detail::read_output(r, root, sc);
  detail::read_stability(r, root, sc);
  detail::read_reservoir(r, root, sc);
  const double total = sc.end_time();
  if (sc.output.field_interval <= 0.0) sc.output.field_interval = total / 50.0;
  if (sc.output.history_interval <= 0.0) sc.output.history_interval = total / 1000.0;

  if (!r.ok()) throw ScenarioError(r.errors());
  return sc;
}

}  // namespace dsdem::io
