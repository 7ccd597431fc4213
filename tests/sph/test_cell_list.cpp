// The SPH cell list (docs/theory.md §11): every pair closer than the support is a candidate,
// exactly once, against brute force; the order within a cell is the index order.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "sph/cell_list.hpp"

using namespace dsdem::sph;

class SphCellListReach : public ::testing::TestWithParam<int> {};

TEST_P(SphCellListReach, FindsEveryNeighbourOnceAgainstBruteForce) {
  const int reach = GetParam();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(-0.3, 0.9), uy(0.1, 0.5);
  const std::size_t n = 1500;
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = ux(rng);
    y[i] = uy(rng);
  }
  // Points on cell borders too.
  x[0] = 0.0;
  y[0] = 0.1;
  x[1] = 0.04;
  y[1] = 0.14;
  x[2] = 0.02;
  y[2] = 0.12;
  const double support = 0.04;
  CellList cells;
  const double xmin = *std::min_element(x.begin(), x.end()), xmax = *std::max_element(x.begin(), x.end());
  const double ymin = *std::min_element(y.begin(), y.end()), ymax = *std::max_element(y.begin(), y.end());
  cells.build(grid_over(xmin, ymin, xmax, ymax, support / reach), x, y, reach);
  // The order is a permutation sorted by cell, ascending index within a cell.
  const auto order = cells.order();
  ASSERT_EQ(order.size(), n);
  for (std::size_t k = 1; k < n; ++k) {
    const auto a = static_cast<std::size_t>(order[k - 1]), b = static_cast<std::size_t>(order[k]);
    ASSERT_TRUE(cells.cell(a) < cells.cell(b) || (cells.cell(a) == cells.cell(b) && a < b));
  }
  std::size_t pairs = 0;
  std::vector<int> seen(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::fill(seen.begin(), seen.end(), 0);
    cells.for_each_range(cells.cell(i), [&](std::int32_t k0, std::int32_t k1) {
      for (std::int32_t k = k0; k < k1; ++k) ++seen[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])];
    });
    for (std::size_t j = 0; j < n; ++j) {
      ASSERT_LE(seen[j], 1);
      const double r2 = (x[i] - x[j]) * (x[i] - x[j]) + (y[i] - y[j]) * (y[i] - y[j]);
      if (r2 < support * support) {
        ASSERT_EQ(seen[j], 1) << i << " " << j;
        ++pairs;
      }
    }
  }
  EXPECT_GT(pairs, 10 * n);  // a meaningful density of neighbours
}

INSTANTIATE_TEST_SUITE_P(Reach, SphCellListReach, ::testing::Values(1, 2));

TEST(SphCellList, RebuildWithoutGrowthKeepsItsStorage) {
  std::vector<double> x{0.0, 0.1, 0.2}, y{0.0, 0.05, 0.1};
  CellList cells;
  const Grid g = grid_over(0.0, 0.0, 0.2, 0.1, 0.05);
  cells.build(g, x, y);
  const auto* before = cells.order().data();
  x[1] = 0.15;
  cells.build(g, x, y);
  EXPECT_EQ(cells.order().data(), before);
  EXPECT_EQ(cells.cell(1), g.cell_of(0.15, 0.05));
}

TEST(SphCellList, AWindowBinsItsMembersInTheirCellsOfTheWholeGrid) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t n = 2000;
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = u(rng);
    y[i] = 0.5 * u(rng);
  }
  const double support = 0.05;
  const Grid whole = grid_over(0.0, 0.0, 1.0, 0.5, support / 2);
  // The members: the points inside [0.3, 0.7] x [0.1, 0.3].
  std::vector<std::int32_t> members;
  for (std::size_t i = 0; i < n; ++i)
    if (x[i] >= 0.3 && x[i] <= 0.7 && y[i] >= 0.1 && y[i] <= 0.3) members.push_back(static_cast<std::int32_t>(i));
  ASSERT_GT(members.size(), 100u);
  const Grid window = window_of(whole, 0.3, 0.1, 0.7, 0.3);
  EXPECT_LT(window.cells(), whole.cells() / 4);
  CellList cells;
  cells.build(window, x, y, members, 2);
  ASSERT_EQ(cells.order().size(), members.size());
  std::vector<int> member(n, 0);
  for (std::int32_t m : members) member[static_cast<std::size_t>(m)] = 1;
  for (std::size_t i = 0; i < n; ++i) {
    if (!member[i]) {
      EXPECT_EQ(cells.cell(i), -1);
      continue;
    }
    // The same column and row as in the whole grid, bit for bit.
    const int c = cells.cell(i);
    EXPECT_EQ(c % window.nx + window.ox, whole.column(x[i]));
    EXPECT_EQ(c / window.nx + window.oy, whole.row(y[i]));
  }
  // Sorted by cell, ascending index within a cell; every member pair within the support found.
  const auto order = cells.order();
  for (std::size_t k = 1; k < order.size(); ++k) {
    const auto a = static_cast<std::size_t>(order[k - 1]), b = static_cast<std::size_t>(order[k]);
    ASSERT_TRUE(cells.cell(a) < cells.cell(b) || (cells.cell(a) == cells.cell(b) && a < b));
  }
  std::size_t pairs = 0;
  for (std::int32_t mi : members) {
    const auto i = static_cast<std::size_t>(mi);
    std::vector<int> seen(n, 0);
    cells.for_each_range(cells.cell(i), [&](std::int32_t k0, std::int32_t k1) {
      for (std::int32_t k = k0; k < k1; ++k) ++seen[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])];
    });
    for (std::int32_t mj : members) {
      const auto j = static_cast<std::size_t>(mj);
      const double r2 = (x[i] - x[j]) * (x[i] - x[j]) + (y[i] - y[j]) * (y[i] - y[j]);
      if (r2 < support * support) {
        ASSERT_EQ(seen[j], 1) << i << " " << j;
        ++pairs;
      }
    }
  }
  EXPECT_GT(pairs, 5 * members.size());
}
