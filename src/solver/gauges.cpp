#include "solver/gauges.hpp"

#include <algorithm>
#include <limits>

namespace dsdem::solver {

namespace {
std::array<double, 3> barycentric(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  const double l1 = ((p - a).x() * (c - a).y() - (p - a).y() * (c - a).x()) / det;
  const double l2 = ((b - a).x() * (p - a).y() - (b - a).y() * (p - a).x()) / det;
  return {1.0 - l1 - l2, l1, l2};
}
}  // namespace

std::optional<Gauge> locate_gauge(const Model& model, const std::string& name, const Vec2& p, double tolerance) {
  Gauge best;
  best.name = name;
  best.at = p;
  double best_outside = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    const auto& c = model.triangles.conn[t];
    const Vec2 &a = model.nodes.X[c[0]], &b = model.nodes.X[c[1]], &d = model.nodes.X[c[2]];
    const auto w = barycentric(p, a, b, d);
    const double outside = -std::min({w[0], w[1], w[2]});  // <= 0 inside
    if (outside < best_outside) {
      best_outside = outside;
      best.triangle = static_cast<Index>(t);
      best.weights = w;
    }
    if (outside <= 0.0) break;
  }
  if (best.triangle == kNoIndex) return std::nullopt;
  if (best_outside > 0.0) {
    // Distance to the nearest triangle: clamp the weights and measure.
    const auto& c = model.triangles.conn[best.triangle];
    std::array<double, 3> w = best.weights;
    for (auto& x : w) x = std::max(0.0, x);
    const double s = w[0] + w[1] + w[2];
    for (auto& x : w) x /= s;
    const Vec2 q = w[0] * model.nodes.X[c[0]] + w[1] * model.nodes.X[c[1]] + w[2] * model.nodes.X[c[2]];
    if ((q - p).norm() > tolerance) return std::nullopt;
    best.weights = w;
  }
  return best;
}

Vec2 gauge_value(const Model& model, const Gauge& g, const std::vector<Vec2>& field) {
  const auto& c = model.triangles.conn[g.triangle];
  return g.weights[0] * field[c[0]] + g.weights[1] * field[c[1]] + g.weights[2] * field[c[2]];
}

std::optional<Gauge3> locate_gauge(const Model3& model, const std::string& name, const Vec3& p, double tolerance) {
  const auto& tet = model.tetrahedra;
  const auto& X = model.nodes.X;
  Gauge3 best;
  best.name = name;
  best.at = p;
  double best_outside = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < tet.size(); ++t) {
    // The reference edge matrix's inverse maps p - X0 to the weights of corners 1-3.
    const Vec3 l = tet.Dm_inv[t] * (p - X[tet.conn[t][0]]);
    const std::array<double, 4> w{1.0 - l.sum(), l.x(), l.y(), l.z()};
    const double outside = -std::min({w[0], w[1], w[2], w[3]});  // <= 0 inside
    if (outside < best_outside) {
      best_outside = outside;
      best.tetrahedron = static_cast<Index>(t);
      best.weights = w;
    }
    if (outside <= 0.0) break;
  }
  if (best.tetrahedron == kNoIndex) return std::nullopt;
  if (best_outside > 0.0) {
    // Distance to the nearest tetrahedron: clamp the weights and measure.
    const auto& c = tet.conn[static_cast<std::size_t>(best.tetrahedron)];
    std::array<double, 4> w = best.weights;
    for (auto& x : w) x = std::max(0.0, x);
    const double s = w[0] + w[1] + w[2] + w[3];
    for (auto& x : w) x /= s;
    const Vec3 q = w[0] * X[c[0]] + w[1] * X[c[1]] + w[2] * X[c[2]] + w[3] * X[c[3]];
    if ((q - p).norm() > tolerance) return std::nullopt;
    best.weights = w;
  }
  return best;
}

Vec3 gauge_value(const Model3& model, const Gauge3& g, const std::vector<Vec3>& field) {
  const auto& c = model.tetrahedra.conn[static_cast<std::size_t>(g.tetrahedron)];
  return g.weights[0] * field[c[0]] + g.weights[1] * field[c[1]] + g.weights[2] * field[c[2]] +
         g.weights[3] * field[c[3]];
}

}  // namespace dsdem::solver
