#include "boundary/boundary_setup.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace dsdem::boundary {

std::vector<BoundaryNode> build_viscous_boundary(const Model& model, const std::vector<io::BoundarySpec>& boundaries) {
  std::vector<BoundaryNode> out;
  const Nodes& nodes = model.nodes;
  // Mesh node -> model node (boundaries lie on continuous zones: one copy per mesh node).
  Index max_origin = 0;
  for (Index o : nodes.origin) max_origin = std::max(max_origin, o);
  std::vector<Index> copy(static_cast<std::size_t>(max_origin) + 1, kNoIndex);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes.origin[i] >= 0 && copy[nodes.origin[i]] == kNoIndex) copy[nodes.origin[i]] = static_cast<Index>(i);
  // Node -> triangles, to find the triangle behind each boundary edge.
  std::vector<std::vector<Index>> node_triangles(nodes.size());
  for (std::size_t t = 0; t < model.triangles.size(); ++t)
    for (Index n : model.triangles.conn[t]) node_triangles[n].push_back(static_cast<Index>(t));
  double y_base = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes.m[i] > 0) y_base = std::min(y_base, nodes.X[i].y());
  // Free surface above x: highest node within half an element of x (reference state).
  auto surface_above = [&](double x, double tol) {
    double top = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (nodes.m[i] > 0 && std::abs(nodes.X[i].x() - x) <= tol) top = std::max(top, nodes.X[i].y());
    return top;
  };

  std::map<Index, std::size_t> index_of;  // model node -> entry in out
  std::map<Index, const io::BoundarySpec*> spec_of;  // the first boundary that named the node
  for (const auto& b : boundaries) {
    if (b.type != io::BoundaryType::ViscousSpring) continue;
    const Index g = model.find_group(b.group);
    if (g == kNoIndex || model.groups[g].kind != GroupKind::Curve || model.groups[g].mesh_edges.empty())
      throw io::ScenarioError({b.where.describe(fmt::format("'{}' must be a curve group for a viscous_spring boundary", b.group))});
    for (const auto& e : model.groups[g].mesh_edges) {
      const Index a = copy[e[0]], c = copy[e[1]];
      // The triangle holding this edge, and its material.
      Index tri = kNoIndex;
      for (Index t : node_triangles[a])
        if (std::find(model.triangles.conn[t].begin(), model.triangles.conn[t].end(), c) != model.triangles.conn[t].end()) tri = t;
      if (tri == kNoIndex)
        throw io::ScenarioError({b.where.describe(fmt::format("curve '{}' does not run along the model's outline", b.group))});
      const auto& conn = model.triangles.conn[tri];
      Index third = conn[0];
      for (Index n : conn)
        if (n != a && n != c) third = n;
      const Vec2 xa = nodes.X[a], xc = nodes.X[c];
      const double length = (xc - xa).norm();
      Vec2 normal(xc.y() - xa.y(), xa.x() - xc.x());
      normal /= normal.norm();
      if (normal.dot(nodes.X[third] - xa) > 0) normal = -normal;  // point away from the triangle
      const ElasticMedium medium = medium_from_material(model.materials[model.triangles.material[tri]]);
      for (Index n : {a, c}) {
        auto [it, fresh] = index_of.try_emplace(n, out.size());
        if (fresh) {
          spec_of[n] = &b;
          BoundaryNode bn;
          bn.node = n;
          bn.medium = medium;
          bn.free_field = b.free_field;
          out.push_back(bn);
        }
        BoundaryNode& bn = out[it->second];
        bn.area += 0.5 * length * model.thickness;
        bn.normal += 0.5 * length * normal;  // length-weighted average of the adjacent edges
      }
    }
  }
  // Coefficients once every group has contributed: a corner node shared by two curves
  // gets both tributary lengths and the averaged normal.
  for (auto& bn : out) {
    bn.normal.normalize();
    const io::BoundarySpec& b = *spec_of[bn.node];
    const double R = b.R ? *b.R : scattering_distance(nodes.X[bn.node], *b.scattering_centre);
    bn.coef = viscous_spring_coefficients(bn.area, bn.medium, R);
  }
  // Free-field column of each node: from the base to the free surface above it. Side
  // nodes use the column at their own x; base nodes the column above them.
  double h_mean = 0.0;
  for (double a : model.triangles.area0) h_mean += std::sqrt(2.0 * a);
  h_mean /= std::max<std::size_t>(1, model.triangles.size());
  for (auto& bn : out) {
    const Vec2 X = nodes.X[bn.node];
    bn.y = X.y() - y_base;
    bn.H = surface_above(X.x(), 0.5 * h_mean) - y_base;
    bn.y = std::clamp(bn.y, 0.0, bn.H);
  }
  return out;
}

}  // namespace dsdem::boundary
