// Broad phase: exactly the brute-force pairs, complete under moves below half the
// skin, O(N) grid, no allocation once warmed up (docs/theory.md §4).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "common/alloc_counter.hpp"
#include "contact/broad_phase.hpp"
#include "contact/narrow_phase.hpp"

using namespace dsdem;
using namespace dsdem::contact;

namespace {

struct Soup {
  std::vector<Vec2> x;
  std::vector<std::array<Index, 3>> conn;
  std::vector<std::uint8_t> active;
};

// n separate triangles (own nodes) with log-uniform sizes in [smin, smax], centres
// uniform in a square sized for a few neighbours each; `active_fraction` take part.
Soup random_soup(unsigned seed, int n, double smin, double smax, double active_fraction) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double mean = 0.5 * (smin + smax);
  const double L = std::sqrt(n * mean * mean / 1.5);
  Soup s;
  for (int t = 0; t < n; ++t) {
    const Vec2 c(L * u(rng), L * u(rng));
    const double size = smin * std::pow(smax / smin, u(rng));
    const double a0 = 2.0 * kPi * u(rng);
    std::array<Index, 3> tri;
    for (int k = 0; k < 3; ++k) {
      const double a = a0 + k * 2.0 * kPi / 3.0 + 0.5 * (u(rng) - 0.5);
      const double rad = size * (0.5 + 0.5 * u(rng));
      tri[k] = static_cast<Index>(s.x.size());
      s.x.push_back(c + rad * Vec2(std::cos(a), std::sin(a)));
    }
    s.conn.push_back(tri);
    s.active.push_back(u(rng) < active_fraction ? 1 : 0);
  }
  return s;
}

Aabb node_box(const Soup& s, Index t, double margin) {
  const auto& c = s.conn[t];
  Aabb b;
  b.lo = s.x[c[0]].cwiseMin(s.x[c[1]]).cwiseMin(s.x[c[2]]).array() - margin;
  b.hi = s.x[c[0]].cwiseMax(s.x[c[1]]).cwiseMax(s.x[c[2]]).array() + margin;
  return b;
}

template <class Skip>
std::vector<std::pair<Index, Index>> brute_force(const Soup& s, double margin, Skip skip) {
  std::vector<std::pair<Index, Index>> out;
  const Index n = static_cast<Index>(s.conn.size());
  for (Index i = 0; i < n; ++i) {
    if (!s.active[i]) continue;
    const Aabb a = node_box(s, i, margin);
    for (Index j = i + 1; j < n; ++j)
      if (s.active[j] && overlaps(a, node_box(s, j, margin)) && !skip(i, j)) out.emplace_back(i, j);
  }
  return out;
}

std::vector<std::pair<Index, Index>> listed(const BroadPhase& bp) {
  std::vector<std::pair<Index, Index>> out;
  for (const ContactPair& p : bp.pairs()) out.emplace_back(p.i, p.j);
  return out;
}

}  // namespace

TEST(BroadPhase, FindsExactlyTheBruteForcePairsInOrder) {
  struct Case {
    unsigned seed;
    int n;
    double smin, smax, active;
  };
  for (const Case& c : {Case{1, 1000, 0.5, 0.5, 1.0}, Case{2, 1500, 0.2, 1.0, 0.9},
                        Case{3, 2000, 0.05, 2.0, 0.8}, Case{4, 1200, 0.01, 3.0, 1.0}}) {
    const Soup s = random_soup(c.seed, c.n, c.smin, c.smax, c.active);
    const double skin = 0.1 * c.smin + 0.02;
    BroadPhase bp;
    bp.build(s.x, s.conn, s.active, skin);
    const auto want = brute_force(s, 0.5 * skin, [](Index, Index) { return false; });
    EXPECT_GT(want.size(), static_cast<std::size_t>(c.n));  // a dense enough set to mean something
    EXPECT_EQ(listed(bp), want) << "seed " << c.seed;       // same pairs, same (sorted) order
    EXPECT_LE(bp.cell_count(), 6L * c.n + 1);
    // With a skip predicate.
    auto skip = [](Index i, Index j) { return (i + j) % 5 == 0; };
    bp.build(s.x, s.conn, s.active, skin, skip);
    EXPECT_EQ(listed(bp), brute_force(s, 0.5 * skin, skip)) << "seed " << c.seed;
  }
}

TEST(BroadPhase, StillCompleteAfterMovesBelowHalfTheSkin) {
  for (unsigned seed : {5u, 6u, 7u}) {
    Soup s = random_soup(seed, 1500, 0.1, 1.0, 1.0);
    const double skin = 0.08;
    BroadPhase bp;
    bp.build(s.x, s.conn, s.active, skin);
    ASSERT_FALSE(bp.needs_rebuild(s.x, s.conn));
    const std::vector<Vec2> x_build = s.x;
    // Every node moves up to 0.499 skin in a random direction.
    std::mt19937 rng(seed + 100);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (Vec2& p : s.x) {
      const double a = 2.0 * kPi * u(rng);
      p += 0.499 * skin * std::sqrt(u(rng)) * Vec2(std::cos(a), std::sin(a));
    }
    ASSERT_FALSE(bp.needs_rebuild(s.x, s.conn));
    const auto have = listed(bp);
    // Every pair whose current triangle boxes overlap, and every real contact of the
    // rounded shapes, is in the list built before the move.
    const auto now = brute_force(s, 0.0, [](Index, Index) { return false; });
    std::size_t contacts = 0;
    for (const auto& pr : now) {
      EXPECT_TRUE(std::binary_search(have.begin(), have.end(), pr)) << pr.first << " " << pr.second;
    }
    std::array<ContactGeometry, kMaxContactsPerPair> out;
    const Index n = static_cast<Index>(s.conn.size());
    std::vector<Spheropolygon> sp;
    std::vector<Aabb> box;
    for (Index t = 0; t < n; ++t) {
      const auto& c = s.conn[t];
      sp.push_back(make_spheropolygon(s.x[c[0]], s.x[c[1]], s.x[c[2]],
                                      rounding_radius(s.x[c[0]], s.x[c[1]], s.x[c[2]], 0.2)));
      box.push_back(bounding_box(sp.back()));
    }
    for (Index i = 0; i < n; ++i)
      for (Index j = i + 1; j < n; ++j)
        if (overlaps(box[i], box[j]) && narrow_phase(sp[i], sp[j], out) > 0) {
          ++contacts;
          EXPECT_TRUE(std::binary_search(have.begin(), have.end(), std::make_pair(i, j)));
        }
    EXPECT_GT(contacts, 100u);
    // A node a little further than half the skin above its triangle's highest node of
    // the build leaves the triangle's enlarged box: the list may be incomplete.
    const auto& c = s.conn[17];
    const double top = std::max({x_build[c[0]].y(), x_build[c[1]].y(), x_build[c[2]].y()});
    s.x[c[0]] = Vec2(x_build[c[0]].x(), top + 0.501 * skin);
    EXPECT_TRUE(bp.needs_rebuild(s.x, s.conn));
  }
}

TEST(BroadPhase, NoRebuildWhileEveryTriangleStaysInItsEnlargedBox) {
  // A whole triangle sliding 0.49 skin along x, and a node moving inside its triangle's
  // box by more than half the skin (a node that is not the box's extreme), keep the list.
  Soup s;
  s.x = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(3, 0), Vec2(4, 0), Vec2(3, 1)};
  s.conn = {{0, 1, 2}, {3, 4, 5}};
  s.active = {1, 1};
  const double skin = 0.2;
  BroadPhase bp;
  bp.build(s.x, s.conn, s.active, skin);
  EXPECT_FALSE(bp.needs_rebuild(s.x, s.conn));
  for (int k = 0; k < 3; ++k) s.x[k].x() += 0.49 * skin;
  EXPECT_FALSE(bp.needs_rebuild(s.x, s.conn));
  s.x[5] = Vec2(3.8, 0.5);  // 0.94 m from where it was, still inside [2.9, 4.1] x [-0.1, 1.1]
  EXPECT_FALSE(bp.needs_rebuild(s.x, s.conn));
  s.x[5] = Vec2(4.11, 0.5);  // out of the box
  EXPECT_TRUE(bp.needs_rebuild(s.x, s.conn));
  // Displacements given separately: the same test on X + u.
  std::vector<Vec2> X = s.x, u(s.x.size(), Vec2::Zero());
  X[5] = Vec2(3.0, 1.0);
  u[5] = Vec2(1.11, -0.5);
  EXPECT_TRUE(bp.needs_rebuild(NodePositions(X, u), s.conn));
  u[5] = Vec2(0.8, -0.5);
  EXPECT_FALSE(bp.needs_rebuild(NodePositions(X, u), s.conn));
}

TEST(BroadPhase, SparseAndElongatedSetsKeepTheGridLinear) {
  // Two clusters 1e6 m apart, then a 1e5 m long line of triangles: the cell count stays
  // O(N) and the pairs are still exact.
  Soup s = random_soup(8, 600, 0.3, 0.6, 1.0);
  Soup far = random_soup(9, 600, 0.3, 0.6, 1.0);
  const Index off = static_cast<Index>(s.x.size());
  for (auto& p : far.x) s.x.push_back(p + Vec2(1e6, 3e5));
  for (auto c : far.conn) s.conn.push_back({c[0] + off, c[1] + off, c[2] + off});
  s.active.insert(s.active.end(), far.active.begin(), far.active.end());
  BroadPhase bp;
  bp.build(s.x, s.conn, s.active, 0.05);
  EXPECT_EQ(listed(bp), brute_force(s, 0.025, [](Index, Index) { return false; }));
  EXPECT_LE(bp.cell_count(), 6L * 1200 + 1);

  Soup line;
  for (int t = 0; t < 1000; ++t) {
    const Index b = static_cast<Index>(line.x.size());
    const double x0 = 100.0 * t;
    line.x.insert(line.x.end(), {Vec2(x0, 0), Vec2(x0 + 60.0, 0.0), Vec2(x0 + 30.0, 1.0)});
    line.conn.push_back({b, b + 1, b + 2});
    line.active.push_back(1);
  }
  bp.build(line.x, line.conn, line.active, 50.0);  // neighbours' boxes just overlap
  EXPECT_EQ(bp.pairs().size(), 999u);
  EXPECT_EQ(listed(bp), brute_force(line, 25.0, [](Index, Index) { return false; }));
  EXPECT_LE(bp.cell_count(), 6L * 1000 + 1);
}

TEST(BroadPhase, RebuildAllocatesNothingOnceWarm) {
  Soup s = random_soup(10, 1500, 0.1, 1.0, 0.9);
  BroadPhase bp;
  bp.build(s.x, s.conn, s.active, 0.05);
  const std::size_t n0 = bp.pairs().size();
  for (Vec2& p : s.x) p *= 1.001;  // a slightly different configuration, same size
  dsdem::test::AllocationScope scope;
  bp.build(s.x, s.conn, s.active, 0.05);
  const bool rebuild = bp.needs_rebuild(s.x, s.conn);
  EXPECT_EQ(scope.count(), 0);
  EXPECT_FALSE(rebuild);
  EXPECT_NEAR(static_cast<double>(bp.pairs().size()), static_cast<double>(n0), 0.05 * n0);
}

TEST(BroadPhase, PairBoundHoldsForAnySetAndSkip) {
  for (unsigned seed = 20; seed < 26; ++seed) {
    const Soup s = random_soup(seed, 400 + 300 * (seed % 3), 0.05 * (1 + seed % 4), 1.0, 0.85);
    BroadPhase bp;
    bp.build(s.x, s.conn, s.active, 0.02 * (1 + seed % 5));
    const std::size_t bound = bp.pair_bound();
    EXPECT_LE(bp.pairs().size(), bound) << "seed " << seed;
    EXPECT_GT(bp.pairs().size(), 0u) << "seed " << seed;
    // Tight enough to reserve from: 2.4x on the bench box, up to 4.1x on these mixed sizes.
    EXPECT_LT(bound, 8 * bp.pairs().size()) << "seed " << seed;
  }
}

// The first build reserves the pair list from pair_bound() before its sweep: the list does
// not grow by doubling, whose last growth held the old and the new block at once (the
// 10^6-element box's peak memory was 43 MB above its steady state). So the build's
// allocations do not depend on how many pairs it finds.
TEST(BroadPhase, FirstBuildAllocatesTheSameForAnyPairCount) {
  auto first_build_allocations = [](int n) {
    const Soup s = random_soup(30, n, 0.2, 1.0, 1.0);
    BroadPhase bp;
    dsdem::test::AllocationScope scope;
    bp.build(s.x, s.conn, s.active, 0.05);
    const long count = scope.count();
    EXPECT_GT(bp.pairs().size(), static_cast<std::size_t>(n));
    return count;
  };
  EXPECT_EQ(first_build_allocations(500), first_build_allocations(16000));
}
