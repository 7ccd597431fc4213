#include "mesh/model_builder.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "fem/cst.hpp"
#include "io/schema.hpp"
#include "mesh/gmsh_reader.hpp"

namespace dsdem::mesh {

RawMesh load_mesh(const io::Scenario& sc, const std::string& work_dir) {
  const std::string path = sc.resolve(sc.mesh_file);
  if (std::filesystem::path(path).extension() == ".geo") {
    std::filesystem::create_directories(work_dir);
    const std::string msh = (std::filesystem::path(work_dir) / (std::filesystem::path(path).stem().string() + ".msh")).string();
    try {
      mesh_geo(path, *sc.element_size, msh);
    } catch (const std::exception& e) {
      throw io::ScenarioError({sc.where_mesh.describe(e.what())});
    }
    RawMesh m = read_msh(msh);
    m.source = path;
    return m;
  }
  try {
    return read_msh(path);
  } catch (const std::exception& e) {
    throw io::ScenarioError({sc.where_mesh.describe(e.what())});
  }
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

  // Region of each surface group.
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
      if (!g || g->dim == 2) errors.push_back(b.where.describe(missing_group_message(mesh, b.group, 1)));
    }
  if (!errors.empty()) {
    std::sort(errors.begin(), errors.end());
    errors.erase(std::unique(errors.begin(), errors.end()), errors.end());
    throw io::ScenarioError(errors);
  }

  // Nodes: shared (continuous mesh). Joint insertion in breakable zones splits them.
  model.nodes.resize(mesh.nodes.size());
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
    model.nodes.X[i] = mesh.nodes[i];
    model.nodes.origin[i] = static_cast<Index>(i);
  }
  model.triangles.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Index g = mesh.triangle_surface_group[t];
    const io::RegionSpec* reg = region_of_group[static_cast<std::size_t>(g)];
    model.triangles.conn[t] = mesh.triangles[t];
    model.triangles.group[t] = g;
    model.triangles.material[t] = material_index.at(reg->material);
    model.triangles.zone[t] = reg->zone;
  }

  // Groups keep the mesh's indices so triangle_surface_group stays valid.
  for (const auto& g : mesh.groups) {
    Group mg;
    mg.name = g.name;
    mg.kind = g.dim == 2 ? GroupKind::Surface : g.dim == 1 ? GroupKind::Curve : GroupKind::Point;
    mg.gmsh_tag = g.tag;
    mg.triangles = g.triangles;
    mg.nodes = g.nodes;
    mg.mesh_edges = g.edges;
    model.groups.push_back(std::move(mg));
  }

  // Reference geometry; a folded element is an input error.
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
  if (!errors.empty()) throw io::ScenarioError(errors);
  compute_lumped_masses(model);
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
