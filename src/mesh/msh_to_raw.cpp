// to_raw_mesh(): a parsed .msh file (msh_format.cpp) in the order the Gmsh API gave it.
#include "mesh/msh_format.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dsdem::mesh {

namespace {

using EntityTriangles = std::map<int, std::vector<Index>>;  // surface entity tag -> triangles

[[noreturn]] void fail(const MshFile& f, long line, const std::string& what) {
  throw std::runtime_error(fmt::format("{}:{}: {}", f.path, line, what));
}

// Nodes entity by entity, as gmsh::model::mesh::getNodes() over all entities gave them;
// returns the mesh index of each file node (kNoIndex: unused).
std::vector<Index> read_nodes(const MshFile& f, RawMesh& mesh) {
  std::vector<Index> index_of(f.node_tags.size(), kNoIndex);
  for (const auto& [key, e] : f.entities)
    for (std::size_t i : e.nodes) {
      index_of[i] = static_cast<Index>(mesh.nodes.size());
      mesh.nodes.emplace_back(f.node_xyz[i][0], f.node_xyz[i][1]);
    }
  if (mesh.nodes.empty()) fail(f, f.last_line, "the mesh has no nodes (was it meshed?)");
  return index_of;
}

Index node_of(const MshFile& f, const std::vector<Index>& index_of, const MshElement& el, int j) {
  return index_of[f.element_nodes[el.first_node + static_cast<std::size_t>(j)]];
}

template <std::size_t N>
std::array<Index, N> nodes_of(const MshFile& f, const std::vector<Index>& index_of, const MshElement& el) {
  std::array<Index, N> v;
  for (std::size_t j = 0; j < N; ++j) v[j] = node_of(f, index_of, el, static_cast<int>(j));
  return v;
}

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// A 3-node triangle, made counter-clockwise; returns whether the file gave it clockwise.
bool add_triangle(const MshFile& f, const MshElement& el, int tag, std::array<Index, 3> t, RawMesh& mesh,
                  std::vector<Index>& triangles_out) {
  const Vec2 a = mesh.nodes[t[1]] - mesh.nodes[t[0]], b = mesh.nodes[t[2]] - mesh.nodes[t[0]];
  const double area2 = cross(a, b);
  const double scale = a.squaredNorm() + b.squaredNorm();
  if (!(std::abs(area2) > 1e-12 * scale))
    fail(f, el.line, fmt::format("triangle {} (surface {}) is degenerate (zero area) near ({:.6g}, {:.6g})", el.tag,
                                 tag, mesh.nodes[t[0]].x(), mesh.nodes[t[0]].y()));
  if (area2 < 0) std::swap(t[1], t[2]);
  triangles_out.push_back(static_cast<Index>(mesh.triangles.size()));
  mesh.triangles.push_back(t);
  return area2 < 0;
}

// A 4-node quadrilateral as four counter-clockwise triangles around a new node where its
// diagonals cross (docs/theory.md §2: taken in pairs they are both diagonal splits, so
// they lock less than any other four); returns whether the file gave it clockwise.
bool add_crossed_quad(const MshFile& f, const MshElement& el, int tag, std::array<Index, 4> q, RawMesh& mesh,
                      std::vector<Index>& triangles_out) {
  const auto at = [&](int j) -> Vec2 { return mesh.nodes[q[static_cast<std::size_t>(j)]]; };
  const double area2 = cross(at(2) - at(0), at(3) - at(1));  // twice its signed area
  const double scale = (at(2) - at(0)).squaredNorm() + (at(3) - at(1)).squaredNorm();
  if (!(std::abs(area2) > 1e-12 * scale))
    fail(f, el.line, fmt::format("quadrilateral {} (surface {}) is degenerate (zero area) near ({:.6g}, {:.6g})", el.tag,
                                 tag, at(0).x(), at(0).y()));
  const bool cw = area2 < 0;
  if (cw) std::swap(q[1], q[3]);
  // a + t (c - a) = b + s (d - b): the diagonals cross inside a strictly convex quadrilateral.
  const Vec2 ac = at(2) - at(0), bd = at(3) - at(1);
  const double t = cross(at(1) - at(0), bd) / cross(ac, bd);
  const Index centre = static_cast<Index>(mesh.nodes.size());
  mesh.nodes.push_back(at(0) + t * ac);
  for (std::size_t j = 0; j < 4; ++j) {
    const std::array<Index, 3> tri{q[j], q[(j + 1) % 4], centre};
    const Vec2 a = mesh.nodes[tri[1]] - mesh.nodes[tri[0]], b = mesh.nodes[tri[2]] - mesh.nodes[tri[0]];
    if (!(cross(a, b) > 1e-12 * scale))
      fail(f, el.line, fmt::format("quadrilateral {} (surface {}) near ({:.6g}, {:.6g}) is not strictly convex: it "
                                   "cannot be split at the crossing of its diagonals", el.tag, tag, at(0).x(), at(0).y()));
    triangles_out.push_back(static_cast<Index>(mesh.triangles.size()));
    mesh.triangles.push_back(tri);
  }
  return cw;
}

// The triangles of one surface entity, made counter-clockwise (with `crossed`, its
// quadrilaterals split in four); a surface whose elements do not share one orientation is
// folded (some are inverted). triangle_element: the file element of each triangle.
void read_surface(const MshFile& f, const std::vector<Index>& index_of, int tag, const MshEntity& e, bool crossed,
                  RawMesh& mesh, EntityTriangles& entity_triangles, std::vector<std::size_t>& triangle_element) {
  int n_ccw = 0, n_cw = 0;
  const MshElement* first_cw = nullptr;
  const MshElement* first_ccw = nullptr;
  for (const auto& [type, elems] : e.elements) {
    if (type != kMshTriangle3 && !(crossed && type == kMshQuad4))
      fail(f, f.elements[elems.front()].line,
           fmt::format("surface {} holds '{}' elements; dsdem needs linear 3-node triangles (Mesh.ElementOrder = 1, "
                       "no recombination){}", tag, msh_element_type(type)->name,
                       type == kMshQuad4 ? ", or mesh.crossed: true to split each quadrilateral into four" : ""));
    for (std::size_t ei : elems) {
      const MshElement& el = f.elements[ei];
      const bool quad = type == kMshQuad4;
      const bool cw = quad ? add_crossed_quad(f, el, tag, nodes_of<4>(f, index_of, el), mesh, entity_triangles[tag])
                           : add_triangle(f, el, tag, nodes_of<3>(f, index_of, el), mesh, entity_triangles[tag]);
      triangle_element.resize(mesh.triangles.size(), ei);
      (cw ? n_cw : n_ccw) += quad ? 4 : 1;
      const MshElement*& first = cw ? first_cw : first_ccw;
      if (!first) first = &el;
    }
  }
  if (n_ccw > 0 && n_cw > 0) {
    const bool few_cw = n_cw <= n_ccw;
    const MshElement& first = few_cw ? *first_cw : *first_ccw;
    fail(f, first.line, fmt::format("surface {} has inverted elements: {} of its {} triangles are {} (first: element {})",
                                    tag, few_cw ? n_cw : n_ccw, n_cw + n_ccw, few_cw ? "clockwise" : "counter-clockwise",
                                    first.tag));
  }
}

// Physical group (dim, tag) over its entities `ents`; the first surface group of a
// triangle becomes its triangle_surface_group.
RawPhysicalGroup make_group(const MshFile& f, const std::vector<Index>& index_of, std::pair<int, int> gkey,
                            const std::vector<int>& ents, EntityTriangles& entity_triangles, RawMesh& mesh) {
  const auto [dim, tag] = gkey;
  RawPhysicalGroup g;
  g.dim = dim;
  g.tag = tag;
  const auto name = f.physical_names.find(gkey);
  g.name = name != f.physical_names.end() && !name->second.empty() ? name->second : fmt::format("physical_{}_{}", dim, tag);
  const Index gi = static_cast<Index>(mesh.groups.size());
  for (int ent : ents) {
    if (dim == 3)
      fail(f, f.last_line, fmt::format("3D physical group '{}' in a plane mesh (a volume mesh holds tetrahedra)", g.name));
    if (dim == 2) {
      for (Index t : entity_triangles[ent]) {
        g.triangles.push_back(t);
        if (mesh.triangle_surface_group[t] == kNoIndex) mesh.triangle_surface_group[t] = gi;
      }
      continue;
    }
    for (const auto& [type, elems] : f.entities.at({dim, ent}).elements) {
      for (std::size_t ei : elems) {
        const MshElement& el = f.elements[ei];
        if (type == kMshLine2)
          g.edges.push_back({node_of(f, index_of, el, 0), node_of(f, index_of, el, 1)});
        else if (type == kMshPoint)
          g.nodes.push_back(node_of(f, index_of, el, 0));
        else
          fail(f, el.line, fmt::format("physical group '{}' has unsupported elements of type {} ('{}')", g.name, type,
                                       msh_element_type(type)->name));
      }
    }
  }
  if (dim == 1) {
    for (const auto& e : g.edges) {
      g.nodes.push_back(e[0]);
      g.nodes.push_back(e[1]);
    }
  }
  std::sort(g.nodes.begin(), g.nodes.end());
  g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
  return g;
}

// A triangle outside every physical surface is an error, named by its element line.
void check_orphans(const MshFile& f, const EntityTriangles& entity_triangles,
                   const std::vector<std::size_t>& triangle_element, const RawMesh& mesh) {
  for (const auto& [key, e] : f.entities) {
    if (key.first != 2) continue;
    const auto it = entity_triangles.find(key.second);
    if (it == entity_triangles.end()) continue;
    for (const Index t : it->second) {
      if (mesh.triangle_surface_group[t] != kNoIndex) continue;
      const Vec2 c = (mesh.nodes[mesh.triangles[t][0]] + mesh.nodes[mesh.triangles[t][1]] + mesh.nodes[mesh.triangles[t][2]]) / 3.0;
      fail(f, f.elements[triangle_element[static_cast<std::size_t>(t)]].line,
           fmt::format("triangle near ({:.6g}, {:.6g}) belongs to no physical surface group; give every surface a Physical Surface",
                       c.x(), c.y()));
    }
  }
}

}  // namespace

RawMesh to_raw_mesh(const MshFile& f, bool crossed) {
  if (is_volume_mesh(f))
    fail(f, f.last_line, "the mesh holds volumes (tetrahedra): a 3D model, which only dsdem run and dsdem check "
                         "take so far (docs/theory.md §14)");
  if (f.first_off_plane.line > 0)
    fail(f, f.first_off_plane.line,
         fmt::format("node {} has z = {} ; a plane mesh lies in z = 0 (a 3D model is meshed as volumes)",
                     f.first_off_plane.tag, f.first_off_plane.z));
  RawMesh mesh;
  mesh.source = f.path;
  mesh.msh_file = f.path;
  const std::vector<Index> index_of = read_nodes(f, mesh);

  // Every triangle of every surface entity (by tag), once; physical groups refer to entities.
  EntityTriangles entity_triangles;
  std::vector<std::size_t> triangle_element;
  for (const auto& [key, e] : f.entities)
    if (key.first == 2) read_surface(f, index_of, key.second, e, crossed, mesh, entity_triangles, triangle_element);
  if (mesh.triangles.empty()) fail(f, f.last_line, "the mesh has no triangles");
  mesh.triangle_surface_group.assign(mesh.triangles.size(), kNoIndex);

  // Physical groups by (dim, tag), each with its entities by tag, as the Gmsh API listed them.
  std::map<std::pair<int, int>, std::vector<int>> groups;
  for (const auto& [key, e] : f.entities)
    for (int p : e.physicals) groups[{key.first, p}].push_back(key.second);
  for (const auto& [gkey, ents] : groups) {
    RawPhysicalGroup g = make_group(f, index_of, gkey, ents, entity_triangles, mesh);
    mesh.groups.push_back(std::move(g));
  }
  check_orphans(f, entity_triangles, triangle_element, mesh);
  return mesh;
}

}  // namespace dsdem::mesh
