#include "mesh/joint_insertion.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>

namespace dsdem {
namespace {

[[noreturn]] void fail(const RawMesh& mesh, const std::string& what) {
  throw std::runtime_error((mesh.source.empty() ? std::string("mesh") : mesh.source) +
                           ": joint insertion: " + what);
}

struct EdgeRef {
  Index lo, hi;  // mesh nodes, lo < hi
  Index tri;
  int local;  // edge local -> local+1 (mod 3) of tri, counter-clockwise
  bool operator<(const EdgeRef& o) const {
    return std::tie(lo, hi, tri, local) < std::tie(o.lo, o.hi, o.tri, o.local);
  }
};

struct CurveEdge {
  Index lo, hi, group;
  bool operator<(const CurveEdge& o) const {
    return std::tie(lo, hi, group) < std::tie(o.lo, o.hi, o.group);
  }
};

Index group_of(const RawMesh& mesh, Index t) {
  return mesh.triangle_surface_group.empty() ? kNoIndex : mesh.triangle_surface_group[t];
}

void check_options(const RawMesh& mesh, const JointInsertionOptions& opt) {
  const Index n_tri = static_cast<Index>(mesh.triangles.size());
  const Index n_groups = static_cast<Index>(mesh.groups.size());
  if (!opt.breakable.empty() && static_cast<Index>(opt.breakable.size()) != n_groups)
    fail(mesh, "breakable flags: " + std::to_string(opt.breakable.size()) + " for " +
                   std::to_string(n_groups) + " groups");
  if (!opt.group_property.empty() && static_cast<Index>(opt.group_property.size()) != n_groups)
    fail(mesh, "group_property: " + std::to_string(opt.group_property.size()) + " for " +
                   std::to_string(n_groups) + " groups");
  if (!mesh.triangle_surface_group.empty() &&
      static_cast<Index>(mesh.triangle_surface_group.size()) != n_tri)
    fail(mesh, "triangle_surface_group has the wrong size");
  auto check_curve = [&](Index g, const char* what) {
    if (g < 0 || g >= n_groups || mesh.groups[g].dim != 1)
      fail(mesh, std::string(what) + ": group index " + std::to_string(g) +
                     " is not a curve group");
  };
  for (const auto& [g, prop] : opt.curve_property) {
    check_curve(g, "curve_property");
    if (prop < 0) fail(mesh, "curve_property of '" + mesh.groups[g].name + "' is negative");
  }
  for (Index g : opt.broken_curves) check_curve(g, "broken_curves");
}

// Per triangle: 1 if breakable; checks that it is valid and counter-clockwise.
std::vector<char> breakable_triangles(const RawMesh& mesh, const JointInsertionOptions& opt) {
  const Index n_nodes = static_cast<Index>(mesh.nodes.size());
  const Index n_tri = static_cast<Index>(mesh.triangles.size());
  const Index n_groups = static_cast<Index>(mesh.groups.size());
  auto breakable_group = [&](Index g) {
    return g != kNoIndex && !opt.breakable.empty() && g >= 0 && g < n_groups && opt.breakable[g];
  };
  std::vector<char> brk(n_tri);
  for (Index t = 0; t < n_tri; ++t) {
    const auto& c = mesh.triangles[t];
    for (Index v : c)
      if (v < 0 || v >= n_nodes)
        fail(mesh, "triangle " + std::to_string(t) + " references missing node " +
                       std::to_string(v));
    const Vec2 e1 = mesh.nodes[c[1]] - mesh.nodes[c[0]];
    const Vec2 e2 = mesh.nodes[c[2]] - mesh.nodes[c[0]];
    if (!(e1.x() * e2.y() - e1.y() * e2.x() > 0.0))
      fail(mesh, "triangle " + std::to_string(t) + " is not counter-clockwise (area <= 0)");
    brk[t] = breakable_group(group_of(mesh, t)) ? 1 : 0;
  }
  return brk;
}

// New nodes: per mesh node, the shared continuous copy, then one per breakable triangle
// (out.nodes, origin, copies, triangles).
void split_nodes(const RawMesh& mesh, const std::vector<char>& brk, JointInsertionResult& out) {
  const Index n_nodes = static_cast<Index>(mesh.nodes.size());
  const Index n_tri = static_cast<Index>(mesh.triangles.size());
  // Node -> incident triangles (CSR, triangles ascending).
  std::vector<Index> inc_off(n_nodes + 1, 0), inc;
  for (const auto& c : mesh.triangles)
    for (Index v : c) ++inc_off[v + 1];
  for (Index v = 0; v < n_nodes; ++v) inc_off[v + 1] += inc_off[v];
  inc.resize(inc_off[n_nodes]);
  {
    std::vector<Index> fill(inc_off.begin(), inc_off.end() - 1);
    for (Index t = 0; t < n_tri; ++t)
      for (Index v : mesh.triangles[t]) inc[fill[v]++] = t;
  }

  out.triangles.assign(n_tri, {kNoIndex, kNoIndex, kNoIndex});
  out.copies_offset.assign(n_nodes + 1, 0);
  auto add_node = [&](Index v) {
    out.nodes.push_back(mesh.nodes[v]);
    out.origin.push_back(v);
    out.copies.push_back(static_cast<Index>(out.nodes.size()) - 1);
    return static_cast<Index>(out.nodes.size()) - 1;
  };
  auto local_of = [&](Index t, Index v) {
    const auto& c = mesh.triangles[t];
    return c[0] == v ? 0 : (c[1] == v ? 1 : 2);
  };
  for (Index v = 0; v < n_nodes; ++v) {
    Index shared = kNoIndex;
    for (Index k = inc_off[v]; k < inc_off[v + 1]; ++k) {
      const Index t = inc[k];
      if (brk[t]) continue;
      if (shared == kNoIndex) shared = add_node(v);
      out.triangles[t][local_of(t, v)] = shared;
    }
    for (Index k = inc_off[v]; k < inc_off[v + 1]; ++k) {
      const Index t = inc[k];
      if (brk[t]) out.triangles[t][local_of(t, v)] = add_node(v);
    }
    out.copies_offset[v + 1] = static_cast<Index>(out.copies.size());
  }
}

// Edges of all triangles, sorted so that the two sides of an edge are adjacent.
std::vector<EdgeRef> sorted_edges(const RawMesh& mesh) {
  const Index n_tri = static_cast<Index>(mesh.triangles.size());
  std::vector<EdgeRef> edges;
  edges.reserve(3 * static_cast<std::size_t>(n_tri));
  for (Index t = 0; t < n_tri; ++t)
    for (int k = 0; k < 3; ++k) {
      const Index p = mesh.triangles[t][k], q = mesh.triangles[t][(k + 1) % 3];
      edges.push_back({std::min(p, q), std::max(p, q), t, k});
    }
  std::sort(edges.begin(), edges.end());
  return edges;
}

std::vector<CurveEdge> sorted_curve_edges(const RawMesh& mesh) {
  const Index n_groups = static_cast<Index>(mesh.groups.size());
  std::vector<CurveEdge> curve_edges;
  for (Index g = 0; g < n_groups; ++g) {
    if (mesh.groups[g].dim != 1) continue;
    for (const auto& e : mesh.groups[g].edges)
      curve_edges.push_back({std::min(e[0], e[1]), std::max(e[0], e[1]), g});
  }
  std::sort(curve_edges.begin(), curve_edges.end());
  return curve_edges;
}

// What a joint between triangles ta < tb takes from its groups and from the named
// curves [lo_it, hi_it) through its edge (rules in joint_insertion.hpp).
struct JointTags {
  Index prop = kNoIndex, curve = kNoIndex;
  bool start_broken = false;
};

JointTags tag_joint(const RawMesh& mesh, const JointInsertionOptions& opt, const std::vector<char>& brk, Index ta,
                    Index tb, std::vector<CurveEdge>::const_iterator lo_it,
                    std::vector<CurveEdge>::const_iterator hi_it) {
  auto side_property = [&](Index g) {
    const Index p = opt.group_property.empty() ? kNoIndex : opt.group_property[g];
    return p == kNoIndex ? opt.default_property : p;
  };
  const Index ga = group_of(mesh, ta), gb = group_of(mesh, tb);
  Index prop;
  if (ga == gb) {
    prop = side_property(ga);
  } else if (opt.interface_property != kNoIndex) {
    prop = opt.interface_property;
  } else {
    Index g = brk[ta] ? ga : gb;
    if (brk[ta] && brk[tb]) g = std::min(ga, gb);
    prop = side_property(g);
  }
  Index curve = kNoIndex, curve_any = kNoIndex;
  bool prop_set = false, start_broken = false;
  for (auto it = lo_it; it != hi_it; ++it) {  // ascending group index
    const Index g = it->group;
    if (curve_any == kNoIndex) curve_any = g;
    const auto cp = opt.curve_property.find(g);
    const bool broken = opt.broken_curves.count(g) > 0;
    if (cp != opt.curve_property.end() && !prop_set) {
      prop = cp->second;
      prop_set = true;
    }
    if ((cp != opt.curve_property.end() || broken) && curve == kNoIndex) curve = g;
    start_broken = start_broken || broken;
  }
  return {prop, curve != kNoIndex ? curve : curve_any, start_broken};
}

}  // namespace

JointInsertionResult insert_joints(const RawMesh& mesh, const JointInsertionOptions& opt) {
  check_options(mesh, opt);
  const std::vector<char> brk = breakable_triangles(mesh, opt);
  JointInsertionResult out;
  split_nodes(mesh, brk, out);
  const std::vector<EdgeRef> edges = sorted_edges(mesh);
  const std::vector<CurveEdge> curve_edges = sorted_curve_edges(mesh);

  Joints& J = out.joints;
  // At most one joint per two edge sides: reserved, so the ten arrays do not grow by
  // doubling (peak memory of large models).
  J.reserve(edges.size() / 2);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t e = i + 1;
    while (e < edges.size() && edges[e].lo == edges[i].lo && edges[e].hi == edges[i].hi) ++e;
    const std::size_t count = e - i;
    const EdgeRef first = edges[i];
    i = e;
    if (count == 1) continue;  // boundary edge
    if (count > 2)
      fail(mesh, "edge (" + std::to_string(first.lo) + ", " + std::to_string(first.hi) +
                     ") is shared by " + std::to_string(count) + " triangles");
    const EdgeRef& ea = edges[e - 2];  // lower triangle index: tri_a
    const EdgeRef& eb = edges[e - 1];
    const Index p = mesh.triangles[ea.tri][ea.local];
    const Index q = mesh.triangles[ea.tri][(ea.local + 1) % 3];
    if (mesh.triangles[eb.tri][eb.local] != q)
      fail(mesh, "triangles " + std::to_string(ea.tri) + " and " + std::to_string(eb.tri) +
                     " run along their shared edge in the same direction");

    // Named curves through this edge.
    auto lo_it = std::lower_bound(curve_edges.begin(), curve_edges.end(),
                                  CurveEdge{first.lo, first.hi, -1});
    auto hi_it = lo_it;
    while (hi_it != curve_edges.end() && hi_it->lo == first.lo && hi_it->hi == first.hi) ++hi_it;
    if (!brk[ea.tri] && !brk[eb.tri]) {
      if (lo_it != hi_it) out.curve_edges_without_joint.push_back({first.lo, first.hi});
      continue;
    }
    const JointTags tags = tag_joint(mesh, opt, brk, ea.tri, eb.tri, lo_it, hi_it);

    const std::size_t j = J.size();
    J.resize(j + 1);
    J.nodes[j] = {out.triangles[ea.tri][ea.local], out.triangles[ea.tri][(ea.local + 1) % 3],
                  out.triangles[eb.tri][(eb.local + 1) % 3], out.triangles[eb.tri][eb.local]};
    J.tri_a[j] = ea.tri;
    J.tri_b[j] = eb.tri;
    J.property[j] = tags.prop;
    J.curve_group[j] = tags.curve;
    J.length0[j] = (mesh.nodes[q] - mesh.nodes[p]).norm();
    if (tags.start_broken) J.set_initially_broken(j, mesh.nodes[p], mesh.nodes[q]);
  }
  return out;
}

}  // namespace dsdem
