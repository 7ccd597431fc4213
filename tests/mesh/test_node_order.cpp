#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <vector>

#include "mesh/node_order.hpp"

using dsdem::Index;
using dsdem::mesh::node_order_by_first_use;

TEST(NodeOrder, NodesFollowTheirFirstTriangleAndUnusedNodesGoLast) {
  // Gmsh-like numbering: corners 0-3 first, the interior node 7 last; 5 is used by no triangle.
  const std::vector<std::array<Index, 3>> conn{{7, 0, 1}, {7, 1, 2}, {6, 4, 2}, {3, 6, 7}};
  const std::vector<Index> new_id = node_order_by_first_use(conn, 8);
  // First use: 7, 0, 1 | 2 | 6, 4 | 3; then the unused 5.
  EXPECT_EQ(new_id, (std::vector<Index>{1, 2, 3, 6, 5, 7, 4, 0}));
  // A permutation of 0..7.
  std::vector<Index> sorted = new_id;
  std::sort(sorted.begin(), sorted.end());
  for (Index i = 0; i < 8; ++i) EXPECT_EQ(sorted[static_cast<std::size_t>(i)], i);
  // Renumbered, the triangles use 0, 1, 2, ... in order of first appearance.
  std::vector<std::array<Index, 3>> renumbered = conn;
  Index next = 0;
  for (auto& c : renumbered) {
    dsdem::mesh::renumber(c, new_id);
    for (Index i : c)
      if (i >= next) EXPECT_EQ(i, next++);
  }
}

TEST(NodeOrder, AlreadyOrderedIsIdentityAndOutOfRangeThrows) {
  const std::vector<std::array<Index, 3>> conn{{0, 1, 2}, {2, 1, 3}};
  EXPECT_EQ(node_order_by_first_use(conn, 4), (std::vector<Index>{0, 1, 2, 3}));
  EXPECT_EQ(node_order_by_first_use({}, 3), (std::vector<Index>{0, 1, 2}));
  EXPECT_THROW(node_order_by_first_use(conn, 3), std::invalid_argument);
  const std::vector<std::array<Index, 3>> negative{{0, -1, 2}};
  EXPECT_THROW(node_order_by_first_use(negative, 3), std::invalid_argument);
}

TEST(NodeOrder, FingerprintChangesWithTheOrderOfTheSamePositions) {
  const std::vector<dsdem::Vec2> X{{0.0, 0.0}, {2.0, 0.0}, {2.0, 3.0}, {0.7, 1.2}};
  std::vector<dsdem::Vec2> swapped = X;
  std::swap(swapped[1], swapped[3]);
  const double a = dsdem::mesh::node_order_fingerprint(X);
  EXPECT_EQ(a, dsdem::mesh::node_order_fingerprint(X));  // deterministic
  EXPECT_NE(a, dsdem::mesh::node_order_fingerprint(swapped));
  std::vector<dsdem::Vec2> moved = X;
  moved[2].y() += 1e-3;
  EXPECT_NE(a, dsdem::mesh::node_order_fingerprint(moved));
}
