#include "io/schema.hpp"

#include <fmt/format.h>

#include "law/registry.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace dsdem::io {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

KeySpec num(std::string pattern, std::string unit, std::string def, double min, double max, std::string doc,
            bool min_excl = false, bool max_excl = false) {
  KeySpec s;
  s.pattern = std::move(pattern);
  s.type = KeyType::Number;
  s.unit = std::move(unit);
  s.default_text = std::move(def);
  s.min = min;
  s.max = max;
  s.min_exclusive = min_excl;
  s.max_exclusive = max_excl;
  s.doc = std::move(doc);
  return s;
}
KeySpec of(std::string pattern, KeyType type, std::string def, std::string doc, std::string unit = "") {
  KeySpec s;
  s.pattern = std::move(pattern);
  s.type = type;
  s.default_text = std::move(def);
  s.doc = std::move(doc);
  s.unit = std::move(unit);
  return s;
}
KeySpec choice(std::string pattern, std::vector<std::string> choices, std::string def, std::string doc) {
  KeySpec s = of(std::move(pattern), KeyType::Choice, std::move(def), std::move(doc));
  s.choices = std::move(choices);
  return s;
}

// One key per parameter of the laws of a registry, under `prefix`, in registration and
// declaration order; a parameter several laws declare is one key (declared alike). Its
// doc names the laws that use it unless all do. Without `keep_required` a required
// parameter has no default here (a set of overrides).
void add_law_params(std::vector<KeySpec>& s, const law::Registry& reg, const std::string& prefix, bool keep_required) {
  std::vector<const law::ParamDecl*> params;
  for (const auto& l : reg.laws())
    for (const auto& p : l.params) {
      const auto same = std::find_if(params.begin(), params.end(), [&](const law::ParamDecl* q) { return q->name == p.name; });
      if (same == params.end()) {
        params.push_back(&p);
        continue;
      }
      const law::ParamDecl& q = **same;
      if (q.unit != p.unit || q.default_text != p.default_text || q.min != p.min || q.max != p.max ||
          q.min_exclusive != p.min_exclusive || q.max_exclusive != p.max_exclusive || q.doc != p.doc)
        throw std::logic_error(fmt::format("{} law '{}' declares parameter '{}' unlike an earlier law",
                                           law::category_name(reg.category()), l.name, p.name));
    }
  for (const law::ParamDecl* p : params) {
    std::string users;
    std::size_t n_users = 0;
    for (const auto& l : reg.laws())
      if (l.has_param(p->name)) {
        users += (users.empty() ? "" : ", ") + l.name;
        ++n_users;
      }
    std::string doc = n_users == reg.size() ? p->doc : users + ": " + p->doc;
    const std::string def = p->required() && !keep_required ? "" : p->default_text;
    s.push_back(num(prefix + "." + p->name, p->unit, def, p->min, p->max, std::move(doc), p->min_exclusive,
                    p->max_exclusive));
  }
}

// The mesh, the materials and the regions that join them.
void add_mesh_and_materials(std::vector<KeySpec>& s) {
  s.push_back(of("title", KeyType::String, "", "Free text shown in the log, summary and report."));
  s.push_back(of("mesh", KeyType::Map, "required", "The Gmsh mesh or geometry."));
  s.push_back(of("mesh.file", KeyType::String, "required",
                 "Gmsh ASCII .msh (format 4.1 or 2.2) or .geo file, relative to the scenario file."));
  s.push_back(num("mesh.element_size", "m", "", 0, kInf,
                  "Maximum element size used to mesh a .geo (required for .geo, ignored for .msh).", true));
  s.push_back(choice("mesh.triangle_order", {"spatial", "file"}, "spatial",
                     "Numbering of the triangles: spatial (along a Hilbert curve through their centroids, "
                     "for memory locality and thread balance) or file (the mesh file's order). The two runs "
                     "differ by rounding only; ParaView's cell ids are the solver's numbers."));
  s.push_back(choice("mesh.plane", {"strain", "stress"}, "strain",
                     "2D idealisation: plane strain (per unit thickness) or plane stress."));
  s.push_back(num("mesh.thickness", "m", "1", 0, kInf, "Out-of-plane thickness (plane stress).", true));

  s.push_back(of("materials", KeyType::Map, "required", "Materials by name."));
  s.push_back(of("materials.*", KeyType::Map, "", "One material."));
  s.push_back(choice("materials.*.model", law::material_laws().names(), std::string(law::kDefaultMaterialLaw),
                     "Constitutive model of the bulk."));
  add_law_params(s, law::material_laws(), "materials.*", true);

  s.push_back(of("regions", KeyType::List, "required", "Assigns a material and a zone to each physical surface group."));
  s.push_back(of("regions[]", KeyType::Map, "", "One region."));
  s.push_back(of("regions[].group", KeyType::String, "required", "Name of a physical surface group of the mesh."));
  s.push_back(of("regions[].material", KeyType::String, "required", "Name of a material under `materials`."));
  s.push_back(choice("regions[].zone", {"continuous", "contact", "discrete"}, "continuous",
                     "continuous: plain FEM (zone B); contact: FEM whose surface takes part in contact (zone C); "
                     "discrete: breakable spheropolygon elements glued by joints (zone A)."));
}

// Boundary conditions, gravity, damping, time and stages.
void add_boundaries_time_stages(std::vector<KeySpec>& s) {
  s.push_back(of("boundaries", KeyType::List, "", "Boundary conditions on curve or point groups."));
  s.push_back(of("boundaries[]", KeyType::Map, "", "One boundary condition."));
  s.push_back(of("boundaries[].group", KeyType::String, "required",
                 "Name of a physical curve or point group, or a surface group (a driven body: all its nodes)."));
  s.push_back(choice("boundaries[].type", {"fixed", "roller", "velocity", "displacement", "free", "viscous_spring"}, "required",
                     "fixed: both directions held; roller: `direction` held; velocity / displacement: the given "
                     "components prescribed (constant or history); free: nothing (overrides an earlier stage); "
                     "viscous_spring: absorbing boundary with the free-field earthquake input (DESIGN.md §5)."));
  s.push_back(num("boundaries[].R", "m", "", 0, kInf, "viscous_spring: distance from the scattering source to the boundary.", true));
  s.push_back(of("boundaries[].scattering_centre", KeyType::Vector2, "",
                 "viscous_spring: point of the scattering source; R is then each node's distance to it.", "m"));
  s.push_back(of("boundaries[].free_field", KeyType::Boolean, "true",
                 "viscous_spring: apply the free-field seismic input forces on this boundary."));
  s.push_back(choice("boundaries[].direction", {"x", "y"}, "",
                     "For a roller: the direction that is held (x for a vertical side, y for a base)."));
  s.push_back(of("boundaries[].x", KeyType::NumberOrTable, "",
                 "Prescribed x component: a number, or a history [[t, value], ...] (linear in between, held after).",
                 "m/s or m"));
  s.push_back(of("boundaries[].y", KeyType::NumberOrTable, "", "Prescribed y component, as for x.", "m/s or m"));

  s.push_back(of("gravity", KeyType::Vector2, "[0, -9.81]", "Gravitational acceleration.", "m/s^2"));
  s.push_back(of("damping", KeyType::Map, "", "Rayleigh damping C = alpha M + beta K (DESIGN.md §6)."));
  s.push_back(num("damping.alpha", "1/s", "0", 0, kInf, "Mass-proportional coefficient."));
  s.push_back(num("damping.beta", "s", "0", 0, kInf, "Stiffness-proportional coefficient."));

  s.push_back(of("time", KeyType::Map, "required", "Time integration."));
  s.push_back(num("time.end", "s", "", 0, kInf,
                  "End time (required without stages; with stages the sum of their durations).", true));
  s.push_back(num("time.dt", "s", "", 0, kInf, "Fixed time step; when absent, safety x the stable step.", true));
  s.push_back(num("time.safety", "", "0.3", 0, 1, "Fraction of the stable time step used.", true));
  s.push_back(of("time.adaptive", KeyType::Boolean, "true without time.dt",
                 "Take the step again as joints break: safety x the stable step of the intact joints, triangles and "
                 "contacts (DESIGN.md §6), so it grows as the stiffest joints go; false keeps the first step. Not "
                 "with time.dt."));

  s.push_back(of("stages", KeyType::List, "", "Stages run one after another; each may override damping and boundaries."));
  s.push_back(of("stages[]", KeyType::Map, "", "One stage."));
  s.push_back(of("stages[].name", KeyType::String, "required", "Stage name (log, histories)."));
  s.push_back(num("stages[].duration", "s", "required", 0, kInf, "Simulated time of the stage.", true));
  s.push_back(of("stages[].damping", KeyType::Map, "", "Rayleigh damping during this stage (else the top-level one)."));
  s.push_back(num("stages[].damping.alpha", "1/s", "0", 0, kInf, "Mass-proportional coefficient."));
  s.push_back(num("stages[].damping.beta", "s", "0", 0, kInf, "Stiffness-proportional coefficient."));
  s.push_back(of("stages[].boundaries", KeyType::List, "",
                 "Boundary conditions during this stage (else the top-level ones)."));
  s.push_back(of("stages[].boundaries[]", KeyType::Map, "", "One boundary condition."));
  for (const char* k : {"group", "type", "direction", "x", "y", "R", "scattering_centre", "free_field"}) {
    KeySpec copy = *std::find_if(s.begin(), s.end(), [&](const KeySpec& q) { return q.pattern == std::string("boundaries[].") + k; });
    copy.pattern = std::string("stages[].boundaries[].") + k;
    s.push_back(copy);
  }
  s.push_back(num("stages[].stop_kinetic_ratio", "", "", 0, 1,
                  "End the stage early once kinetic energy falls below this fraction of its peak in the stage.", true));
}

// Cohesive joints (DESIGN.md §3; paper eqs. 6-9).
void add_joints(std::vector<KeySpec>& s) {
  s.push_back(of("joints", KeyType::Map, "", "Cohesive joint properties for discrete (breakable) zones."));
  const std::vector<std::pair<std::string, std::string>> joint_sets{
      {"joints.default", "Properties of every joint unless a group, interface or curve entry overrides them."},
      {"joints.groups.*", "Overrides for joints inside one discrete surface group."},
      {"joints.interface", "Overrides for joints between a discrete group and a continuous one (the bond to bedrock)."},
      {"joints.curves.*", "Overrides for joints on a named mesh curve (pre-existing crack, weak interlayer)."}};
  s.push_back(of("joints.groups", KeyType::Map, "", "Per discrete group overrides, by group name."));
  s.push_back(of("joints.curves", KeyType::Map, "", "Per curve overrides, by curve group name."));
  for (const auto& [prefix, doc] : joint_sets) {
    const bool base = prefix == "joints.default";
    s.push_back(of(prefix, KeyType::Map, "", doc));
    s.push_back(choice(prefix + ".law", law::joint_laws().names(), base ? std::string(law::kDefaultJointLaw) : "",
                       base ? "Joint law (its parameters follow)."
                            : "Joint law of these joints (default: the one of joints.default)."));
    // Required values are required once, in joints.default; the other sets override.
    add_law_params(s, law::joint_laws(), prefix, base);
    s.push_back(of(prefix + ".broken", KeyType::Boolean, "false", "Start broken (a pre-existing crack: contact only)."));
  }
}

// Spheropolygon contact (DESIGN.md §4; paper eqs. 1-5).
void add_contact(std::vector<KeySpec>& s) {
  s.push_back(of("contact", KeyType::Map, "", "Contact between spheropolygons of the discrete and contact zones."));
  s.push_back(choice("contact.law", law::contact_laws().names(), std::string(law::kDefaultContactLaw),
                     "Contact law (its parameters follow)."));
  add_law_params(s, law::contact_laws(), "contact", true);
  s.push_back(num("contact.rounding", "", "0.05", 0, 0.5, "Rounding radius as a fraction of each triangle's inscribed radius.", true, true));
  s.push_back(num("contact.skin", "m", "auto", 0, kInf, "Broad-phase skin (default: half the mean inscribed radius).", true));
  s.push_back(of("contact.output", KeyType::Boolean, "false", "Write contact points and forces as a VTU series (contacts.pvd)."));
  s.push_back(of("contact.pairs", KeyType::List, "", "Friction / restitution / stiffness for particular pairs of surface groups."));
  s.push_back(of("contact.pairs[]", KeyType::Map, "", "One pair of groups."));
  s.push_back(of("contact.pairs[].groups", KeyType::List, "required", "Two surface group names (the same name twice: within one group)."));
  s.push_back(num("contact.pairs[].friction", "", "contact.friction", 0, kInf, "Coulomb friction coefficient."));
  s.push_back(num("contact.pairs[].restitution", "", "contact.restitution", 0, 1, "Coefficient of restitution.", true));
  s.push_back(num("contact.pairs[].kn", "Pa", "contact.kn", 0, kInf, "Normal stiffness.", true));
}

// Earthquake input (DESIGN.md §5; paper §2.2) and the stage switches after it.
void add_earthquake(std::vector<KeySpec>& s) {
  s.push_back(of("earthquake", KeyType::Map, "", "Design ground motion fed through viscous-spring boundaries."));
  s.push_back(num("earthquake.incident_factor", "", "0.5", 0, kInf,
                  "Incident wave = this factor x the design (outcrop) motion (0.5 for a uniform half-space).", true));
  for (const std::string comp : {"horizontal", "vertical"}) {
    const std::string base = "earthquake." + comp;
    s.push_back(of(base, KeyType::Map, "", comp == "horizontal" ? "Horizontal component: vertically incident SV wave."
                                                                  : "Vertical component: vertically incident P wave."));
    s.push_back(of(base + ".file", KeyType::String, "", "Accelerogram: CSV (t, a) or PEER .AT2, relative to the scenario."));
    s.push_back(choice(base + ".units", {"g", "m/s2"}, "g", "Units of a CSV accelerogram (AT2 is always g)."));
    s.push_back(num(base + ".scale", "", "1", -kInf, kInf, "Factor applied to the record (e.g. to scale it to a PGA)."));
    s.push_back(of(base + ".generate", KeyType::Map, "", "Generate an artificial accelerogram (GB 17741 method) instead of a file."));
    s.push_back(choice(base + ".generate.spectrum", {"hydraulic", "gb50011"}, "hydraulic", "Target spectrum."));
    s.push_back(num(base + ".generate.pga", "g", "0.05", 0, kInf, "Peak ground acceleration.", true));
    s.push_back(num(base + ".generate.Tg", "s", "0.35", 0.1, 10, "Characteristic period.", true));
    s.push_back(num(base + ".generate.beta_max", "", "2.25", 1, kInf, "Peak of the hydraulic beta spectrum."));
    s.push_back(num(base + ".generate.damping", "", "0.05", 0, 1, "Damping ratio of the target spectrum.", true, true));
    s.push_back(num(base + ".generate.duration", "s", "10", 0, kInf, "Duration.", true));
    s.push_back(num(base + ".generate.dt", "s", "0.02", 0, kInf, "Sampling step.", true));
    s.push_back(num(base + ".generate.seed", "", "1", 0, kInf, "Random seed (same seed, same wave)."));
    s.push_back(num(base + ".generate.t1", "s", "1.5", 0, kInf, "End of the rising part of the intensity envelope."));
    s.push_back(num(base + ".generate.t2", "s", "6.5", 0, kInf, "Start of the decay of the intensity envelope."));
    s.push_back(num(base + ".generate.c", "1/s", "1", 0, kInf, "Decay rate of the envelope."));
  }
  s.push_back(of("stages[].earthquake", KeyType::Boolean, "false",
                 "The earthquake acts during this stage (its time zero is the stage start)."));

  s.push_back(of("stages[].failure", KeyType::Boolean, "true",
                 "Joints may damage and break in this stage (false for a gravity stage: elastic joints)."));
}

// Output intervals, checkpoints and gauges.
void add_output(std::vector<KeySpec>& s) {
  s.push_back(of("output", KeyType::Map, "", "What is written and how often."));
  s.push_back(num("output.field_interval", "s", "end/50", 0, kInf, "Interval between VTU frames.", true));
  s.push_back(num("output.history_interval", "s", "end/1000", 0, kInf, "Interval between history rows.", true));
  s.push_back(num("output.progress_interval", "s", "2", 0, kInf, "Wall-clock interval between progress lines.", true));
  s.push_back(num("output.checkpoint_steps", "", "0", 0, kInf,
                  "Write OUT/checkpoint.h5 every this many steps (0: only by wall clock, at the end and on SIGINT/SIGTERM)."));
  s.push_back(num("output.checkpoint_interval", "s", "600", 0, kInf,
                  "Wall-clock interval between checkpoints (0: none by wall clock). A checkpoint is always written at "
                  "the end and on SIGINT/SIGTERM; continue with `dsdem run SCENARIO --restart OUT/checkpoint.h5`."));
  s.push_back(of("output.gauges", KeyType::List, "", "Gauges: material points followed through the run."));
  s.push_back(of("output.gauges[]", KeyType::Map, "", "One gauge."));
  s.push_back(of("output.gauges[].name", KeyType::String, "required", "Gauge name (history column prefix)."));
  s.push_back(of("output.gauges[].at", KeyType::Vector2, "required",
                 "Reference position; the gauge follows the material point there.", "m"));
}

// Keys in the order of docs/scenario-reference.md.
std::vector<KeySpec> build_schema() {
  std::vector<KeySpec> s;
  add_mesh_and_materials(s);
  add_boundaries_time_stages(s);
  add_joints(s);
  add_contact(s);
  add_earthquake(s);
  add_output(s);
  return s;
}

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
    case KeyType::Map: return "map";
    case KeyType::List: return "list";
    case KeyType::Table: return "[[t, value], ...]";
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
  static const std::vector<KeySpec> schema = build_schema();
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

std::optional<std::vector<std::array<double, 2>>> SchemaReader::table(const YAML::Node& map, const KeyPath& parent,
                                                                      const std::string& key) {
  const KeyPath p = parent.child(key);
  const YAML::Node n = map[key];
  if (!n.IsDefined() || n.IsNull()) return std::nullopt;
  std::vector<std::array<double, 2>> rows;
  double v;
  if (n.IsScalar() && parse_double(n, v)) {
    if (!std::isfinite(v)) error(n, p.actual, "not a finite number");
    rows.push_back({0.0, v});
    return rows;
  }
  if (!n.IsSequence() || n.size() == 0) {
    error(n, p.actual, "expected a number or a non-empty list of [t, value] rows");
    return std::nullopt;
  }
  for (std::size_t i = 0; i < n.size(); ++i) {
    std::array<double, 2> r{};
    if (!n[i].IsSequence() || n[i].size() != 2 || !parse_double(n[i][0], r[0]) || !parse_double(n[i][1], r[1]) ||
        !std::isfinite(r[0]) || !std::isfinite(r[1])) {
      error(n[i], fmt::format("{}[{}]", p.actual, i), "expected a row [t, value] of two numbers");
      return std::nullopt;
    }
    if (!rows.empty() && !(r[0] > rows.back()[0])) {
      error(n[i], fmt::format("{}[{}]", p.actual, i), fmt::format("times must increase: {} after {}", r[0], rows.back()[0]));
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
  for (const auto& s : scenario_schema()) {
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
