#include "solver/water_loads.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

namespace dsdem::solver {

void WaterLoads::set(const Model& m, WaterSetup w) {
  if (exposed_.size() != m.triangles.size()) build_edges(m);
  crack_level_.assign(m.groups.size(), kNoLevel);
  for (const auto& [g, level] : w.crack_levels) {
    if (g < 0 || static_cast<std::size_t>(g) >= m.groups.size())
      throw std::invalid_argument(fmt::format("water: crack level for group {} of {}", g, m.groups.size()));
    crack_level_[g] = level;
  }
  setup_ = std::move(w);
  unit_weight_ = setup_.unit_weight();
  has_water_ = true;
  active_ = true;
}

void WaterLoads::clear() {
  has_water_ = false;
  // Forces of the last step still do the first half of their work in the next one.
  active_ = std::any_of(previous_.begin(), previous_.end(), [](const std::array<Vec2, 3>& f) {
    return !f[0].isZero(0.0) || !f[1].isZero(0.0) || !f[2].isZero(0.0);
  });
}

void WaterLoads::build_edges(const Model& m) {
  const auto& tri = m.triangles;
  const std::size_t nt = tri.size();
  exposed_.assign(nt, 0);
  edge_joint_.assign(nt, {kNoIndex, kNoIndex, kNoIndex});
  previous_.assign(nt, {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()});
  work_.assign(nt, 0.0);
  // An edge is exposed when no other triangle has its two nodes (set-up only).
  auto key = [](Index a, Index b) {
    const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
    return (lo << 32) | hi;
  };
  std::unordered_map<std::uint64_t, int> count;
  count.reserve(3 * nt);
  for (const auto& c : tri.conn)
    for (int k = 0; k < 3; ++k) ++count[key(c[k], c[(k + 1) % 3])];
  for (std::size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      if (count[key(tri.conn[t][k], tri.conn[t][(k + 1) % 3])] == 1) exposed_[t] |= static_cast<std::uint8_t>(1u << k);
  // Joint j glues edge a0 -> a1 of tri_a (counter-clockwise along it) to b1 -> b0 of tri_b.
  const auto& J = m.joints;
  auto mark = [&](Index t, Index from, Index to, Index j) {
    const auto& c = tri.conn[t];
    for (int k = 0; k < 3; ++k)
      if (c[k] == from && c[(k + 1) % 3] == to) edge_joint_[t][k] = j;
  };
  for (std::size_t j = 0; j < J.size(); ++j) {
    const auto& jn = J.nodes[j];
    mark(J.tri_a[j], jn[0], jn[1], static_cast<Index>(j));
    mark(J.tri_b[j], jn[3], jn[2], static_cast<Index>(j));
  }
}

}  // namespace dsdem::solver
