#include "mesh/model_builder3d.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "fem/tet4.hpp"
#include "law/registry.hpp"

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

}  // namespace dsdem::mesh
