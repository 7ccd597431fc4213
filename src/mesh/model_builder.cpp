#include "mesh/model_builder.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "fem/cst.hpp"
#include "io/schema.hpp"
#include "law/registry.hpp"
#include "mesh/gmsh_reader.hpp"
#include "contact/spheropolygon.hpp"
#include "mesh/joint_insertion.hpp"
#include "mesh/node_order.hpp"
#include "mesh/triangle_order.hpp"

#include <spdlog/spdlog.h>

namespace dsdem::mesh {

namespace {

RawMesh read_mesh_file(const io::Scenario& sc, const std::string& work_dir) {
  const std::string path = sc.resolve(sc.mesh_file);
  if (std::filesystem::path(path).extension() == ".geo") {
    std::filesystem::create_directories(work_dir);
    const std::string msh = (std::filesystem::path(work_dir) / (std::filesystem::path(path).stem().string() + ".msh")).string();
    try {
      mesh_geo(path, *sc.element_size, msh, sc.crossed_mesh);
    } catch (const std::exception& e) {
      throw io::ScenarioError({sc.where_mesh.describe(e.what())});
    }
    RawMesh m = read_msh(msh, sc.crossed_mesh);
    m.source = path;
    return m;
  }
  try {
    return read_msh(path, sc.crossed_mesh);
  } catch (const std::exception& e) {
    throw io::ScenarioError({sc.where_mesh.describe(e.what())});
  }
}

}  // namespace

RawMesh load_mesh(const io::Scenario& sc, const std::string& work_dir) {
  RawMesh m = read_mesh_file(sc, work_dir);
  if (sc.spatial_triangle_order) apply_triangle_order(m, spatial_triangle_order(m.nodes, m.triangles));
  return m;
}

static std::vector<std::string> group_names(const RawMesh& mesh, int dim) {
  std::vector<std::string> names;
  for (const auto& g : mesh.groups)
    if (g.dim == dim || (dim == 1 && g.dim == 0)) names.push_back(g.name);
  return names;
}

static std::string missing_group_message(const RawMesh& mesh, const std::string& name, int dim) {
  const auto names = group_names(mesh, dim);
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  const std::string near = io::nearest(name, names);
  return fmt::format("the mesh {} has no {} group '{}'{}; its {} groups are: {}", mesh.source,
                     dim == 2 ? "surface" : "curve or point", name, near.empty() ? "" : " (did you mean '" + near + "'?)",
                     dim == 2 ? "surface" : "curve/point", list.empty() ? "(none)" : list);
}

namespace {

// Mean element size sqrt(2A) of the triangles of one surface group, m.
double mean_element_size(const RawMesh& mesh, Index group) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (mesh.triangle_surface_group[t] != group) continue;
    const auto& c = mesh.triangles[t];
    const Vec2 a = mesh.nodes[c[1]] - mesh.nodes[c[0]], b = mesh.nodes[c[2]] - mesh.nodes[c[0]];
    sum += std::sqrt(std::abs(a.x() * b.y() - a.y() * b.x()));
    ++n;
  }
  return n > 0 ? sum / n : 0.0;
}

// A property from a (merged) spec; kn from the penalty rule p*E/h when absent (docs/theory.md §3).
// h here is a reference size (the group's mean): each joint rescales kn to its own local
// element size after insertion (set_local_penalty_scales), which log_penalty_stiffness reports.
JointProperties make_joint_property(const std::string& name, const io::JointSpec& spec, double E, double h,
                                    std::vector<std::string>& errors) {
  JointProperties p;
  p.name = name;
  p.law = static_cast<Index>(law::joint_laws().index(spec.law.value_or(std::string(law::kDefaultJointLaw))));
  const io::GivenParams& g = spec.params;
  if (const auto kn = g.get("kn")) {
    p.kn = *kn;
  } else {
    const double penalty = g.get("penalty").value_or(10.0);
    p.kn = penalty * E / h;
    p.penalty_h = h;
  }
  p.ks = g.get("ks").value_or(p.kn);
  p.ks_given = g.get("ks").has_value();
  p.ft = g.get("ft").value_or(0.0);
  p.c = g.get("c").value_or(0.0);
  p.phi = g.get("phi").value_or(0.0) * kPi / 180.0;
  p.GI = g.get("GI").value_or(0.0);
  p.GII = g.get("GII").value_or(0.0);
  p.initially_broken = spec.broken.value_or(false);
  const std::string problem = validate(p);
  if (!problem.empty()) errors.push_back(spec.where.describe(fmt::format("joint properties '{}': {}", name, problem)));
  return p;
}

// One log line per penalty property: kn = p E / h_local over its joints (docs/theory.md §3: logged
// as a range per joint set).
void log_penalty_stiffness(const Model& model) {
  const auto& J = model.joints;
  for (std::size_t p = 0; p < model.joint_properties.size(); ++p) {
    const JointProperties& prop = model.joint_properties[p];
    if (!(prop.penalty_h > 0.0)) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0, h_lo = lo, h_hi = 0.0;
    std::size_t n = 0;
    for (std::size_t j = 0; j < J.size(); ++j) {
      if (J.property[j] != static_cast<Index>(p)) continue;
      const double s = J.stiffness_scale[j];
      lo = std::min(lo, prop.kn * s), hi = std::max(hi, prop.kn * s);
      h_lo = std::min(h_lo, prop.penalty_h / s), h_hi = std::max(h_hi, prop.penalty_h / s);
      ++n;
    }
    if (n == 0) continue;
    spdlog::info("joints '{}': kn = p*E/h from the penalty rule with h the local element size (mean sqrt(2A) of the two "
                 "triangles, {:.4g} to {:.4g} m): kn = {:.4g} to {:.4g} Pa/m over {} joints (p*E = {:.4g} Pa){}",
                 prop.name, h_lo, h_hi, lo, hi, n, prop.kn * prop.penalty_h, prop.ks_given ? "; ks given" : "");
  }
}

}  // namespace

void build_joint_properties(const io::Scenario& sc, const RawMesh& mesh,
                            const std::vector<const io::RegionSpec*>& region_of_group,
                            const std::map<std::string, Index>& material_index, Model& model,
                            dsdem::JointInsertionOptions& opt, std::vector<std::string>& errors) {
  const io::JointsSection& js = sc.joints;
  double E_min = std::numeric_limits<double>::infinity(), h_min_group = std::numeric_limits<double>::infinity();
  for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
    const io::RegionSpec* reg = region_of_group[g];
    if (!reg || reg->zone != Zone::Discrete) continue;
    opt.breakable[g] = true;
    const Material& mat = model.materials[material_index.at(reg->material)];
    const double h = mean_element_size(mesh, static_cast<Index>(g));
    E_min = std::min(E_min, mat.E);
    h_min_group = std::min(h_min_group, h);
    io::JointSpec spec = js.defaults;
    if (auto it = js.groups.find(mesh.groups[g].name); it != js.groups.end()) spec = spec.merged(it->second);
    opt.group_property[g] = static_cast<Index>(model.joint_properties.size());
    model.joint_properties.push_back(make_joint_property(mesh.groups[g].name, spec, mat.E, h, errors));
  }
  for (const auto& [name, spec] : js.groups) {
    const RawPhysicalGroup* g = mesh.find(name);
    if (!g || g->dim != 2 || !opt.breakable[static_cast<std::size_t>(g - mesh.groups.data())])
      errors.push_back(spec.where.describe(fmt::format("'{}' is not a discrete surface group of the mesh", name)));
  }
  opt.default_property = 0;
  for (Index gp : opt.group_property)
    if (gp != kNoIndex) {
      opt.default_property = gp;
      break;
    }
  if (js.interface) {
    opt.interface_property = static_cast<Index>(model.joint_properties.size());
    model.joint_properties.push_back(
        make_joint_property("interface", js.defaults.merged(*js.interface), E_min, h_min_group, errors));
  }
  for (const auto& [name, spec] : js.curves) {
    const RawPhysicalGroup* g = mesh.find(name);
    if (!g || g->dim != 1) {
      errors.push_back(spec.where.describe(missing_group_message(mesh, name, 1)));
      continue;
    }
    const Index gi = static_cast<Index>(g - mesh.groups.data());
    opt.curve_property[gi] = static_cast<Index>(model.joint_properties.size());
    const io::JointSpec merged = js.defaults.merged(spec);
    model.joint_properties.push_back(make_joint_property(name, merged, E_min, h_min_group, errors));
    if (merged.broken.value_or(false)) opt.broken_curves.insert(gi);
  }
}

namespace {

// Zone-C triangles of one connected continuous mesh are one body: they never collide
// with each other (their elements cannot separate).
void set_contact_bodies(const Model& model, ContactSetup& c) {
  const std::size_t nt = model.triangles.size();
  std::vector<Index> parent(nt);
  for (std::size_t t = 0; t < nt; ++t) parent[t] = static_cast<Index>(t);
  auto root = [&](Index i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<Index> first(model.nodes.size(), kNoIndex);
  for (std::size_t t = 0; t < nt; ++t) {
    if (model.triangles.zone[t] != Zone::ContactBedrock) continue;
    for (Index n : model.triangles.conn[t]) {
      if (first[n] == kNoIndex) first[n] = static_cast<Index>(t);
      else {
        const Index a = root(first[n]), b = root(static_cast<Index>(t));
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
  }
  for (std::size_t t = 0; t < nt; ++t)
    if (model.triangles.zone[t] == Zone::ContactBedrock) c.body[t] = root(static_cast<Index>(t));
}

// Stiffness: given, or p_c * E of the softer side (docs/theory.md §4); times the thickness
// (plane stress) so forces are those of the slab. Sets the defaults and a pair per two
// active surface groups, then the scenario's pairs; returns E of the softest group.
double set_contact_pairs(const io::Scenario& sc, Model& model, std::vector<std::string>& errors) {
  ContactSetup& c = model.contact;
  const io::ContactSpec& cs = sc.contact;
  auto group_E = [&](Index g) {
    double E = std::numeric_limits<double>::infinity();
    for (Index t : model.groups[g].triangles) E = std::min(E, model.materials[model.triangles.material[t]].E);
    return E;
  };
  std::vector<Index> active_groups;
  for (std::size_t g = 0; g < model.groups.size(); ++g) {
    if (model.groups[g].kind != GroupKind::Surface || model.groups[g].triangles.empty()) continue;
    if (c.active[model.groups[g].triangles.front()]) active_groups.push_back(static_cast<Index>(g));
  }
  double E_min = std::numeric_limits<double>::infinity();
  for (Index g : active_groups) E_min = std::min(E_min, group_E(g));
  auto props = [&](double E, std::optional<double> kn, std::optional<double> mu, std::optional<double> e) {
    ContactProperties p;
    p.kn = kn.value_or(cs.kn.value_or(cs.penalty * E)) * model.thickness;
    p.ks = cs.ks_ratio * p.kn;
    p.mu = mu.value_or(cs.friction);
    p.restitution = e.value_or(cs.restitution);
    return p;
  };
  c.defaults = props(E_min, std::nullopt, std::nullopt, std::nullopt);
  c.max_kn = c.defaults.kn;
  for (std::size_t a = 0; a < active_groups.size(); ++a)
    for (std::size_t b = a; b < active_groups.size(); ++b) {
      const double E = std::min(group_E(active_groups[a]), group_E(active_groups[b]));
      c.pairs.push_back({active_groups[a], active_groups[b], props(E, std::nullopt, std::nullopt, std::nullopt)});
    }
  for (const auto& ps : cs.pairs) {
    const Index ga = model.find_group(ps.group_a), gb = model.find_group(ps.group_b);
    bool ok = true;
    for (auto [name, g] : {std::pair{ps.group_a, ga}, std::pair{ps.group_b, gb}}) {
      if (g == kNoIndex || model.groups[g].kind != GroupKind::Surface ||
          std::find(active_groups.begin(), active_groups.end(), g) == active_groups.end()) {
        errors.push_back(ps.where.describe(
            fmt::format("'{}' is not a surface group of the discrete or contact zone", name)));
        ok = false;
      }
    }
    if (!ok) continue;
    const double E = std::min(group_E(ga), group_E(gb));
    c.pairs.push_back({std::min(ga, gb), std::max(ga, gb), props(E, ps.params.get("kn"), ps.params.get("friction"), ps.params.get("restitution"))});
  }
  for (const auto& p : c.pairs) c.max_kn = std::max(c.max_kn, p.props.kn);
  return E_min;
}

}  // namespace

void setup_contact(const io::Scenario& sc, Model& model, std::vector<std::string>& errors) {
  ContactSetup& c = model.contact;
  const std::size_t nt = model.triangles.size();
  c.active.assign(nt, 0);
  c.radius.assign(nt, 0.0);
  c.body.assign(nt, -1);
  for (std::size_t t = 0; t < nt; ++t) c.active[t] = model.triangles.zone[t] != Zone::Bedrock ? 1 : 0;
  c.enabled = std::count(c.active.begin(), c.active.end(), 1) > 0;
  if (!c.enabled) return;
  const io::ContactSpec& cs = sc.contact;
  for (std::size_t t = 0; t < nt; ++t) {
    if (!c.active[t]) continue;
    const auto& n = model.triangles.conn[t];
    c.radius[t] = contact::rounding_radius(model.nodes.X[n[0]], model.nodes.X[n[1]], model.nodes.X[n[2]], cs.rounding);
  }
  set_contact_bodies(model, c);
  const double E_min = set_contact_pairs(sc, model, errors);
  c.skin = cs.skin.value_or(0.0);
  c.output = cs.output;
  spdlog::info("contact: {} spheropolygons, default kn = {:.4g} N/m per m of overlap ({}), friction {}, restitution {}",
               std::count(c.active.begin(), c.active.end(), 1), c.defaults.kn,
               cs.kn ? "given" : fmt::format("p_c*E with p_c = {}, E = {:.4g} Pa", cs.penalty, E_min), cs.friction,
               cs.restitution);
}

namespace {

void throw_sorted(std::vector<std::string>& errors) {
  std::sort(errors.begin(), errors.end());
  errors.erase(std::unique(errors.begin(), errors.end()), errors.end());
  throw io::ScenarioError(errors);
}

// Region of each surface group (by mesh group index); checks that every surface group
// with triangles has one and that the boundaries' groups exist.
std::vector<const io::RegionSpec*> regions_of_groups(const io::Scenario& sc, const RawMesh& mesh) {
  std::vector<std::string> errors;
  std::vector<const io::RegionSpec*> region_of_group(mesh.groups.size(), nullptr);
  for (const auto& reg : sc.regions) {
    const RawPhysicalGroup* g = mesh.find(reg.group);
    if (!g || g->dim != 2) {
      errors.push_back(reg.where_group.describe(missing_group_message(mesh, reg.group, 2)));
      continue;
    }
    region_of_group[static_cast<std::size_t>(g - mesh.groups.data())] = &reg;
  }
  for (std::size_t gi = 0; gi < mesh.groups.size(); ++gi) {
    if (mesh.groups[gi].dim == 2 && !region_of_group[gi]) {
      bool owns_triangles = false;
      for (Index t = 0; t < static_cast<Index>(mesh.triangles.size()); ++t)
        if (mesh.triangle_surface_group[t] == static_cast<Index>(gi)) owns_triangles = true;
      if (owns_triangles)
        errors.push_back(fmt::format("{}: regions: the mesh's surface group '{}' has no region (material and zone)",
                                     sc.file, mesh.groups[gi].name));
    }
  }
  // Groups referenced by boundaries and gauges.
  for (const auto& stage : sc.stages)
    for (const auto& b : stage.boundaries) {
      const RawPhysicalGroup* g = mesh.find(b.group);
      if (!g) errors.push_back(b.where.describe(missing_group_message(mesh, b.group, 1)));
    }
  if (!errors.empty()) throw_sorted(errors);
  return region_of_group;
}

// Copies of each mesh node in the model (CSR, as JointInsertionResult).
struct NodeCopies {
  std::vector<Index> offset, copies;
};

// Nodes, triangles and joints of a model with discrete zones (joints inserted).
NodeCopies insert_discrete_nodes(const io::Scenario& sc, const RawMesh& mesh,
                                 const std::vector<const io::RegionSpec*>& region_of_group,
                                 const std::map<std::string, Index>& material_index, Model& model,
                                 std::vector<std::string>& errors) {
  dsdem::JointInsertionOptions opt;
  opt.breakable.assign(mesh.groups.size(), false);
  opt.group_property.assign(mesh.groups.size(), kNoIndex);
  build_joint_properties(sc, mesh, region_of_group, material_index, model, opt, errors);
  if (!errors.empty()) throw io::ScenarioError(errors);
  dsdem::JointInsertionResult ins;
  try {
    ins = insert_joints(mesh, opt);
  } catch (const std::exception& e) {
    throw io::ScenarioError({e.what()});
  }
  // Nodes numbered in the order the triangles use them (mesh/node_order.hpp): the same
  // motion, the node data of a thread's triangles next to each other. Written in place:
  // a renumbered copy of the node arrays, freed at once, would keep its pages resident
  // (glibc then serves later large blocks from its heap).
  const std::vector<Index> new_id = node_order_by_first_use(ins.triangles, ins.nodes.size());
  model.nodes.resize(ins.nodes.size());
  for (std::size_t i = 0; i < ins.nodes.size(); ++i) {
    model.nodes.X[static_cast<std::size_t>(new_id[i])] = ins.nodes[i];
    model.nodes.origin[static_cast<std::size_t>(new_id[i])] = ins.origin[i];
  }
  model.triangles.resize(ins.triangles.size());
  for (std::size_t t = 0; t < ins.triangles.size(); ++t) {
    model.triangles.conn[t] = ins.triangles[t];
    renumber(model.triangles.conn[t], new_id);
  }
  model.joints = std::move(ins.joints);
  for (auto& nd : model.joints.nodes) renumber(nd, new_id);
  mark_initially_broken(model.joints, model.joint_properties, model.nodes.X);
  NodeCopies nc;
  nc.offset = std::move(ins.copies_offset);
  nc.copies = std::move(ins.copies);
  renumber(nc.copies, new_id);
  return nc;
}

// Nodes and triangles of a continuous model: nodes shared, numbered as in the discrete case.
NodeCopies continuous_nodes(const RawMesh& mesh, Model& model) {
  NodeCopies nc;
  const std::vector<Index> new_id = node_order_by_first_use(mesh.triangles, mesh.nodes.size());
  model.nodes.resize(mesh.nodes.size());
  model.triangles.resize(mesh.triangles.size());
  nc.offset.resize(mesh.nodes.size() + 1);
  nc.copies.reserve(mesh.nodes.size());
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
    model.nodes.X[static_cast<std::size_t>(new_id[i])] = mesh.nodes[i];
    model.nodes.origin[static_cast<std::size_t>(new_id[i])] = static_cast<Index>(i);
    nc.offset[i + 1] = static_cast<Index>(i + 1);
    nc.copies.push_back(new_id[i]);
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    model.triangles.conn[t] = mesh.triangles[t];
    renumber(model.triangles.conn[t], new_id);
  }
  return nc;
}

// Groups keep the mesh's indices so triangle_surface_group stays valid.
void build_groups(const RawMesh& mesh, const NodeCopies& nc, Model& model) {
  for (const auto& g : mesh.groups) {
    Group mg;
    mg.name = g.name;
    mg.kind = g.dim == 2 ? GroupKind::Surface : g.dim == 1 ? GroupKind::Curve : GroupKind::Point;
    mg.gmsh_tag = g.tag;
    mg.triangles = g.triangles;
    // A surface's nodes are those of its triangles (a driven body moves all of them).
    if (g.dim == 2)
      for (Index t : g.triangles)
        for (Index n : model.triangles.conn[t]) mg.nodes.push_back(n);
    // Every copy of a split mesh node belongs to the curve or point it lay on.
    for (Index n : g.nodes)
      if (static_cast<std::size_t>(n) + 1 < nc.offset.size())
        for (Index k = nc.offset[n]; k < nc.offset[n + 1]; ++k) mg.nodes.push_back(nc.copies[k]);
    std::sort(mg.nodes.begin(), mg.nodes.end());
    mg.nodes.erase(std::unique(mg.nodes.begin(), mg.nodes.end()), mg.nodes.end());
    mg.mesh_edges = g.edges;
    model.groups.push_back(std::move(mg));
  }
}

// Reference geometry; a folded element is an input error.
void set_reference_geometry(const RawMesh& mesh, Model& model, std::vector<std::string>& errors) {
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    const auto& c = model.triangles.conn[t];
    const auto geo = fem::reference_geometry(model.nodes.X[c[0]], model.nodes.X[c[1]], model.nodes.X[c[2]]);
    if (!(geo.area > 0.0)) {
      const Vec2 ctr = (model.nodes.X[c[0]] + model.nodes.X[c[1]] + model.nodes.X[c[2]]) / 3.0;
      errors.push_back(fmt::format("{}: element {} near ({:.6g}, {:.6g}) is inverted or degenerate (area {:.3g} m^2)",
                                   mesh.source, t, ctr.x(), ctr.y(), geo.area));
      continue;
    }
    model.triangles.Dm_inv[t] = geo.Dm_inv;
    model.triangles.area0[t] = geo.area;
  }
}

}  // namespace

Model build_model(const io::Scenario& sc, const RawMesh& mesh) {
  std::vector<std::string> errors;
  Model model;
  model.plane_stress = sc.plane_stress;
  model.thickness = sc.thickness;

  // Materials in a fixed order (the scenario map is sorted by name).
  std::map<std::string, Index> material_index;
  for (const auto& [name, m] : sc.materials) {
    material_index[name] = static_cast<Index>(model.materials.size());
    model.materials.push_back(m);
  }
  const std::vector<const io::RegionSpec*> region_of_group = regions_of_groups(sc, mesh);

  const bool any_discrete = std::any_of(sc.regions.begin(), sc.regions.end(),
                                       [](const io::RegionSpec& r) { return r.zone == Zone::Discrete; });
  const NodeCopies nc = any_discrete
                            ? insert_discrete_nodes(sc, mesh, region_of_group, material_index, model, errors)
                            : continuous_nodes(mesh, model);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Index g = mesh.triangle_surface_group[t];
    const io::RegionSpec* reg = region_of_group[static_cast<std::size_t>(g)];
    model.triangles.group[t] = g;
    model.triangles.material[t] = material_index.at(reg->material);
    model.triangles.zone[t] = reg->zone;
  }
  build_groups(mesh, nc, model);
  set_reference_geometry(mesh, model, errors);
  if (!errors.empty()) throw io::ScenarioError(errors);
  set_local_penalty_scales(model.joints, model.joint_properties, model.triangles.area0);
  log_penalty_stiffness(model);
  compute_lumped_masses(model);
  setup_law_state(model);
  setup_contact(sc, model, errors);
  if (!errors.empty()) throw io::ScenarioError(errors);
  return model;
}

void compute_lumped_masses(Model& model) {
  std::fill(model.nodes.m.begin(), model.nodes.m.end(), 0.0);
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    const Material& mat = model.materials[model.triangles.material[t]];
    const double m3 = mat.rho * model.triangles.area0[t] * model.thickness / 3.0;
    for (Index n : model.triangles.conn[t]) model.nodes.m[n] += m3;
  }
}

void setup_law_state(Model& model) {
  const auto& laws = law::material_laws();
  std::vector<std::uint8_t> used(model.materials.size(), 0);
  for (const Index m : model.triangles.material) used[static_cast<std::size_t>(m)] = 1;
  StateArrays& state = model.triangles.state;
  state = {};
  // Columns in material order, then declaration order: the same model gives the same layout.
  for (std::size_t m = 0; m < model.materials.size(); ++m) {
    Material& mat = model.materials[m];
    const law::LawDecl& decl = laws.get(mat.model);
    mat.law = static_cast<Index>(laws.index(mat.model));
    mat.state_columns.clear();
    if (!used[m]) continue;
    for (const auto& var : decl.state) mat.state_columns.push_back(state.add(var.name, var.unit, model.triangles.size()));
  }
  // Joints: the state the laws of the joint properties in use declare.
  Joints& J = model.joints;
  J.law_state = {};
  std::vector<std::uint8_t> law_used(law::joint_laws().size(), 0);
  for (const Index p : J.property) law_used[static_cast<std::size_t>(model.joint_properties[p].law)] = 1;
  for (std::size_t l = 0; l < law_used.size(); ++l)
    if (law_used[l])
      for (const auto& var : law::joint_laws().at(l).state) J.law_state.add(var.name, var.unit, J.size());
}

}  // namespace dsdem::mesh

namespace dsdem::mesh {
Model build_model(const RawMesh& mesh, const Material& material, Zone zone) {
  io::Scenario sc;
  sc.file = "(in code)";
  sc.plane_stress = material.plane_stress;
  sc.thickness = material.thickness;
  sc.materials[material.name.empty() ? "material" : material.name] = material;
  sc.materials.begin()->second.name = sc.materials.begin()->first;
  for (const auto& g : mesh.groups)
    if (g.dim == 2) sc.regions.push_back(io::RegionSpec{g.name, sc.materials.begin()->first, zone, {}, {}});
  sc.stages.push_back(io::StageSpec{});
  return build_model(sc, mesh);
}
}  // namespace dsdem::mesh
