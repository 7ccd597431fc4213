// to_raw_mesh_3d(): a parsed volume .msh file (msh_format.cpp) in the order the Gmsh API gave it.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "mesh/msh_format.hpp"

namespace dsdem::mesh {

namespace {

[[noreturn]] void fail(const MshFile& f, long line, const std::string& what) {
  throw std::runtime_error(fmt::format("{}:{}: {}", f.path, line, what));
}

std::string at(const Vec3& p) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", p.x(), p.y(), p.z()); }

using Face = std::array<Index, 3>;
Face sorted(Face f) {
  std::sort(f.begin(), f.end());
  return f;
}

struct Reader {
  const MshFile& f;
  RawMesh3& mesh;
  std::vector<Index> index_of;                     // file node -> mesh node (kNoIndex: unused)
  std::map<int, std::vector<Index>> entity_tets;   // volume entity tag -> tetrahedra
  std::vector<std::size_t> tet_element;            // the file element of each tetrahedron

  Index node(const MshElement& el, int j) const {
    return index_of[f.element_nodes[el.first_node + static_cast<std::size_t>(j)]];
  }

  void read_nodes() {
    index_of.assign(f.node_tags.size(), kNoIndex);
    for (const auto& [key, e] : f.entities)
      for (std::size_t i : e.nodes) {
        index_of[i] = static_cast<Index>(mesh.nodes.size());
        mesh.nodes.emplace_back(f.node_xyz[i][0], f.node_xyz[i][1], f.node_xyz[i][2]);
      }
    if (mesh.nodes.empty()) fail(f, f.last_line, "the mesh has no nodes (was it meshed?)");
  }

  // The tetrahedra of one volume entity, made right-handed; a volume whose elements do not
  // share one orientation is folded (some are inverted).
  void read_volume(int tag, const MshEntity& e) {
    int n_pos = 0, n_neg = 0;
    const MshElement* first_neg = nullptr;
    const MshElement* first_pos = nullptr;
    for (const auto& [type, elems] : e.elements) {
      if (type != kMshTetrahedron4)
        fail(f, f.elements[elems.front()].line,
             fmt::format("volume {} holds '{}' elements; dsdem needs linear 4-node tetrahedra (Mesh.ElementOrder = 1, "
                         "no recombination)", tag, msh_element_type(type)->name));
      for (std::size_t ei : elems) {
        const MshElement& el = f.elements[ei];
        std::array<Index, 4> t{node(el, 0), node(el, 1), node(el, 2), node(el, 3)};
        const Vec3 a = mesh.nodes[t[1]] - mesh.nodes[t[0]], b = mesh.nodes[t[2]] - mesh.nodes[t[0]],
                   c = mesh.nodes[t[3]] - mesh.nodes[t[0]];
        const double vol6 = a.dot(b.cross(c));
        const double scale = a.squaredNorm() + b.squaredNorm() + c.squaredNorm();
        if (!(std::abs(vol6) > 1e-12 * scale * std::sqrt(scale)))
          fail(f, el.line, fmt::format("tetrahedron {} (volume {}) is degenerate (zero volume) near {}", el.tag, tag,
                                       at(mesh.nodes[t[0]])));
        if (vol6 < 0) std::swap(t[1], t[2]);
        (vol6 < 0 ? n_neg : n_pos) += 1;
        const MshElement*& first = vol6 < 0 ? first_neg : first_pos;
        if (!first) first = &el;
        entity_tets[tag].push_back(static_cast<Index>(mesh.tetrahedra.size()));
        mesh.tetrahedra.push_back(t);
        tet_element.push_back(ei);
      }
    }
    if (n_pos > 0 && n_neg > 0) {
      const bool few_neg = n_neg <= n_pos;
      const MshElement& first = few_neg ? *first_neg : *first_pos;
      fail(f, first.line, fmt::format("volume {} has inverted elements: {} of its {} tetrahedra are {}-handed (first: "
                                      "element {})", tag, few_neg ? n_neg : n_pos, n_neg + n_pos,
                                      few_neg ? "left" : "right", first.tag));
    }
  }

  // Physical group (dim, tag) over its entities.
  RawPhysicalGroup3 make_group(std::pair<int, int> gkey, const std::vector<int>& ents) {
    const auto [dim, tag] = gkey;
    RawPhysicalGroup3 g;
    g.dim = dim;
    g.tag = tag;
    const auto name = f.physical_names.find(gkey);
    g.name = name != f.physical_names.end() && !name->second.empty() ? name->second
                                                                     : fmt::format("physical_{}_{}", dim, tag);
    const Index gi = static_cast<Index>(mesh.groups.size());
    for (int ent : ents) {
      if (dim == 3) {
        for (Index t : entity_tets[ent]) {
          g.tetrahedra.push_back(t);
          if (mesh.tetrahedron_volume_group[t] == kNoIndex) mesh.tetrahedron_volume_group[t] = gi;
        }
        continue;
      }
      for (const auto& [type, elems] : f.entities.at({dim, ent}).elements) {
        for (std::size_t ei : elems) {
          const MshElement& el = f.elements[ei];
          if (dim == 2 && type == kMshTriangle3) {  // checked to be a face by to_raw_mesh_3d
            const Face tri{node(el, 0), node(el, 1), node(el, 2)};
            g.faces.push_back(tri);
            g.nodes.insert(g.nodes.end(), tri.begin(), tri.end());
          } else if ((dim == 1 && type == kMshLine2) || (dim == 0 && type == kMshPoint)) {
            for (int j = 0; j < msh_element_type(type)->num_nodes; ++j) g.nodes.push_back(node(el, j));
          } else {
            fail(f, el.line, fmt::format("physical group '{}' has unsupported elements of type {} ('{}')", g.name, type,
                                         msh_element_type(type)->name));
          }
        }
      }
    }
    std::sort(g.nodes.begin(), g.nodes.end());
    g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
    return g;
  }
};

}  // namespace

bool is_volume_mesh(const MshFile& f) {
  for (const auto& [key, e] : f.entities)
    if (key.first == 3 && !e.elements.empty()) return true;
  return false;
}

RawMesh3 to_raw_mesh_3d(const MshFile& f) {
  RawMesh3 mesh;
  mesh.source = f.path;
  mesh.msh_file = f.path;
  Reader r{f, mesh, {}, {}, {}};
  r.read_nodes();
  for (const auto& [key, e] : f.entities)
    if (key.first == 3) r.read_volume(key.second, e);
  if (mesh.tetrahedra.empty()) fail(f, f.last_line, "the mesh has no tetrahedra");
  mesh.tetrahedron_volume_group.assign(mesh.tetrahedra.size(), kNoIndex);

  std::set<Face> faces;
  for (const auto& t : mesh.tetrahedra)
    for (int k = 0; k < 4; ++k) faces.insert(sorted({t[k], t[(k + 1) % 4], t[(k + 2) % 4]}));

  // Every surface triangle is a tetrahedron's face, in physical groups or not (Mesh.SaveAll).
  for (const auto& [key, e] : f.entities) {
    if (key.first != 2) continue;
    for (const auto& [type, elems] : e.elements)
      for (std::size_t ei : elems) {
        const MshElement& el = f.elements[ei];
        if (type != kMshTriangle3)
          fail(f, el.line, fmt::format("surface {} of a volume mesh holds '{}' elements (3-node triangles expected)",
                                       key.second, msh_element_type(type)->name));
        if (!faces.count(sorted({r.node(el, 0), r.node(el, 1), r.node(el, 2)})))
          fail(f, el.line, fmt::format("triangle {} of surface {} near {} is no tetrahedron's face: a volume mesh may "
                                       "not hold loose surfaces (mesh surfaces as the boundaries of volumes)", el.tag,
                                       key.second, at(mesh.nodes[r.node(el, 0)])));
      }
  }
  std::map<std::pair<int, int>, std::vector<int>> groups;
  for (const auto& [key, e] : f.entities)
    for (int p : e.physicals) groups[{key.first, p}].push_back(key.second);
  for (const auto& [gkey, ents] : groups) mesh.groups.push_back(r.make_group(gkey, ents));

  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
    if (mesh.tetrahedron_volume_group[t] == kNoIndex)
      fail(f, f.elements[r.tet_element[t]].line,
           fmt::format("tetrahedron near {} belongs to no physical volume group; give every volume a Physical Volume",
                       at(mesh.nodes[mesh.tetrahedra[t][0]])));
  return mesh;
}

}  // namespace dsdem::mesh
