// The readers of the scenario's sections, called by parse_scenario() (scenario.cpp) in
// the order of the schema (io/schema.cpp); every problem goes to the SchemaReader.
#include "io/scenario_sections.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "io/input_file.hpp"
#include "law/registry.hpp"

namespace dsdem::io::detail {

SourceLocation location(const SchemaReader& r, const YAML::Node& n, const std::string& key) {
  SourceLocation loc;
  loc.file = r.file();
  loc.key = key;
  if (const std::string* assignment = r.override_for(key)) {
    loc.file = "--set " + *assignment;  // the value has no line in the file
  } else if (n.IsDefined()) {
    loc.line = n.Mark().line;
    loc.column = n.Mark().column;
  }
  return loc;
}

namespace {

TimeHistory to_history(const std::vector<std::array<double, 2>>& rows) {
  TimeHistory h;
  for (const auto& r : rows) {
    h.t.push_back(r[0]);
    h.value.push_back(r[1]);
  }
  return h;
}

std::vector<BoundarySpec> read_boundaries(SchemaReader& r, const YAML::Node& list, const KeyPath& path) {
  std::vector<BoundarySpec> out;
  if (!list.IsDefined()) return out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node b = list[i];
    const KeyPath p = path.index(i);
    if (!b.IsMap()) {
      r.error(b, p.actual, "expected a map with group and type");
      continue;
    }
    r.check_keys(b, p);
    BoundarySpec spec;
    spec.group = r.string(b, p, "group").value_or("");
    spec.where = location(r, b["group"].IsDefined() ? b["group"] : b, p.child("group").actual);
    const std::string type = r.string(b, p, "type").value_or("");
    const auto dir = r.string(b, p, "direction");
    auto x = r.table(b, p, "x");
    auto y = r.table(b, p, "y");
    auto z = r.table(b, p, "z");
    if (x) spec.x = to_history(*x);
    if (y) spec.y = to_history(*y);
    if (z) spec.z = to_history(*z);
    if (type == "fixed") {
      spec.type = BoundaryType::Fixed;
    } else if (type == "free") {
      spec.type = BoundaryType::Free;
    } else if (type == "roller") {
      spec.type = BoundaryType::Roller;
      if (!dir) r.error(b, p.child("direction").actual, "a roller needs the direction it holds: x, y or z");
      spec.direction = dir && *dir == "z" ? 2 : dir && *dir == "y" ? 1 : 0;
    } else if (type == "viscous_spring") {
      spec.type = BoundaryType::ViscousSpring;
      spec.R = r.number(b, p, "R");
      if (auto c = r.vector(b, p, "scattering_centre")) {
        spec.scattering_centre = Vec2((*c)[0], (*c)[1]);
        if (c->size() == 3) spec.scattering_centre_3d = Vec3((*c)[0], (*c)[1], (*c)[2]);
      }
      spec.free_field = r.boolean(b, p, "free_field").value_or(true);
      if (!spec.R && !spec.scattering_centre)
        r.error(b, p.actual, "a viscous_spring boundary needs R (m) or scattering_centre ([x, y] m)");
    } else if (type == "velocity" || type == "displacement") {
      spec.type = type == "velocity" ? BoundaryType::Velocity : BoundaryType::Displacement;
      if (!spec.x && !spec.y && !spec.z)
        r.error(b, p.actual, fmt::format("a {} condition needs x, y and/or z (a number or [[t, value], ...])", type));
    }
    if (spec.type != BoundaryType::ViscousSpring && (b["R"].IsDefined() || b["scattering_centre"].IsDefined()))
      r.error(b, p.actual, "R and scattering_centre belong to type viscous_spring");
    if ((spec.type == BoundaryType::Fixed || spec.type == BoundaryType::Roller || spec.type == BoundaryType::Free ||
         spec.type == BoundaryType::ViscousSpring) &&
        (spec.x || spec.y || spec.z))
      r.error(b, p.actual, fmt::format("'{}' takes no x/y/z values; use type velocity or displacement", type));
    out.push_back(std::move(spec));
  }
  return out;
}

DampingSpec read_damping(SchemaReader& r, const YAML::Node& map, const KeyPath& path, const DampingSpec& fallback) {
  if (!map.IsDefined()) return fallback;
  r.check_keys(map, path);
  DampingSpec d;
  d.alpha = r.number(map, path, "alpha").value_or(0.0);
  d.beta = r.number(map, path, "beta").value_or(0.0);
  return d;
}

// Reports each key of `m` that is a parameter of another law of `reg` but not of `decl`,
// the law chosen by the key `law_key`.
void check_law_keys(SchemaReader& r, const YAML::Node& m, const KeyPath& p, const law::LawDecl& decl,
                    const law::Registry& reg, const std::string& law_key) {
  for (auto it = m.begin(); it != m.end(); ++it) {
    const std::string key = it->first.Scalar();
    if (decl.has_param(key)) continue;
    std::vector<std::string> owners;
    for (const auto& l : reg.laws())
      if (l.has_param(key)) owners.push_back(l.name);
    if (!owners.empty())
      r.error(it->first, p.child(key).actual,
              fmt::format("'{}' belongs to {} {}, not to {} {} chosen here (set {}: {} or remove the key)", key,
                          law_key, fmt::join(owners, " or "), law_key, decl.name, law_key, owners.front()));
  }
}

// The parameters `decl` declares, read from `m` in declaration order: given values,
// numeric defaults, rule defaults (e.g. c / tan(phi)); NaN when absent with none. Runs
// the law's cross-checks once every value is valid.
std::vector<double> read_law_params(SchemaReader& r, const YAML::Node& m, const KeyPath& p, const law::LawDecl& decl,
                                    const law::Registry& reg, const std::string& law_key) {
  check_law_keys(r, m, p, decl, reg, law_key);
  const std::size_t errors_before = r.errors().size();
  std::vector<double> values;
  values.reserve(decl.params.size());
  for (const auto& param : decl.params) {
    std::optional<double> v = r.number(m, p, param.name);
    if (!v && param.rule && !m[param.name].IsDefined()) v = param.rule(decl, values);
    values.push_back(v.value_or(std::numeric_limits<double>::quiet_NaN()));
  }
  if (decl.check && r.errors().size() == errors_before)
    for (const auto& problem : decl.check(decl, values)) {
      const YAML::Node at = m[problem.param];
      r.error(at.IsDefined() ? at : m, p.child(problem.param).actual, problem.message);
    }
  return values;
}

// The parameters of `decl` that `m` gives (and the required ones, which the schema
// reports when missing), by declared name.
GivenParams read_given_params(SchemaReader& r, const YAML::Node& m, const KeyPath& p, const law::LawDecl& decl,
                              bool per_pair_only) {
  GivenParams g;
  for (const auto& param : decl.params) {
    if (per_pair_only && !param.per_pair) continue;
    if (!m[param.name].IsDefined() && !param.required()) continue;  // an absent one keeps the other sets' value
    if (const std::optional<double> v = r.number(m, p, param.name)) g.values[param.name] = *v;
  }
  return g;
}

JointSpec read_joint_spec(SchemaReader& r, const YAML::Node& m, const KeyPath& p, const std::string& inherited_law) {
  JointSpec j;
  j.where = location(r, m, p.actual);
  if (!m.IsMap()) {
    r.error(m, p.actual, "expected a map of joint properties (the joint law's parameters and broken)");
    return j;
  }
  r.check_keys(m, p);
  if (m["law"].IsDefined()) j.law = r.string(m, p, "law");
  if (const law::LawDecl* decl = law::joint_laws().find(j.law.value_or(inherited_law))) {
    check_law_keys(r, m, p, *decl, law::joint_laws(), "law");
    j.params = read_given_params(r, m, p, *decl, false);
  }
  if (m["broken"].IsDefined()) j.broken = r.boolean(m, p, "broken");
  return j;
}

}  // namespace

// The mesh file, its plane idealisation and thickness.
void read_mesh(SchemaReader& r, YAML::Node& root, Scenario& sc) {
  const KeyPath top{"", ""};
  // mesh
  if (YAML::Node mesh = r.section(root, top, "mesh", YAML::NodeType::Map); mesh.IsDefined()) {
    const KeyPath p = top.child("mesh");
    r.check_keys(mesh, p);
    sc.mesh_file = r.string(mesh, p, "file").value_or("");
    sc.where_mesh = location(r, mesh["file"].IsDefined() ? mesh["file"] : mesh, "mesh.file");
    sc.element_size = r.number(mesh, p, "element_size");
    sc.crossed_mesh = r.boolean(mesh, p, "crossed").value_or(false);
    sc.spatial_triangle_order = r.string(mesh, p, "triangle_order").value_or("spatial") == Scenario::triangle_order_name(true);
    sc.plane_stress = r.string(mesh, p, "plane").value_or("strain") == "stress";
    sc.thickness = r.number(mesh, p, "thickness").value_or(1.0);
    if (!sc.mesh_file.empty()) {
      const std::string ext = std::filesystem::path(sc.mesh_file).extension().string();
      if (ext != ".msh" && ext != ".geo")
        r.error(mesh["file"], "mesh.file", fmt::format("'{}' is neither a .msh nor a .geo file", sc.mesh_file));
      else if (const std::string problem = input_file_problem(sc.resolve(sc.mesh_file)); !problem.empty())
        r.error(mesh["file"], "mesh.file", problem);
      else if (ext == ".geo" && !sc.element_size)
        r.error(mesh, "mesh.element_size", "a .geo geometry needs an element size to be meshed");
    }
    if (!sc.plane_stress && mesh["thickness"].IsDefined() && sc.thickness != 1.0)
      r.error(mesh["thickness"], "mesh.thickness", "a thickness other than 1 needs plane: stress (plane strain is per unit thickness)");
  }
}

// Materials by name with their law's parameters.
void read_materials(SchemaReader& r, YAML::Node& root, Scenario& sc) {
  const KeyPath top{"", ""};
  // materials
  if (YAML::Node mats = r.section(root, top, "materials", YAML::NodeType::Map); mats.IsDefined()) {
    const KeyPath p = top.child("materials");
    for (auto it = mats.begin(); it != mats.end(); ++it) {
      const std::string name = it->first.Scalar();
      const KeyPath mp = p.item(name);
      const YAML::Node m = it->second;
      if (!m.IsMap()) {
        r.error(m, mp.actual, "expected a map with E, nu, rho");
        continue;
      }
      r.check_keys(m, mp);
      Material mat;
      mat.name = name;
      mat.model = r.string(m, mp, "model").value_or(std::string(law::kDefaultMaterialLaw));
      // The law's parameters as it declares them (law/laws.cpp); E, nu, rho among them.
      if (const law::LawDecl* decl = law::material_laws().find(mat.model)) {
        mat.law = static_cast<Index>(law::material_laws().index(mat.model));
        mat.params = read_law_params(r, m, mp, *decl, law::material_laws(), "model");
        if (sc.plane_stress && !decl->plane_stress)
          r.error(m["model"], mp.child("model").actual,
                  fmt::format("{} is plane strain only; remove mesh.plane: stress", mat.model));
        auto or_zero = [](double v) { return std::isnan(v) ? 0.0 : v; };
        mat.E = or_zero(decl->value(mat.params, "E"));
        mat.nu = or_zero(decl->value(mat.params, "nu"));
        mat.rho = or_zero(decl->value(mat.params, "rho"));
      }
      sc.materials[name] = mat;
    }
    if (mats.size() == 0) r.error(mats, "materials", "at least one material is needed");
  }
  for (auto& [name, m] : sc.materials) {
    m.plane_stress = sc.plane_stress;
    m.thickness = sc.thickness;
  }
}

// Regions: a material and a zone per surface group.
void read_regions(SchemaReader& r, YAML::Node& root, Scenario& sc) {
  const KeyPath top{"", ""};
  // regions
  if (YAML::Node regs = r.section(root, top, "regions", YAML::NodeType::Sequence); regs.IsDefined()) {
    const KeyPath p = top.child("regions");
    std::vector<std::string> names;
    for (const auto& [n, m] : sc.materials) names.push_back(n);
    for (std::size_t i = 0; i < regs.size(); ++i) {
      const KeyPath rp = p.index(i);
      const YAML::Node g = regs[i];
      if (!g.IsMap()) {
        r.error(g, rp.actual, "expected a map with group, material and zone");
        continue;
      }
      r.check_keys(g, rp);
      RegionSpec reg;
      reg.group = r.string(g, rp, "group").value_or("");
      reg.material = r.string(g, rp, "material").value_or("");
      const std::string zone = r.string(g, rp, "zone").value_or("continuous");
      reg.zone = zone == "discrete" ? Zone::Discrete : zone == "contact" ? Zone::ContactBedrock : Zone::Bedrock;
      reg.where_group = location(r, g["group"].IsDefined() ? g["group"] : g, rp.child("group").actual);
      reg.where_material = location(r, g["material"].IsDefined() ? g["material"] : g, rp.child("material").actual);
      if (!reg.material.empty() && !sc.materials.count(reg.material)) {
        const std::string near = nearest(reg.material, names);
        r.error(g["material"], rp.child("material").actual,
                fmt::format("no material '{}' under materials{}", reg.material,
                            near.empty() ? "" : "; did you mean '" + near + "'?"));
      }
      for (const auto& other : sc.regions)
        if (!reg.group.empty() && other.group == reg.group)
          r.error(g["group"], rp.child("group").actual, fmt::format("group '{}' is given two regions", reg.group));
      sc.regions.push_back(reg);
    }
  }
}

// Water at rest (top level or a stage's): a level or a line, the density, where the pore
// pressure acts, water in named cracks.
WaterSpec read_water(SchemaReader& r, const YAML::Node& w, const KeyPath& p) {
  r.check_keys(w, p);
  WaterSpec ws;
  // dry: true keeps the values (checked alike) and switches the water off.
  ws.present = !r.boolean(w, p, "dry").value_or(false);
  const std::optional<double> level = r.number(w, p, "level");
  const auto line = r.polyline(w, p, "line");
  const std::optional<double> ru = r.number(w, p, "ru");
  if ((level ? 1 : 0) + (line ? 1 : 0) + (ru ? 1 : 0) > 1)
    r.error(w[ru ? "ru" : "line"], p.child(ru ? "ru" : "line").actual, "give one of level, line and ru");
  if (ws.present && !level && !line && !ru && !w["line"].IsDefined())
    r.error(w, p.actual, "missing level (m) or line [[x, z], ...] (m): the piezometric line (or a ratio ru)");
  ws.ru = ru.value_or(0.0);
  if (level) ws.line = {Vec2(0.0, *level)};
  if (line)
    for (const auto& row : *line) ws.line.emplace_back(row[0], row[1]);
  ws.where = location(r, w[line ? "line" : "level"].IsDefined() ? w[line ? "line" : "level"] : w,
                      p.child(line ? "line" : "level").actual);
  ws.density = r.number(w, p, "density").value_or(1000.0);
  ws.pore_pressure_in_matrix = r.string(w, p, "pore_pressure").value_or("saturated") == "saturated";
  if (YAML::Node cs = r.section(w, p, "cracks", YAML::NodeType::Sequence); cs.IsDefined()) {
    const KeyPath cp = p.child("cracks");
    for (std::size_t i = 0; i < cs.size(); ++i) {
      const KeyPath ip = cp.index(i);
      if (!cs[i].IsMap()) {
        r.error(cs[i], ip.actual, "expected a map with curve and level");
        continue;
      }
      r.check_keys(cs[i], ip);
      CrackWaterSpec c;
      c.curve = r.string(cs[i], ip, "curve").value_or("");
      c.level = r.number(cs[i], ip, "level").value_or(0.0);
      c.where = location(r, cs[i]["curve"].IsDefined() ? cs[i]["curve"] : cs[i], ip.child("curve").actual);
      ws.cracks.push_back(std::move(c));
    }
  }
  return ws;
}

// Boundaries, gravity, damping, time and the stages that take them over.
void read_time_and_stages(SchemaReader& r, YAML::Node& root, Scenario& sc) {
  const KeyPath top{"", ""};
  std::vector<BoundarySpec> boundaries;
  if (YAML::Node b = r.section(root, top, "boundaries", YAML::NodeType::Sequence); b.IsDefined())
    boundaries = read_boundaries(r, b, top.child("boundaries"));

  if (auto g = r.vector(root, top, "gravity")) {
    sc.gravity_components = static_cast<int>(g->size());
    sc.where_gravity = location(r, root["gravity"], top.child("gravity").actual);
    if (g->size() == 2) sc.gravity = Vec2((*g)[0], (*g)[1]);
    else sc.gravity_3d = Vec3((*g)[0], (*g)[1], (*g)[2]);
  }
  DampingSpec damping;
  if (YAML::Node d = r.section(root, top, "damping", YAML::NodeType::Map); d.IsDefined())
    damping = read_damping(r, d, top.child("damping"), damping);
  WaterSpec water;
  if (YAML::Node w = r.section(root, top, "water", YAML::NodeType::Map); w.IsDefined())
    water = read_water(r, w, top.child("water"));

  std::optional<double> end;
  if (YAML::Node t = r.section(root, top, "time", YAML::NodeType::Map); t.IsDefined()) {
    const KeyPath p = top.child("time");
    r.check_keys(t, p);
    end = r.number(t, p, "end");
    sc.dt = r.number(t, p, "dt");
    sc.safety = r.number(t, p, "safety").value_or(0.3);
    const std::optional<bool> adaptive = r.boolean(t, p, "adaptive");
    if (adaptive && *adaptive && sc.dt)
      r.error(t["adaptive"], p.child("adaptive").actual,
              "adaptive: true takes the step from the stable step as joints break; it cannot be combined with a "
              "fixed time.dt (remove one of them)");
    sc.adaptive_dt = adaptive.value_or(true) && !sc.dt;
  }

  if (YAML::Node st = r.section(root, top, "stages", YAML::NodeType::Sequence); st.IsDefined()) {
    const KeyPath p = top.child("stages");
    for (std::size_t i = 0; i < st.size(); ++i) {
      const KeyPath sp = p.index(i);
      const YAML::Node s = st[i];
      if (!s.IsMap()) {
        r.error(s, sp.actual, "expected a map with name and duration");
        continue;
      }
      r.check_keys(s, sp);
      StageSpec stage;
      stage.name = r.string(s, sp, "name").value_or(fmt::format("stage{}", i + 1));
      stage.duration = r.number(s, sp, "duration").value_or(0.0);
      stage.damping = read_damping(r, r.section(s, sp, "damping", YAML::NodeType::Map), sp.child("damping"), damping);
      if (YAML::Node sb = r.section(s, sp, "boundaries", YAML::NodeType::Sequence); sb.IsDefined())
        stage.boundaries = read_boundaries(r, sb, sp.child("boundaries"));
      else
        stage.boundaries = boundaries;
      stage.stop_kinetic_ratio = r.number(s, sp, "stop_kinetic_ratio").value_or(0.0);
      stage.failure = r.boolean(s, sp, "failure").value_or(true);
      stage.earthquake = r.boolean(s, sp, "earthquake").value_or(false);
      if (YAML::Node w = r.section(s, sp, "water", YAML::NodeType::Map); w.IsDefined())
        stage.water = read_water(r, w, sp.child("water"));
      else
        stage.water = water;
      sc.stages.push_back(std::move(stage));
    }
    if (end && st.size() > 0)
      r.error(root["time"]["end"], "time.end", "give either time.end or stages with durations, not both");
  } else {
    StageSpec stage;
    stage.name = "main";
    stage.duration = end.value_or(0.0);
    stage.damping = damping;
    stage.boundaries = boundaries;
    stage.water = water;
    if (!end && root["time"].IsDefined()) r.error(root["time"], "time.end", "missing value (end time, s); or give stages");
    sc.stages.push_back(std::move(stage));
  }
}

// Joint properties: defaults, per group, the interface, per curve.
void read_joints(SchemaReader& r, YAML::Node& root, Scenario& sc) {
  const KeyPath top{"", ""};
  if (YAML::Node j = r.section(root, top, "joints", YAML::NodeType::Map); j.IsDefined()) {
    const KeyPath p = top.child("joints");
    r.check_keys(j, p);
    sc.joints.present = true;
    sc.joints.where = location(r, j, "joints");
    const std::string default_law(law::kDefaultJointLaw);
    if (YAML::Node d = r.section(j, p, "default", YAML::NodeType::Map); d.IsDefined())
      sc.joints.defaults = read_joint_spec(r, d, p.child("default"), default_law);
    else
      r.error(j, "joints.default", "missing section (the properties of every joint)");
    if (!sc.joints.defaults.law) sc.joints.defaults.law = default_law;
    const std::string base_law = *sc.joints.defaults.law;
    if (YAML::Node g = r.section(j, p, "groups", YAML::NodeType::Map); g.IsDefined())
      for (auto it = g.begin(); it != g.end(); ++it)
        sc.joints.groups[it->first.Scalar()] =
            read_joint_spec(r, it->second, p.child("groups").item(it->first.Scalar()), base_law);
    if (YAML::Node i = r.section(j, p, "interface", YAML::NodeType::Map); i.IsDefined())
      sc.joints.interface = read_joint_spec(r, i, p.child("interface"), base_law);
    if (YAML::Node c = r.section(j, p, "curves", YAML::NodeType::Map); c.IsDefined())
      for (auto it = c.begin(); it != c.end(); ++it)
        sc.joints.curves[it->first.Scalar()] =
            read_joint_spec(r, it->second, p.child("curves").item(it->first.Scalar()), base_law);
  }
}

// Contact law, its parameters and per pair overrides.
void read_contact(SchemaReader& r, YAML::Node& root, Scenario& sc) {
  const KeyPath top{"", ""};
  if (YAML::Node c = r.section(root, top, "contact", YAML::NodeType::Map); c.IsDefined()) {
    const KeyPath p = top.child("contact");
    r.check_keys(c, p);
    ContactSpec& cs = sc.contact;
    cs.present = true;
    cs.law = r.string(c, p, "law").value_or(std::string(law::kDefaultContactLaw));
    if (const law::LawDecl* decl = law::contact_laws().find(cs.law))
      check_law_keys(r, c, p, *decl, law::contact_laws(), "law");
    cs.penalty = r.number(c, p, "penalty").value_or(1.0);
    cs.kn = c["kn"].IsDefined() ? r.number(c, p, "kn") : std::nullopt;
    cs.ks_ratio = r.number(c, p, "ks_ratio").value_or(1.0);
    cs.friction = r.number(c, p, "friction").value_or(0.5);
    cs.restitution = r.number(c, p, "restitution").value_or(1.0);
    cs.rounding = r.number(c, p, "rounding").value_or(0.05);
    cs.skin = c["skin"].IsDefined() ? r.number(c, p, "skin") : std::nullopt;
    cs.output = r.boolean(c, p, "output").value_or(false);
    if (YAML::Node pl = r.section(c, p, "pairs", YAML::NodeType::Sequence); pl.IsDefined()) {
      for (std::size_t i = 0; i < pl.size(); ++i) {
        const KeyPath ip = p.child("pairs").index(i);
        if (!pl[i].IsMap()) {
          r.error(pl[i], ip.actual, "expected a map with groups and the contact law's pair parameters");
          continue;
        }
        r.check_keys(pl[i], ip);
        ContactPairSpec ps;
        const YAML::Node g = pl[i]["groups"];
        if (!g.IsSequence() || g.size() != 2 || !g[0].IsScalar() || !g[1].IsScalar())
          r.error(g.IsDefined() ? g : pl[i], ip.child("groups").actual, "expected two surface group names [a, b]");
        else {
          ps.group_a = g[0].Scalar();
          ps.group_b = g[1].Scalar();
        }
        ps.where = location(r, g.IsDefined() ? g : pl[i], ip.child("groups").actual);
        if (const law::LawDecl* decl = law::contact_laws().find(cs.law))
          ps.params = read_given_params(r, pl[i], ip, *decl, true);
        cs.pairs.push_back(ps);
      }
    }
  }
}

// The earthquake's components: a record file or a generated wave.
void read_earthquake(SchemaReader& r, YAML::Node& root, Scenario& sc) {
  const KeyPath top{"", ""};
  if (YAML::Node q = r.section(root, top, "earthquake", YAML::NodeType::Map); q.IsDefined()) {
    const KeyPath p = top.child("earthquake");
    r.check_keys(q, p);
    sc.earthquake.present = true;
    sc.earthquake.incident_factor = r.number(q, p, "incident_factor").value_or(0.5);
    for (auto [name, spec] : {std::pair<std::string, MotionSpec*>{"horizontal", &sc.earthquake.horizontal},
                              {"vertical", &sc.earthquake.vertical}}) {
      YAML::Node m = r.section(q, p, name, YAML::NodeType::Map);
      if (!m.IsDefined()) continue;
      const KeyPath mp = p.child(name);
      r.check_keys(m, mp);
      spec->present = true;
      spec->where = location(r, m, mp.actual);
      spec->scale = r.number(m, mp, "scale").value_or(1.0);
      if (m["direction"].IsDefined()) {
        spec->direction_given = true;
        const std::string d = r.string(m, mp, "direction").value_or("x");
        char* end = nullptr;
        const double az = std::strtod(d.c_str(), &end);
        if (d == "x") spec->azimuth_deg = 0.0;
        else if (d == "y") spec->azimuth_deg = 90.0;
        else if (end != d.c_str() && *end == '\0' && std::isfinite(az) && az >= 0.0 && az < 360.0) spec->azimuth_deg = az;
        else
          r.error(m["direction"], mp.child("direction").actual,
                  fmt::format("'{}' is not a direction: x, y or an azimuth in degrees from x toward y in [0, 360)", d));
      }
      spec->units = r.string(m, mp, "units").value_or("g");
      if (auto f = r.string(m, mp, "file")) {
        spec->file = sc.resolve(*f);
        if (const std::string problem = input_file_problem(spec->file); !problem.empty())
          r.error(m["file"], mp.child("file").actual, problem);
      }
      if (YAML::Node g = r.section(m, mp, "generate", YAML::NodeType::Map); g.IsDefined()) {
        const KeyPath gp = mp.child("generate");
        r.check_keys(g, gp);
        spec->generate = true;
        spec->spectrum = r.string(g, gp, "spectrum").value_or("hydraulic");
        spec->pga_g = r.number(g, gp, "pga").value_or(0.05);
        spec->Tg = r.number(g, gp, "Tg").value_or(0.35);
        spec->beta_max = r.number(g, gp, "beta_max").value_or(2.25);
        spec->damping = r.number(g, gp, "damping").value_or(0.05);
        spec->duration = r.number(g, gp, "duration").value_or(10.0);
        spec->dt = r.number(g, gp, "dt").value_or(0.02);
        spec->seed = static_cast<std::uint64_t>(r.integer(g, gp, "seed").value_or(1));
        spec->t1 = r.number(g, gp, "t1").value_or(1.5);
        spec->t2 = r.number(g, gp, "t2").value_or(6.5);
        spec->c = r.number(g, gp, "c").value_or(1.0);
      }
      if (spec->generate == !spec->file.empty() && (spec->generate || m["file"].IsDefined() == false))
        r.error(m, mp.actual, "give either file or generate");
    }
  }
}

// Output intervals, checkpoints and gauges.
void read_output(SchemaReader& r, YAML::Node& root, Scenario& sc) {
  const KeyPath top{"", ""};
  if (YAML::Node o = r.section(root, top, "output", YAML::NodeType::Map); o.IsDefined()) {
    const KeyPath p = top.child("output");
    r.check_keys(o, p);
    sc.output.field_interval = r.number(o, p, "field_interval").value_or(0.0);
    sc.output.history_interval = r.number(o, p, "history_interval").value_or(0.0);
    sc.output.progress_interval = r.number(o, p, "progress_interval").value_or(2.0);
    sc.output.checkpoint_steps = static_cast<long>(r.integer(o, p, "checkpoint_steps").value_or(0));
    sc.output.checkpoint_interval = r.number(o, p, "checkpoint_interval").value_or(600.0);
    if (YAML::Node gs = r.section(o, p, "gauges", YAML::NodeType::Sequence); gs.IsDefined()) {
      const KeyPath gp = p.child("gauges");
      for (std::size_t i = 0; i < gs.size(); ++i) {
        const KeyPath ip = gp.index(i);
        if (!gs[i].IsMap()) {
          r.error(gs[i], ip.actual, "expected a map with name and at");
          continue;
        }
        r.check_keys(gs[i], ip);
        GaugeSpec g;
        g.name = r.string(gs[i], ip, "name").value_or("");
        if (auto at = r.vector(gs[i], ip, "at")) {
          g.components = static_cast<int>(at->size());
          if (g.components == 2) g.at = Vec2((*at)[0], (*at)[1]);
          else g.at_3d = Vec3((*at)[0], (*at)[1], (*at)[2]);
        }
        g.where = location(r, gs[i]["at"].IsDefined() ? gs[i]["at"] : gs[i], ip.child("at").actual);
        for (const auto& other : sc.output.gauges)
          if (!g.name.empty() && other.name == g.name)
            r.error(gs[i]["name"], ip.child("name").actual, fmt::format("two gauges are named '{}'", g.name));
        sc.output.gauges.push_back(g);
      }
    }
  }
}

// Strength reduction (docs/theory.md §9): bounds, criteria, pseudo-static coefficients, monitored points.
void read_stability(SchemaReader& r, YAML::Node& root, Scenario& sc) {
  const KeyPath top{"", ""};
  YAML::Node s = r.section(root, top, "stability", YAML::NodeType::Map);
  if (!s.IsDefined()) return;
  const KeyPath p = top.child("stability");
  r.check_keys(s, p);
  StabilitySpec& st = sc.stability;
  st.present = true;
  st.where = location(r, s, p.actual);
  st.kh = r.number(s, p, "kh");
  st.kv = r.number(s, p, "kv");
  if (auto b = r.vector2(s, p, "bounds")) {
    st.F_low = (*b)[0];
    st.F_high = (*b)[1];
    if (!(st.F_low > 0.0 && st.F_high > st.F_low))
      r.error(s["bounds"], p.child("bounds").actual,
              fmt::format("[{}, {}]: give [F_low, F_high] with 0 < F_low < F_high", st.F_low, st.F_high));
  }
  st.where_bounds = location(r, s["bounds"].IsDefined() ? s["bounds"] : s, p.child("bounds").actual);
  st.tolerance = r.number(s, p, "tolerance").value_or(0.005);
  st.equilibrium_ratio = r.number(s, p, "equilibrium_ratio").value_or(1e-5);
  st.max_steps = static_cast<long>(r.integer(s, p, "max_steps").value_or(0));
  st.failure_displacement = r.number(s, p, "failure_displacement").value_or(0.0);
  st.local_damping = r.number(s, p, "local_damping").value_or(0.8);
  st.damping_alpha = r.number(s, p, "damping");
  st.check_budget = r.boolean(s, p, "check_budget").value_or(false);
  st.keep_tension = r.boolean(s, p, "keep_tension").value_or(false);
  st.dynamic = r.boolean(s, p, "dynamic").value_or(false);
  if (YAML::Node ms = r.section(s, p, "monitor", YAML::NodeType::Sequence); ms.IsDefined()) {
    const KeyPath mp = p.child("monitor");
    for (std::size_t i = 0; i < ms.size(); ++i) {
      const KeyPath ip = mp.index(i);
      if (!ms[i].IsMap()) {
        r.error(ms[i], ip.actual, "expected a map with name and at");
        continue;
      }
      r.check_keys(ms[i], ip);
      GaugeSpec g;
      g.name = r.string(ms[i], ip, "name").value_or("");
      if (auto at = r.vector2(ms[i], ip, "at")) g.at = Vec2((*at)[0], (*at)[1]);
      g.where = location(r, ms[i]["at"].IsDefined() ? ms[i]["at"] : ms[i], ip.child("at").actual);
      st.monitor.push_back(g);
    }
  }
}

}  // namespace dsdem::io::detail
