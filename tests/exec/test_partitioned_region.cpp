#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <vector>

#include "exec/partitioned_region.hpp"

using dsdem::exec::PartitionedRegion;
using dsdem::exec::SplitRegion;
using dsdem::exec::TunedRegion;

namespace {

void spin_for(double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < until) {
  }
}

}  // namespace

TEST(TunedRegion, VisitsEveryItemOnceAndTunesTheSplitTowardsTheSlowerItems) {
  constexpr std::size_t n = 200;
  for (int threads = 1; threads <= 3; ++threads) {
    TunedRegion region;
    std::vector<std::atomic<int>> visits(n);
    const int bits = region.run(threads, n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) visits[i].fetch_add(1);
      return 1 | (b <= 10 && 10 < e ? 4 : 0);  // every run bit 1, the one holding item 10 bit 4
    });
    EXPECT_EQ(bits, 5) << threads;
    for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(visits[i].load(), 1) << threads << " " << i;
  }
  // Two threads, the later half of the items ten times as costly: the first thread's share
  // grows (each thread's run follows its busy time).
  TunedRegion region;
  for (int call = 0; call < 30; ++call)
    region.run(2, n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) spin_for(i < n / 2 ? 2e-6 : 2e-5);
      return 0;
    });
  ASSERT_EQ(region.split().share().size(), 2u);
  EXPECT_GT(region.split().share()[0], 0.55);
}

namespace {

// Run t of a partition writes a[i] for its items in phase 1; phase 2 reads a[i + 1] (in a
// later run at a run's end) after waiting for the later runs; phase 3 and the gather
// record their visits.
struct PartitionKernels {
  std::size_t n;
  const PartitionedRegion& region;
  std::vector<long>& a;
  std::vector<long>& b;
  std::vector<std::atomic<int>>& third_visits;
  std::vector<std::atomic<int>>& gathers;
  int stop_in_run = -1;
  std::size_t begin(int t, int T) const { return T == 1 ? (t == 0 ? 0 : n) : region.begin(n, t); }
  std::size_t end(int t, int T) const { return T == 1 ? n : region.begin(n, t + 1); }
  bool first(int t, int T) {
    for (std::size_t i = begin(t, T); i < end(t, T); ++i) a[i] = static_cast<long>(3 * i + 1);
    return t == stop_in_run;
  }
  long second(int t, int T, PartitionedRegion::Later& later) {
    const std::size_t e = end(t, T);
    for (std::size_t i = begin(t, T); i < e; ++i) {
      if (i + 1 == e && e < n) later.wait();  // a[e] is a later run's
      b[i] = a[i] + (i + 1 < n ? a[i + 1] : 0);
    }
    return static_cast<long>(e - begin(t, T));
  }
  void third(int t, int T, bool) {
    for (std::size_t i = begin(t, T); i < end(t, T); ++i) third_visits[i].fetch_add(1);
  }
  void gather(int t, int) { gathers[static_cast<std::size_t>(t)].fetch_add(1); }
};

}  // namespace

TEST(PartitionedRegion, RunsEveryItemOnceWithTheLaterRunsFirstPhaseSeen) {
  constexpr std::size_t n = 1000;
  std::vector<long> reference;
  for (int threads = 1; threads <= 3; ++threads) {
    PartitionedRegion region;
    if (threads == 3) region.pin({0.2, 0.5, 0.3});  // the results do not depend on the split
    for (int call = 0; call < 3; ++call) {
      std::vector<long> a(n, 0), b(n, 0);
      std::vector<std::atomic<int>> third(n), gathers(3);
      PartitionKernels k{n, region, a, b, third, gathers};
      region.prepare(threads);
      const PartitionedRegion::Result r = region.run(threads, k);
      EXPECT_FALSE(r.stopped);
      EXPECT_EQ(r.count, static_cast<long>(n));
      for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(third[i].load(), 1) << threads << " " << i;
      // The gather runs on every thread of a team of several, after the barrier.
      for (int t = 0; t < 3; ++t) EXPECT_EQ(gathers[t].load(), r.threads > 1 && t < r.threads ? 1 : 0);
      if (reference.empty()) reference = b;
      EXPECT_EQ(b, reference) << threads;
    }
  }
  // A stop from any run: every thread skips the gather.
  PartitionedRegion region;
  std::vector<long> a(n, 0), b(n, 0);
  std::vector<std::atomic<int>> third(n), gathers(2);
  PartitionKernels k{n, region, a, b, third, gathers, 1};
  region.prepare(2);
  const PartitionedRegion::Result r = region.run(2, k);
  if (r.threads == 2) {
    EXPECT_TRUE(r.stopped);
    EXPECT_EQ(gathers[0].load() + gathers[1].load(), 0);
  }
}

namespace {

struct SplitKernels {
  std::size_t n;
  std::vector<std::atomic<int>>& filtered;
  std::atomic<int>& collects;
  std::vector<std::atomic<int>>& items_done;
  std::vector<std::atomic<int>>& pair_threads;
  std::atomic<int>& gathers;
  bool do_split = true;
  long filter(int, int, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) filtered[i].fetch_add(1);
    return static_cast<long>(e - b);
  }
  bool split(int) const { return do_split; }
  bool scales() const { return true; }
  void collect(int) { collects.fetch_add(1); }
  std::size_t items() const { return items_done.size(); }
  void item(std::size_t s) { items_done[s].fetch_add(1); }
  void prepare(int, int, bool) {}
  void pairs(int t, int T, bool split, std::span<const double> cum) {
    if (split || t == 0) pair_threads[static_cast<std::size_t>(t)].fetch_add(1);
    if (!cum.empty()) EXPECT_EQ(cum.size(), static_cast<std::size_t>(T) + 1);
  }
  void gather(int, int) { gathers.fetch_add(1); }
};

}  // namespace

TEST(SplitRegion, FiltersEveryItemOnceAndSplitsThePairLoopOnlyWhenAsked) {
  constexpr std::size_t n = 500;
  for (int threads = 1; threads <= 3; ++threads) {
    for (bool split : {false, true}) {
      SplitRegion region;
      std::vector<std::atomic<int>> filtered(n), items(77), pair_threads(3);
      std::atomic<int> collects{0}, gathers{0};
      SplitKernels k{n, filtered, collects, items, pair_threads, gathers, split};
      const SplitRegion::Result r = region.run(threads, n, k);
      EXPECT_EQ(r.count, static_cast<long>(n));
      for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(filtered[i].load(), 1);
      EXPECT_EQ(collects.load(), 1);
      for (auto& c : items) EXPECT_EQ(c.load(), 1);
      const bool ran_split = split && r.threads > 1;
      EXPECT_EQ(r.split, ran_split);
      EXPECT_EQ(gathers.load(), ran_split ? r.threads : 0);
      for (int t = 0; t < 3; ++t) EXPECT_EQ(pair_threads[t].load(), t == 0 || (ran_split && t < r.threads) ? 1 : 0);
    }
  }
}
