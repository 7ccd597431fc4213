#include "mesh/triangle_order.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace dsdem::mesh {

std::uint64_t hilbert_index(std::uint32_t x, std::uint32_t y, int order) {
  // Quadrant by quadrant from the coarsest: add the quadrant's offset, then rotate and
  // reflect the remaining coordinates into that quadrant's orientation of the curve.
  std::uint64_t d = 0;
  for (std::uint32_t s = std::uint32_t{1} << (order - 1); s > 0; s >>= 1) {
    const std::uint32_t rx = (x & s) ? 1u : 0u;
    const std::uint32_t ry = (y & s) ? 1u : 0u;
    d += static_cast<std::uint64_t>(s) * s * ((3u * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = s - 1 - (x & (s - 1));
        y = s - 1 - (y & (s - 1));
      }
      std::swap(x, y);
    }
    x &= s - 1;
    y &= s - 1;
  }
  return d;
}

std::vector<Index> spatial_triangle_order(std::span<const Vec2> nodes, std::span<const std::array<Index, 3>> triangles) {
  std::vector<Index> order(triangles.size());
  std::iota(order.begin(), order.end(), Index{0});
  if (triangles.size() < 2 || nodes.empty()) return order;
  Vec2 lo = nodes[0], hi = nodes[0];
  for (const Vec2& p : nodes) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  if (!(extent > 0.0) || !std::isfinite(extent)) return order;
  constexpr int kOrder = 16;
  constexpr double kCells = double(1u << kOrder);
  // A coordinate's cell; a centroid that is not a number (never from a mesh the reader
  // accepts) goes to cell 0 rather than into an undefined conversion.
  const auto cell = [&](double v) {
    const double c = v / extent * kCells;
    return c >= kCells - 1.0 ? static_cast<std::uint32_t>(kCells - 1.0) : c > 0.0 ? static_cast<std::uint32_t>(c) : 0u;
  };
  std::vector<std::uint64_t> key(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& c = triangles[t];
    const Vec2 centroid = (nodes[static_cast<std::size_t>(c[0])] + nodes[static_cast<std::size_t>(c[1])] +
                           nodes[static_cast<std::size_t>(c[2])]) / 3.0;
    key[t] = hilbert_index(cell(centroid.x() - lo.x()), cell(centroid.y() - lo.y()), kOrder);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](Index a, Index b) { return key[static_cast<std::size_t>(a)] < key[static_cast<std::size_t>(b)]; });
  return order;
}

void apply_triangle_order(RawMesh& mesh, std::span<const Index> order) {
  const std::size_t n = mesh.triangles.size();
  if (order.size() != n)
    throw std::invalid_argument("apply_triangle_order: " + std::to_string(order.size()) + " entries for " +
                                std::to_string(n) + " triangles");
  std::vector<Index> new_id(n, kNoIndex);
  for (std::size_t k = 0; k < n; ++k) {
    const Index old = order[k];
    if (old < 0 || static_cast<std::size_t>(old) >= n || new_id[static_cast<std::size_t>(old)] != kNoIndex)
      throw std::invalid_argument("apply_triangle_order: the order is not a permutation of the triangles");
    new_id[static_cast<std::size_t>(old)] = static_cast<Index>(k);
  }
  std::vector<std::array<Index, 3>> triangles(n);
  std::vector<Index> surface_group(n);
  for (std::size_t k = 0; k < n; ++k) {
    triangles[k] = mesh.triangles[static_cast<std::size_t>(order[k])];
    surface_group[k] = mesh.triangle_surface_group[static_cast<std::size_t>(order[k])];
  }
  mesh.triangles = std::move(triangles);
  mesh.triangle_surface_group = std::move(surface_group);
  for (auto& g : mesh.groups) {
    for (Index& t : g.triangles) t = new_id[static_cast<std::size_t>(t)];
    std::sort(g.triangles.begin(), g.triangles.end());
  }
}

}  // namespace dsdem::mesh
