#include "mesh/structured.hpp"

#include <algorithm>

namespace dsdem::mesh {

RawMesh rectangle_mesh(int nx, int ny, double lx, double ly, Diagonal diagonal, double x0, double y0,
                       const std::string& surface_name) {
  RawMesh m;
  m.source = "rectangle_mesh";
  auto id = [&](int i, int j) { return static_cast<Index>(j * (nx + 1) + i); };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.nodes.emplace_back(x0 + lx * i / nx, y0 + ly * j / ny);
  RawPhysicalGroup dom;
  dom.name = surface_name;
  dom.dim = 2;
  dom.tag = 1;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Index a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (diagonal == Diagonal::Cross) {
        const Index ctr = static_cast<Index>(m.nodes.size());
        m.nodes.emplace_back(x0 + lx * (i + 0.5) / nx, y0 + ly * (j + 0.5) / ny);
        for (auto t : {std::array<Index, 3>{a, b, ctr}, {b, c, ctr}, {c, d, ctr}, {d, a, ctr}}) m.triangles.push_back(t);
      } else if (diagonal == Diagonal::Right || (i + j) % 2 == 0) {
        m.triangles.push_back({a, b, c});
        m.triangles.push_back({a, c, d});
      } else {
        m.triangles.push_back({a, b, d});
        m.triangles.push_back({b, c, d});
      }
    }
  for (Index t = 0; t < static_cast<Index>(m.triangles.size()); ++t) dom.triangles.push_back(t);
  m.groups.push_back(dom);
  m.triangle_surface_group.assign(m.triangles.size(), 0);
  auto curve = [&](const std::string& name, int tag, auto node_at, int count) {
    RawPhysicalGroup g;
    g.name = name;
    g.dim = 1;
    g.tag = tag;
    for (int k = 0; k < count; ++k) g.edges.push_back({node_at(k), node_at(k + 1)});
    for (int k = 0; k <= count; ++k) g.nodes.push_back(node_at(k));
    std::sort(g.nodes.begin(), g.nodes.end());
    m.groups.push_back(g);
  };
  curve("bottom", 1, [&](int k) { return id(k, 0); }, nx);
  curve("right", 2, [&](int k) { return id(nx, k); }, ny);
  curve("top", 3, [&](int k) { return id(nx - k, ny); }, nx);
  curve("left", 4, [&](int k) { return id(0, ny - k); }, ny);
  return m;
}

void append_mesh(RawMesh& mesh, const RawMesh& other) {
  const Index node_offset = static_cast<Index>(mesh.nodes.size());
  const Index tri_offset = static_cast<Index>(mesh.triangles.size());
  mesh.nodes.insert(mesh.nodes.end(), other.nodes.begin(), other.nodes.end());
  for (auto t : other.triangles) {
    for (auto& n : t) n += node_offset;
    mesh.triangles.push_back(t);
  }
  for (std::size_t k = 0; k < other.triangles.size(); ++k) {
    const RawPhysicalGroup& og = other.groups[other.triangle_surface_group[k]];
    const RawPhysicalGroup* existing = mesh.find(og.name);
    Index gi = existing ? static_cast<Index>(existing - mesh.groups.data()) : kNoIndex;
    if (gi == kNoIndex) {
      RawPhysicalGroup g;
      g.name = og.name;
      g.dim = og.dim;
      g.tag = static_cast<int>(mesh.groups.size()) + 1;
      mesh.groups.push_back(g);
      gi = static_cast<Index>(mesh.groups.size()) - 1;
    }
    mesh.triangle_surface_group.push_back(gi);
    mesh.groups[gi].triangles.push_back(tri_offset + static_cast<Index>(k));
  }
  for (const auto& og : other.groups) {
    if (og.dim == 2) continue;
    RawPhysicalGroup* g = nullptr;
    for (auto& q : mesh.groups)
      if (q.name == og.name) g = &q;
    if (!g) {
      mesh.groups.push_back(RawPhysicalGroup{og.name, og.dim, static_cast<int>(mesh.groups.size()) + 1, {}, {}, {}});
      g = &mesh.groups.back();
    }
    for (auto e : og.edges) g->edges.push_back({e[0] + node_offset, e[1] + node_offset});
    for (auto n : og.nodes) g->nodes.push_back(n + node_offset);
    std::sort(g->nodes.begin(), g->nodes.end());
  }
}

}  // namespace dsdem::mesh

namespace dsdem::mesh {

RawMesh3 box_mesh(int nx, int ny, int nz, double lx, double ly, double lz, const Vec3& origin) {
  RawMesh3 m;
  m.source = "box_mesh";
  const int n[3] = {nx, ny, nz};
  auto id = [&](int i, int j, int k) { return static_cast<Index>((k * (ny + 1) + j) * (nx + 1) + i); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        m.nodes.emplace_back(origin.x() + lx * i / nx, origin.y() + ly * j / ny, origin.z() + lz * k / nz);
  RawPhysicalGroup3 dom;
  dom.name = "domain";
  dom.dim = 3;
  dom.tag = 1;
  // Kuhn's six tetrahedra: from corner 000 to 111 by unit steps along the axes in each order.
  constexpr int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& order : kOrders) {
          std::array<Index, 4> t;
          int c[3] = {i, j, k};
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[order[s]];
            t[static_cast<std::size_t>(s) + 1] = id(c[0], c[1], c[2]);
          }
          const Vec3 a = m.nodes[t[1]] - m.nodes[t[0]], b = m.nodes[t[2]] - m.nodes[t[0]],
                     d = m.nodes[t[3]] - m.nodes[t[0]];
          if (a.dot(b.cross(d)) < 0.0) std::swap(t[1], t[2]);
          dom.tetrahedra.push_back(static_cast<Index>(m.tetrahedra.size()));
          m.tetrahedra.push_back(t);
        }
  m.tetrahedron_volume_group.assign(m.tetrahedra.size(), 0);
  m.groups.push_back(std::move(dom));
  // The six faces: each cell face split along its diagonal from its lowest corner, as the
  // cells' tetrahedra split it.
  const char* names[3][2] = {{"xmin", "xmax"}, {"ymin", "ymax"}, {"zmin", "zmax"}};
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      RawPhysicalGroup3 g;
      g.name = names[axis][side];
      g.dim = 2;
      g.tag = 2 + 2 * axis + side;
      const int p = (axis + 1) % 3, q = (axis + 2) % 3;
      for (int b = 0; b < n[q]; ++b)
        for (int a = 0; a < n[p]; ++a) {
          auto node = [&](int da, int db) {
            int c[3];
            c[axis] = side ? n[axis] : 0;
            c[p] = a + da;
            c[q] = b + db;
            return id(c[0], c[1], c[2]);
          };
          g.faces.push_back({node(0, 0), node(1, 0), node(1, 1)});
          g.faces.push_back({node(0, 0), node(1, 1), node(0, 1)});
          for (const Index v : {node(0, 0), node(1, 0), node(1, 1), node(0, 1)}) g.nodes.push_back(v);
        }
      std::sort(g.nodes.begin(), g.nodes.end());
      g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
      m.groups.push_back(std::move(g));
    }
  return m;
}

}  // namespace dsdem::mesh
