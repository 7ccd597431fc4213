#include "boundary/boundary_setup.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace dsdem::boundary {

SurfaceProfile::SurfaceProfile(const std::vector<Vec2>& X, const std::vector<std::array<Index, 3>>& conn) {
  if (conn.empty()) return;
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, length = 0.0;
  for (const auto& c : conn)
    for (int k = 0; k < 3; ++k) {
      const Vec2& a = X[c[k]];
      xmin = std::min(xmin, a.x());
      xmax = std::max(xmax, a.x());
      length += std::abs(X[c[(k + 1) % 3]].x() - a.x());
    }
  // Columns about as wide as an edge is long in x: a few edges per column.
  const double mean_dx = length / (3.0 * static_cast<double>(conn.size()));
  x0_ = xmin;
  columns_ = mean_dx > 0.0 ? std::clamp<std::size_t>(static_cast<std::size_t>((xmax - xmin) / mean_dx), 1, 3 * conn.size()) : 1;
  width_ = xmax > xmin ? (xmax - xmin) / static_cast<double>(columns_) : 1.0;
  std::vector<std::array<Vec2, 2>> all;
  all.reserve(3 * conn.size());
  for (const auto& c : conn)
    for (int k = 0; k < 3; ++k) {
      Vec2 a = X[c[k]], b = X[c[(k + 1) % 3]];
      if (b.x() < a.x()) std::swap(a, b);
      all.push_back({a, b});
    }
  offset_.assign(columns_ + 1, 0);
  for (const auto& e : all)
    for (std::size_t col = column(e[0].x()); col <= column(e[1].x()); ++col) ++offset_[col + 1];
  for (std::size_t col = 0; col < columns_; ++col) offset_[col + 1] += offset_[col];
  edges_.resize(offset_[columns_]);
  std::vector<std::size_t> fill(offset_.begin(), offset_.end() - 1);
  for (const auto& e : all)
    for (std::size_t col = column(e[0].x()); col <= column(e[1].x()); ++col) edges_[fill[col]++] = e;
}

std::size_t SurfaceProfile::column(double x) const {
  const double c = std::floor((x - x0_) / width_);
  return c <= 0.0 ? 0 : std::min(columns_ - 1, static_cast<std::size_t>(c));
}

double SurfaceProfile::top(double x) const {
  double top = -std::numeric_limits<double>::infinity();
  if (offset_.empty()) return top;
  const std::size_t col = column(x);
  for (std::size_t k = offset_[col]; k < offset_[col + 1]; ++k) {
    const Vec2& a = edges_[k][0];
    const Vec2& b = edges_[k][1];
    if (x < a.x() || x > b.x()) continue;
    const double y = b.x() > a.x() ? a.y() + (x - a.x()) * (b.y() - a.y()) / (b.x() - a.x()) : std::max(a.y(), b.y());
    top = std::max(top, y);
  }
  return top;
}

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
  // nodes use the column at their own x; base nodes the column above them. (The highest
  // node within half a mean element of x can miss the surface under a coarse, graded
  // mesh.)
  const SurfaceProfile surface(nodes.X, model.triangles.conn);
  for (auto& bn : out) {
    const Vec2 X = nodes.X[bn.node];
    bn.height = X.y() - y_base;
    bn.H = surface.top(X.x()) - y_base;
    bn.height = std::clamp(bn.height, 0.0, bn.H);
  }
  return out;
}

}  // namespace dsdem::boundary
