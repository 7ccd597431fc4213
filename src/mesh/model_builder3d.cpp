#include "mesh/model_builder3d.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "fem/tet4.hpp"
#include "io/schema.hpp"
#include "law/registry.hpp"
#include "mesh/gmsh_reader.hpp"

namespace dsdem::mesh {

Model3 build_model_3d(const RawMesh3& mesh, const std::map<std::string, Material>& materials) {
  Model3 model;
  model.nodes.resize(mesh.nodes.size());
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
    model.nodes.X[i] = mesh.nodes[i];
    model.nodes.origin[i] = static_cast<Index>(i);
  }
  // Materials in name order; each volume group takes its own by name.
  std::map<std::string, Index> material_index;
  const auto& laws = law::material_laws();
  for (const auto& [name, mat] : materials) {
    Material m = mat;
    m.name = name;
    m.plane_stress = false;
    m.law = static_cast<Index>(laws.index(m.model));
    if (m.law < 0) throw std::invalid_argument(fmt::format("material '{}': unknown law '{}'", name, m.model));
    material_index[name] = static_cast<Index>(model.materials.size());
    model.materials.push_back(std::move(m));
  }
  std::vector<Index> group_material(mesh.groups.size(), kNoIndex);
  for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
    const RawPhysicalGroup3& rg = mesh.groups[g];
    Group3 out{rg.name, rg.dim, rg.tag, rg.tetrahedra, rg.faces, rg.nodes};
    if (rg.dim == 3) {
      const auto it = material_index.find(rg.name);
      if (it == material_index.end())
        throw std::invalid_argument(fmt::format("volume '{}' has no material", rg.name));
      group_material[g] = it->second;
      for (const Index t : rg.tetrahedra)
        for (const Index v : mesh.tetrahedra[static_cast<std::size_t>(t)]) out.nodes.push_back(v);
      std::sort(out.nodes.begin(), out.nodes.end());
      out.nodes.erase(std::unique(out.nodes.begin(), out.nodes.end()), out.nodes.end());
    }
    model.groups.push_back(std::move(out));
  }
  Tetrahedra& tet = model.tetrahedra;
  const std::size_t n = mesh.tetrahedra.size();
  tet.conn = mesh.tetrahedra;
  tet.group = mesh.tetrahedron_volume_group;
  tet.material.resize(n);
  tet.Dm_inv.resize(n);
  tet.volume0.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto& c = tet.conn[t];
    tet.material[t] = group_material[static_cast<std::size_t>(tet.group[t])];
    const auto g = fem::tet_reference_geometry(mesh.nodes[c[0]], mesh.nodes[c[1]], mesh.nodes[c[2]], mesh.nodes[c[3]]);
    if (!(g.volume > 0.0)) {
      const Vec3& p = mesh.nodes[c[0]];
      throw std::invalid_argument(fmt::format("{}: tetrahedron {} near ({:.6g}, {:.6g}, {:.6g}) has volume {:.3g} m^3 "
                                              "(inverted or degenerate)", mesh.source, t, p.x(), p.y(), p.z(), g.volume));
    }
    tet.Dm_inv[t] = g.Dm_inv;
    tet.volume0[t] = g.volume;
  }
  compute_lumped_masses(model);
  return model;
}

Model3 build_model_3d(const RawMesh3& mesh, const Material& material) {
  std::map<std::string, Material> by_group;
  for (const auto& g : mesh.groups)
    if (g.dim == 3) by_group[g.name] = material;
  return build_model_3d(mesh, by_group);
}

void compute_lumped_masses(Model3& model) {
  auto& m = model.nodes.m;
  std::fill(m.begin(), m.end(), 0.0);
  const Tetrahedra& tet = model.tetrahedra;
  for (std::size_t t = 0; t < tet.size(); ++t) {
    const double mt = fem::tet_lumped_mass(model.materials[static_cast<std::size_t>(tet.material[t])].rho, tet.volume0[t]);
    for (const Index v : tet.conn[t]) m[static_cast<std::size_t>(v)] += mt;
  }
}

namespace fs = std::filesystem;

std::optional<RawMesh3> load_volume_mesh(const io::Scenario& sc, const std::string& work_dir) {
  const std::string path = sc.resolve(sc.mesh_file);
  try {
    if (fs::path(path).extension() == ".geo") {
      // A 1D mesh is enough to list the geometry's entities: volumes make it a 3D model.
      fs::create_directories(work_dir);
      const std::string probe = (fs::path(work_dir) / (fs::path(path).stem().string() + ".entities.msh")).string();
      mesh_geo(path, *sc.element_size, probe, false, 1);
      const std::string text = [&] {
        std::ifstream in(probe, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      }();
      fs::remove(probe);
      // The header of $Entities counts points, curves, surfaces and volumes (the 1D mesh
      // itself may hold no nodes: only physical groups' elements are saved).
      const std::size_t at = text.find("$Entities\n");
      std::istringstream counts(at == std::string::npos ? std::string() : text.substr(at + 10, 200));
      long points = 0, curves = 0, surfaces = 0, volumes = 0;
      if (!(counts >> points >> curves >> surfaces >> volumes))
        throw std::runtime_error(fmt::format("{}: gmsh listed no entities of the geometry", path));
      if (volumes == 0) return std::nullopt;
      const std::string msh = (fs::path(work_dir) / (fs::path(path).stem().string() + ".msh")).string();
      mesh_geo(path, *sc.element_size, msh, false, 3);
      RawMesh3 m = std::get<RawMesh3>(read_msh_any(msh));
      m.source = path;
      return m;
    }
    auto any = read_msh_any(path, sc.crossed_mesh);
    if (auto* m = std::get_if<RawMesh3>(&any)) return std::move(*m);
    return std::nullopt;
  } catch (const io::ScenarioError&) {
    throw;
  } catch (const std::exception& e) {
    throw io::ScenarioError({sc.where_mesh.describe(e.what())});
  }
}

Model3 build_model_3d(const io::Scenario& sc, const RawMesh3& mesh) {
  std::vector<std::string> errors;
  std::vector<std::string> volumes;
  for (const auto& g : mesh.groups)
    if (g.dim == 3) volumes.push_back(g.name);
  std::string list;
  for (const auto& v : volumes) list += (list.empty() ? "" : ", ") + v;
  std::map<std::string, Material> by_volume;
  for (const auto& r : sc.regions) {
    const RawPhysicalGroup3* g = mesh.find(r.group);
    if (!g || g->dim != 3) {
      const std::string near = io::nearest(r.group, volumes);
      errors.push_back(r.where_group.describe(fmt::format(
          "the mesh {} has no volume group '{}'{}; its volumes are: {}", mesh.source, r.group,
          near.empty() ? "" : " (did you mean '" + near + "'?)", list.empty() ? "(none)" : list)));
      continue;
    }
    const auto m = sc.materials.find(r.material);
    if (m == sc.materials.end()) continue;  // the scenario's own check names it
    by_volume[r.group] = m->second;
  }
  for (const auto& v : volumes)
    if (!by_volume.count(v))
      errors.push_back(fmt::format("{}: regions: the mesh's volume '{}' has no region (give it a material)", sc.file, v));
  if (!errors.empty()) throw io::ScenarioError(errors);
  try {
    // Materials under the scenario's names, each volume group taking its region's.
    Model3 model = build_model_3d(mesh, by_volume);
    for (auto& mat : model.materials)  // build_model_3d named them after the volumes
      for (const auto& r : sc.regions)
        if (r.group == mat.name) mat.name = r.material;
    return model;
  } catch (const std::invalid_argument& e) {
    throw io::ScenarioError({fmt::format("{}: {}", sc.file, e.what())});
  }
}

}  // namespace dsdem::mesh
