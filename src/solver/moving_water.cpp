#include "solver/moving_water.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>

namespace dsdem::solver {

std::vector<sph::SolidEdge> exposed_edges(const Model& m, std::span<const Index> triangles) {
  const auto& tri = m.triangles;
  auto key = [](Index a, Index b) {
    const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
    return (lo << 32) | hi;
  };
  std::unordered_map<std::uint64_t, int> count;
  count.reserve(3 * tri.size());
  for (const auto& c : tri.conn)
    for (int k = 0; k < 3; ++k) ++count[key(c[k], c[(k + 1) % 3])];
  // A joint glues edge jn0 -> jn1 of tri_a to jn3 -> jn2 of tri_b.
  std::unordered_set<std::uint64_t> glued;
  const auto& J = m.joints;
  for (std::size_t j = 0; j < J.size(); ++j) {
    if (J.broken[j]) continue;
    const auto& jn = J.nodes[j];
    glued.insert(key(jn[0], jn[1]));
    glued.insert(key(jn[2], jn[3]));
  }
  std::vector<sph::SolidEdge> edges;
  for (Index t : triangles) {
    const auto& c = tri.conn[t];
    for (int k = 0; k < 3; ++k) {
      const Index a = c[k], b = c[(k + 1) % 3];
      if (count[key(a, b)] == 1 && !glued.count(key(a, b))) edges.push_back({a, b});
    }
  }
  return edges;
}

}  // namespace dsdem::solver
