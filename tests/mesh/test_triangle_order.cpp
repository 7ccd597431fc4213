#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <vector>

#include "mesh/triangle_order.hpp"

using dsdem::Index;
using dsdem::RawMesh;
using dsdem::Vec2;
using dsdem::mesh::apply_triangle_order;
using dsdem::mesh::hilbert_index;
using dsdem::mesh::spatial_triangle_order;

TEST(TriangleOrder, HilbertIndexVisitsEveryCellOnceInUnitSteps) {
  for (const int order : {1, 2, 3, 5}) {
    const std::uint32_t n = 1u << order;
    std::vector<std::array<std::uint32_t, 2>> cell_at(std::size_t(n) * n, {n, n});
    for (std::uint32_t x = 0; x < n; ++x)
      for (std::uint32_t y = 0; y < n; ++y) {
        const std::uint64_t d = hilbert_index(x, y, order);
        ASSERT_LT(d, std::uint64_t(n) * n) << x << "," << y;
        ASSERT_EQ(cell_at[d][0], n) << "distance " << d << " given twice";
        cell_at[d] = {x, y};
      }
    // Consecutive distances are edge neighbours: the curve never jumps.
    for (std::size_t d = 1; d < cell_at.size(); ++d) {
      const int dx = std::abs(int(cell_at[d][0]) - int(cell_at[d - 1][0]));
      const int dy = std::abs(int(cell_at[d][1]) - int(cell_at[d - 1][1]));
      EXPECT_EQ(dx + dy, 1) << "order " << order << ", distance " << d;
    }
    // It starts at the origin corner and ends at the other bottom corner.
    EXPECT_EQ(cell_at.front(), (std::array<std::uint32_t, 2>{0, 0}));
    EXPECT_EQ(cell_at.back(), (std::array<std::uint32_t, 2>{n - 1, 0}));
  }
  // The grid the ordering uses (2^16 cells a side): distances fit, and stay distinct.
  EXPECT_LT(hilbert_index(65535, 65535, 16), std::uint64_t(1) << 32);
  EXPECT_NE(hilbert_index(65535, 65535, 16), hilbert_index(65534, 65535, 16));
}

namespace {

// An n x n grid of unit squares, each cut in two triangles, numbered in a scrambled
// order (stride 7 through the list, coprime with 2 n^2 for n = 8), in two groups.
RawMesh scrambled_grid(int n) {
  RawMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.nodes.emplace_back(double(i), double(j));
  std::vector<std::array<Index, 3>> tris;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Index a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      tris.push_back({a, b, c});
      tris.push_back({a, c, d});
    }
  for (std::size_t k = 0; k < tris.size(); ++k) m.triangles.push_back(tris[(k * 7) % tris.size()]);
  m.triangle_surface_group.resize(m.triangles.size());
  m.groups.resize(2);
  m.groups[0].name = "left";
  m.groups[1].name = "right";
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const bool right = m.nodes[static_cast<std::size_t>(m.triangles[t][0])].x() >= n / 2;
    m.triangle_surface_group[t] = right ? 1 : 0;
    m.groups[right ? 1 : 0].triangles.push_back(static_cast<Index>(t));
  }
  return m;
}

// The unit square holding triangle t's centroid.
std::array<int, 2> square_of(const RawMesh& m, std::size_t t) {
  const auto& c = m.triangles[t];
  const Vec2 g = (m.nodes[c[0]] + m.nodes[c[1]] + m.nodes[c[2]]) / 3.0;
  return {int(g.x()), int(g.y())};
}

// The largest step, in squares (|di| + |dj|), between consecutive triangles.
int largest_step(const RawMesh& m) {
  int step = 0;
  for (std::size_t t = 1; t < m.triangles.size(); ++t) {
    const auto a = square_of(m, t - 1), b = square_of(m, t);
    step = std::max(step, std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]));
  }
  return step;
}

}  // namespace

TEST(TriangleOrder, NeighboursInSpaceBecomeNeighboursInNumber) {
  RawMesh m = scrambled_grid(8);
  const RawMesh before = m;
  const std::vector<Index> order = spatial_triangle_order(m.nodes, m.triangles);
  apply_triangle_order(m, order);
  // The 8 x 8 squares are blocks of the 2^16 grid, so the curve walks them square by
  // square: consecutive triangles share a square or an edge of one.
  EXPECT_GT(largest_step(before), 3);
  EXPECT_EQ(largest_step(m), 1);
  // Same triangles, each with its group; the groups list the new numbers, sorted.
  for (std::size_t k = 0; k < m.triangles.size(); ++k) {
    EXPECT_EQ(m.triangles[k], before.triangles[static_cast<std::size_t>(order[k])]);
    EXPECT_EQ(m.triangle_surface_group[k], before.triangle_surface_group[static_cast<std::size_t>(order[k])]);
  }
  std::size_t listed = 0;
  for (std::size_t g = 0; g < m.groups.size(); ++g) {
    EXPECT_TRUE(std::is_sorted(m.groups[g].triangles.begin(), m.groups[g].triangles.end()));
    for (const Index t : m.groups[g].triangles) EXPECT_EQ(m.triangle_surface_group[static_cast<std::size_t>(t)], Index(g));
    listed += m.groups[g].triangles.size();
  }
  EXPECT_EQ(listed, m.triangles.size());
  // Deterministic: the same mesh gives the same order.
  EXPECT_EQ(spatial_triangle_order(before.nodes, before.triangles), order);
}

TEST(TriangleOrder, DegenerateInputsKeepTheFileOrder) {
  const std::vector<Vec2> point(3, Vec2(2.0, 2.0));
  const std::vector<std::array<Index, 3>> two{{0, 1, 2}, {2, 1, 0}};
  EXPECT_EQ(spatial_triangle_order(point, two), (std::vector<Index>{0, 1}));
  EXPECT_TRUE(spatial_triangle_order({}, {}).empty());
  // Triangles sharing one cell keep their order (stable).
  const std::vector<Vec2> nodes{{0, 0}, {1, 0}, {0, 1}, {100, 100}};
  const std::vector<std::array<Index, 3>> same{{0, 1, 2}, {1, 2, 0}, {2, 0, 1}};
  EXPECT_EQ(spatial_triangle_order(nodes, same), (std::vector<Index>{0, 1, 2}));
}

TEST(TriangleOrder, ANodeThatIsNotANumberStillGivesAPermutation) {
  // The reader refuses such meshes; the ordering must not convert NaN to an integer anyway.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Vec2> nodes{{0, 0}, {1, 0}, {0, 1}, {nan, 0.5}, {4, 4}};
  const std::vector<std::array<Index, 3>> tris{{0, 1, 2}, {1, 3, 2}, {1, 4, 2}};
  std::vector<Index> order = spatial_triangle_order(nodes, tris);
  std::sort(order.begin(), order.end());
  EXPECT_EQ(order, (std::vector<Index>{0, 1, 2}));
}

TEST(TriangleOrder, AnOrderThatIsNotAPermutationIsRefused) {
  RawMesh m = scrambled_grid(2);
  EXPECT_THROW(apply_triangle_order(m, std::vector<Index>{0, 1}), std::invalid_argument);
  std::vector<Index> twice(m.triangles.size(), 0);
  EXPECT_THROW(apply_triangle_order(m, twice), std::invalid_argument);
  std::vector<Index> out_of_range(m.triangles.size());
  for (std::size_t k = 0; k < out_of_range.size(); ++k) out_of_range[k] = Index(k + 1);
  EXPECT_THROW(apply_triangle_order(m, out_of_range), std::invalid_argument);
}
