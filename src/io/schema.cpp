#include "io/schema.hpp"
#include "io/schema_table.hpp"

#include <fmt/format.h>

#include "law/registry.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace dsdem::io {

namespace {

// The doc text without its final period, for use inside a message.
std::string brief(const std::string& doc) {
  return !doc.empty() && doc.back() == '.' ? doc.substr(0, doc.size() - 1) : doc;
}

std::string type_name(KeyType t) {
  switch (t) {
    case KeyType::Number: return "number";
    case KeyType::Integer: return "integer";
    case KeyType::String: return "string";
    case KeyType::Boolean: return "boolean";
    case KeyType::Vector2: return "[x, y]";
    case KeyType::Vector: return "[x, y] or [x, y, z]";
    case KeyType::Range: return "[min, max]";
    case KeyType::Map: return "map";
    case KeyType::List: return "list";
    case KeyType::Table: return "[[t, value], ...]";
    case KeyType::Polyline: return "[[x, z], ...]";
    case KeyType::Points: return "[[x, y], ...]";
    case KeyType::Choice: return "one of";
    case KeyType::NumberOrTable: return "number or [[t, value], ...]";
  }
  return "?";
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t sub = prev[j - 1] + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

const std::vector<KeySpec>& scenario_schema() {
  static const std::vector<KeySpec> schema = detail::build_schema();
  return schema;
}

const KeySpec* find_spec(const std::string& pattern) {
  for (const auto& s : scenario_schema())
    if (s.pattern == pattern) return &s;
  return nullptr;
}

std::string schema_markdown() {
  std::string md =
      "# Scenario reference\n\nGenerated from the code's own schema (`dsdem schema`); every key the scenario "
      "accepts, with its unit, default and allowed range. `*` stands for a name you choose, `[]` for an entry "
      "of a list.\n\n| key | type | unit | default | allowed | meaning |\n|---|---|---|---|---|---|\n";
  for (const auto& s : scenario_schema()) {
    std::string allowed;
    if (s.type == KeyType::Choice) {
      for (const auto& c : s.choices) allowed += (allowed.empty() ? "" : ", ") + ("`" + c + "`");
    } else if (s.type == KeyType::Number || s.type == KeyType::Integer) {
      const bool lo = std::isfinite(s.min), hi = std::isfinite(s.max);
      if (lo && hi)
        allowed = fmt::format("{} {} x {} {}", s.min, s.min_exclusive ? "<" : "<=", s.max_exclusive ? "<" : "<=", s.max);
      else if (lo)
        allowed = fmt::format("{} {}", s.min_exclusive ? ">" : ">=", s.min);
      else if (hi)
        allowed = fmt::format("{} {}", s.max_exclusive ? "<" : "<=", s.max);
    }
    md += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", s.pattern, type_name(s.type), s.unit,
                      s.default_text.empty() ? "" : s.default_text, allowed, s.doc);
  }
  // The laws as they declare themselves: their parameters are the keys above, their state
  // variables the cell fields of the VTU frames and arrays of the checkpoint.
  md += "\n## Laws\n\nEach law's parameters are keys above (`materials.*.model`, `joints.*.law`, `contact.law` "
        "choose the law). Its named state variables are one value per item (triangle), zero at the start, written as "
        "cell fields of the VTU frames (named with their unit) and kept in checkpoints; state described in words is "
        "kept in the law's own module.\n\n"
        "| kind | law | parameters | state variables | meaning |\n|---|---|---|---|---|\n";
  for (const law::Category c : {law::Category::Material, law::Category::Joint, law::Category::Contact})
    for (const auto& l : law::registry(c).laws()) {
      std::string params, state;
      for (const auto& p : l.params) params += (params.empty() ? "" : ", ") + ("`" + p.name + "`");
      for (const auto& v : l.state)
        state += (state.empty() ? "" : ", ") + fmt::format("`{}`{}", v.name, v.unit.empty() ? "" : " (" + v.unit + ")");
      if (!l.module_state.empty()) state += (state.empty() ? "" : "; ") + l.module_state;
      md += fmt::format("| {} | `{}` | {} | {} | {} |\n", law::category_name(c), l.name, params,
                        state.empty() ? "none" : state, l.doc);
    }
  return md;
}

KeyPath KeyPath::child(const std::string& key) const {
  return {actual.empty() ? key : actual + "." + key, pattern.empty() ? key : pattern + "." + key};
}
KeyPath KeyPath::item(const std::string& name) const { return {actual + "." + name, pattern + ".*"}; }
KeyPath KeyPath::index(std::size_t i) const { return {fmt::format("{}[{}]", actual, i), pattern + "[]"}; }

std::string nearest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  // Suggest only plausible typos: at most a third of the word wrong (and at least 2 edits allowed).
  if (best_d <= std::max<std::size_t>(2, word.size() / 3)) return best;
  return "";
}

void SchemaReader::error_at(int line, int column, const std::string& path, const std::string& message) {
  if (line >= 0)
    errors_.push_back(fmt::format("{}:{}:{}: {}: {}", file_, line + 1, column + 1, path, message));
  else
    errors_.push_back(fmt::format("{}: {}: {}", file_, path, message));
}

void SchemaReader::set_overrides(const std::vector<std::string>& assignments) { overrides_ = assignments; }

const std::string* SchemaReader::override_for(const std::string& actual) const {
  if (overrides_.empty()) return nullptr;
  // Error paths write list entries as stages[1]; --set keys as stages.1.
  std::string path;
  for (const char ch : actual)
    if (ch == '[') path += '.';
    else if (ch != ']') path += ch;
  // The last assignment wins, as when they were applied.
  for (auto it = overrides_.rbegin(); it != overrides_.rend(); ++it) {
    const std::string key = it->substr(0, it->find('='));
    if (path == key || (path.size() > key.size() && path.compare(0, key.size(), key) == 0 && path[key.size()] == '.'))
      return &*it;
  }
  return nullptr;
}

void SchemaReader::error(const YAML::Node& at, const std::string& path, const std::string& message) {
  if (const std::string* assignment = override_for(path)) {
    errors_.push_back(fmt::format("--set {}: {}: {}", *assignment, path, message));
  } else if (at.IsDefined() && !at.IsNull()) {
    const YAML::Mark m = at.Mark();
    error_at(m.line, m.column, path, message);
  } else if (at.IsDefined()) {
    const YAML::Mark m = at.Mark();
    error_at(m.line, m.column, path, message);
  } else {
    error_at(-1, -1, path, message);
  }
}

const KeySpec& SchemaReader::spec(const KeyPath& p) const {
  if (schema_) {
    for (const auto& s : *schema_)
      if (s.pattern == p.pattern) return s;
    throw std::logic_error("schema has no key " + p.pattern);  // programming error
  }
  const KeySpec* s = find_spec(p.pattern);
  if (!s) throw std::logic_error("scenario schema has no key " + p.pattern);  // programming error
  return *s;
}

void SchemaReader::check_range(const YAML::Node& at, const KeyPath& p, const KeySpec& s, double v) {
  const bool below = s.min_exclusive ? !(v > s.min) : !(v >= s.min);
  const bool above = s.max_exclusive ? !(v < s.max) : !(v <= s.max);
  if (!std::isfinite(v)) {
    error(at, p.actual, fmt::format("{} is not a finite number", v));
  } else if (below || above) {
    std::string range;
    if (std::isfinite(s.min)) range += fmt::format("{} {}", s.min_exclusive ? ">" : ">=", s.min);
    if (std::isfinite(s.max)) range += fmt::format("{}{} {}", range.empty() ? "" : " and ", s.max_exclusive ? "<" : "<=", s.max);
    error(at, p.actual, fmt::format("{} is out of range: must be {}{} ({})", v, range,
                                    s.unit.empty() ? "" : " " + s.unit, brief(s.doc)));
  }
}

static bool parse_double(const YAML::Node& n, double& out) {
  if (!n.IsScalar()) return false;
  try {
    out = n.as<double>();
    return true;
  } catch (...) {
    return false;
  }
}

std::optional<double> SchemaReader::number(const YAML::Node& map, const KeyPath& parent, const std::string& key) {
  const KeyPath p = parent.child(key);
  const KeySpec& s = spec(p);
  const YAML::Node n = map[key];
  if (!n.IsDefined() || n.IsNull()) {
    if (s.required()) error(map, p.actual, fmt::format("missing value ({}{})", brief(s.doc), s.unit.empty() ? "" : ", in " + s.unit));
    if (!s.default_text.empty() && !s.required()) {
      try {
        return std::stod(s.default_text);
      } catch (...) {
        return std::nullopt;  // a computed default ("end/50") is applied by the caller
      }
    }
    return std::nullopt;
  }
  double v;
  if (!parse_double(n, v)) {
    error(n, p.actual, fmt::format("expected a number{}, got '{}'", s.unit.empty() ? "" : " in " + s.unit,
                                   n.IsScalar() ? n.Scalar() : std::string("a ") + (n.IsMap() ? "map" : "list")));
    return std::nullopt;
  }
  check_range(n, p, s, v);
  return v;
}

std::optional<long long> SchemaReader::integer(const YAML::Node& map, const KeyPath& parent, const std::string& key) {
  const auto v = number(map, parent, key);
  if (!v) return std::nullopt;
  if (std::floor(*v) != *v) {
    error(map[key], parent.child(key).actual, fmt::format("expected an integer, got {}", *v));
    return std::nullopt;
  }
  return static_cast<long long>(*v);
}

std::optional<std::string> SchemaReader::string(const YAML::Node& map, const KeyPath& parent, const std::string& key) {
  const KeyPath p = parent.child(key);
  const KeySpec& s = spec(p);
  const YAML::Node n = map[key];
  if (!n.IsDefined() || n.IsNull()) {
    if (s.required()) error(map, p.actual, fmt::format("missing value ({})", brief(s.doc)));
    if (!s.default_text.empty() && !s.required()) return s.default_text;
    return std::nullopt;
  }
  if (!n.IsScalar()) {
    error(n, p.actual, fmt::format("expected a {}, got a {}", s.type == KeyType::Choice ? "name" : "string",
                                   n.IsMap() ? "map" : "list"));
    return std::nullopt;
  }
  const std::string v = n.Scalar();
  if (s.type == KeyType::Choice && std::find(s.choices.begin(), s.choices.end(), v) == s.choices.end()) {
    std::string list;
    for (const auto& c : s.choices) list += (list.empty() ? "" : ", ") + c;
    const std::string near = nearest(v, s.choices);
    error(n, p.actual, fmt::format("'{}' is not one of: {}{}", v, list, near.empty() ? "" : "; did you mean '" + near + "'?"));
    return std::nullopt;
  }
  return v;
}

std::optional<bool> SchemaReader::boolean(const YAML::Node& map, const KeyPath& parent, const std::string& key) {
  const KeyPath p = parent.child(key);
  const KeySpec& s = spec(p);
  const YAML::Node n = map[key];
  if (!n.IsDefined() || n.IsNull()) {
    if (s.required()) error(map, p.actual, fmt::format("missing value ({})", brief(s.doc)));
    if (s.default_text == "true") return true;
    if (s.default_text == "false") return false;
    return std::nullopt;
  }
  try {
    return n.as<bool>();
  } catch (...) {
    error(n, p.actual, fmt::format("expected true or false, got '{}'", n.IsScalar() ? n.Scalar() : "a collection"));
    return std::nullopt;
  }
}

std::optional<std::array<double, 2>> SchemaReader::vector2(const YAML::Node& map, const KeyPath& parent,
                                                           const std::string& key) {
  const KeyPath p = parent.child(key);
  const KeySpec& s = spec(p);
  const YAML::Node n = map[key];
  if (!n.IsDefined() || n.IsNull()) {
    if (s.required()) error(map, p.actual, fmt::format("missing value ({}, [x, y] in {})", brief(s.doc), s.unit));
    return std::nullopt;
  }
  std::array<double, 2> v{};
  if (!n.IsSequence() || n.size() != 2 || !parse_double(n[0], v[0]) || !parse_double(n[1], v[1]) ||
      !std::isfinite(v[0]) || !std::isfinite(v[1])) {
    error(n, p.actual, fmt::format("expected two numbers [x, y]{}", s.unit.empty() ? "" : " in " + s.unit));
    return std::nullopt;
  }
  return v;
}

std::optional<std::vector<double>> SchemaReader::vector(const YAML::Node& map, const KeyPath& parent,
                                                       const std::string& key) {
  const KeyPath p = parent.child(key);
  const KeySpec& s = spec(p);
  const YAML::Node n = map[key];
  if (!n.IsDefined() || n.IsNull()) {
    if (s.required()) error(map, p.actual, fmt::format("missing value ({}, [x, y] or [x, y, z] in {})", brief(s.doc), s.unit));
    return std::nullopt;
  }
  std::vector<double> v(n.IsSequence() ? n.size() : 0);
  bool ok = n.IsSequence() && (n.size() == 2 || n.size() == 3);
  for (std::size_t i = 0; ok && i < v.size(); ++i) ok = parse_double(n[i], v[i]) && std::isfinite(v[i]);
  if (!ok) {
    error(n, p.actual, fmt::format("expected [x, y] (a plane model) or [x, y, z] (a 3D model){}",
                                   s.unit.empty() ? "" : " in " + s.unit));
    return std::nullopt;
  }
  return v;
}

std::optional<std::vector<std::array<double, 2>>> SchemaReader::table(const YAML::Node& map, const KeyPath& parent,
                                                                      const std::string& key) {
  return rows(map, parent, key, /*polyline=*/false);
}

std::optional<std::vector<std::array<double, 2>>> SchemaReader::polyline(const YAML::Node& map, const KeyPath& parent,
                                                                         const std::string& key) {
  return rows(map, parent, key, /*polyline=*/true);
}

std::optional<std::vector<Vec2>> SchemaReader::points(const YAML::Node& map, const KeyPath& parent,
                                                     const std::string& key, std::size_t at_least) {
  const KeyPath p = parent.child(key);
  const YAML::Node n = map[key];
  if (!n.IsDefined() || n.IsNull()) {
    if (spec(p).required()) error(map, p.actual, "missing: a list of [x, y] points");
    return std::nullopt;
  }
  if (!n.IsSequence() || n.size() < at_least) {
    error(n, p.actual, fmt::format("expected a list of at least {} [x, y] points", at_least));
    return std::nullopt;
  }
  std::vector<Vec2> pts;
  for (std::size_t i = 0; i < n.size(); ++i) {
    double x = 0.0, y = 0.0;
    if (!n[i].IsSequence() || n[i].size() != 2 || !parse_double(n[i][0], x) || !parse_double(n[i][1], y) ||
        !std::isfinite(x) || !std::isfinite(y)) {
      error(n[i], fmt::format("{}[{}]", p.actual, i), "expected a point [x, y] of two numbers");
      return std::nullopt;
    }
    pts.emplace_back(x, y);
  }
  return pts;
}

std::optional<std::vector<std::array<double, 2>>> SchemaReader::rows(const YAML::Node& map, const KeyPath& parent,
                                                                     const std::string& key, bool polyline) {
  const KeyPath p = parent.child(key);
  const YAML::Node n = map[key];
  if (!n.IsDefined() || n.IsNull()) return std::nullopt;
  std::vector<std::array<double, 2>> rows;
  double v;
  if (!polyline && n.IsScalar() && parse_double(n, v)) {
    if (!std::isfinite(v)) error(n, p.actual, "not a finite number");
    rows.push_back({0.0, v});
    return rows;
  }
  const char* row = polyline ? "[x, z]" : "[t, value]";
  if (!n.IsSequence() || n.size() == 0) {
    error(n, p.actual, polyline ? "expected a non-empty list of [x, z] points"
                                : "expected a number or a non-empty list of [t, value] rows");
    return std::nullopt;
  }
  for (std::size_t i = 0; i < n.size(); ++i) {
    std::array<double, 2> r{};
    if (!n[i].IsSequence() || n[i].size() != 2 || !parse_double(n[i][0], r[0]) || !parse_double(n[i][1], r[1]) ||
        !std::isfinite(r[0]) || !std::isfinite(r[1])) {
      error(n[i], fmt::format("{}[{}]", p.actual, i), fmt::format("expected a row {} of two numbers", row));
      return std::nullopt;
    }
    if (!rows.empty() && !(r[0] > rows.back()[0])) {
      error(n[i], fmt::format("{}[{}]", p.actual, i),
            fmt::format("{} must increase: {} after {}", polyline ? "x" : "times", r[0], rows.back()[0]));
      return std::nullopt;
    }
    rows.push_back(r);
  }
  return rows;
}

YAML::Node SchemaReader::section(const YAML::Node& map, const KeyPath& parent, const std::string& key,
                                 YAML::NodeType::value type) {
  const KeyPath p = parent.child(key);
  const KeySpec& s = spec(p);
  const YAML::Node n = map[key];
  if (!n.IsDefined() || n.IsNull()) {
    if (s.required()) error(map, p.actual, fmt::format("missing section ({})", brief(s.doc)));
    return YAML::Node(YAML::NodeType::Undefined);
  }
  if (n.Type() != type) {
    error(n, p.actual, fmt::format("expected a {}", type == YAML::NodeType::Map ? "map (key: value lines)" : "list (- items)"));
    return YAML::Node(YAML::NodeType::Undefined);
  }
  return n;
}

void SchemaReader::check_keys(const YAML::Node& map, const KeyPath& path) {
  if (!map.IsMap()) return;
  std::vector<std::string> valid;
  const std::string prefix = path.pattern.empty() ? "" : path.pattern + ".";
  for (const auto& s : schema_ ? *schema_ : scenario_schema()) {
    if (s.pattern.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = s.pattern.substr(prefix.size());
    if (rest.empty() || rest.find('.') != std::string::npos || rest == "*") continue;
    const std::string key = rest.substr(0, rest.find('['));
    if (std::find(valid.begin(), valid.end(), key) == valid.end()) valid.push_back(key);
  }
  for (auto it = map.begin(); it != map.end(); ++it) {
    const std::string key = it->first.Scalar();
    if (std::find(valid.begin(), valid.end(), key) != valid.end()) continue;
    const std::string near = nearest(key, valid);
    std::string list;
    for (const auto& v : valid) list += (list.empty() ? "" : ", ") + v;
    error(it->first, path.child(key).actual,
          near.empty() ? fmt::format("unknown key; valid keys here: {}", list)
                       : fmt::format("unknown key; did you mean '{}'?", near));
  }
}

}  // namespace dsdem::io
