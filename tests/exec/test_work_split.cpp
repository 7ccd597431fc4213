#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "exec/work_split.hpp"

using dsdem::exec::balance_shares;

TEST(BalanceShares, MovesWorkToTheFasterThreadUntilBothFinishTogether) {
  // Equal times: nothing to move.
  std::vector<double> share{0.5, 0.5};
  balance_shares(share, std::vector<double>{1e-3, 1e-3});
  EXPECT_DOUBLE_EQ(share[0], 0.5);
  EXPECT_DOUBLE_EQ(share[1], 0.5);
  // Thread 1 runs at 2/3 of thread 0's rate: the shares that finish together are 0.6 / 0.4.
  // Each call moves a tenth of the way there; the shares always sum to 1.
  const double rate[2] = {1.5, 1.0};  // work per second
  for (int step = 0; step < 200; ++step) {
    const std::vector<double> busy{share[0] / rate[0], share[1] / rate[1]};
    const double before = share[0];
    balance_shares(share, busy);
    EXPECT_GE(share[0], before);
    EXPECT_NEAR(share[0] + share[1], 1.0, 1e-15);
  }
  EXPECT_NEAR(share[0], 0.6, 1e-6);
  // A thread stalled for a whole step (preempted) loses at most a tenth of its share per
  // step and never falls below 0.1 / T.
  share = {0.5, 0.5};
  balance_shares(share, std::vector<double>{1e-3, 1.0});
  EXPECT_NEAR(share[1], 0.45, 1e-3);
  for (int step = 0; step < 500; ++step) balance_shares(share, std::vector<double>{1e-3, 1.0});
  EXPECT_DOUBLE_EQ(share[1], 0.05);
  EXPECT_NEAR(share[0], 0.95, 1e-15);
  // No timing (0, NaN) or a mismatched size: unchanged.
  share = {0.3, 0.7};
  balance_shares(share, std::vector<double>{0.0, 1e-3});
  balance_shares(share, std::vector<double>{std::nan(""), 1e-3});
  balance_shares(share, std::vector<double>{1e-3});
  EXPECT_EQ(share, (std::vector<double>{0.3, 0.7}));
  // Three threads, one twice as fast: it ends with half the work.
  share = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  const double rate3[3] = {1.0, 2.0, 1.0};
  for (int step = 0; step < 300; ++step)
    balance_shares(share, std::vector<double>{share[0] / rate3[0], share[1] / rate3[1], share[2] / rate3[2]});
  EXPECT_NEAR(share[0], 0.25, 1e-6);
  EXPECT_NEAR(share[1], 0.5, 1e-6);
  EXPECT_NEAR(share[2], 0.25, 1e-6);
}

TEST(CumulativeShares, RunFromZeroToOneWhateverTheSum) {
  std::vector<double> cum;
  dsdem::exec::cumulative_shares(std::vector<double>{1.0, 3.0}, cum);
  EXPECT_EQ(cum, (std::vector<double>{0.0, 0.25, 1.0}));
  dsdem::exec::cumulative_shares(std::vector<double>{0.2, 0.3, 0.5}, cum);
  ASSERT_EQ(cum.size(), 4u);
  EXPECT_EQ(cum[0], 0.0);
  EXPECT_NEAR(cum[1], 0.2, 1e-15);
  EXPECT_NEAR(cum[2], 0.5, 1e-15);
  EXPECT_EQ(cum[3], 1.0);
}

TEST(TunedSplit, RunsTileTheItemsAndFollowTheMeasuredTimes) {
  dsdem::exec::TunedSplit split;
  split.prepare(2);
  EXPECT_EQ(split.begin(1000, 0), 0u);
  EXPECT_EQ(split.begin(1000, 1), 500u);
  EXPECT_EQ(split.begin(1000, 2), 1000u);
  // Thread 1 took twice as long for the same share: it gets less next time (thread 0's run
  // ends later).
  split.set_busy(0, 1e-3);
  split.set_busy(1, 2e-3);
  split.rebalance();
  split.prepare(2);
  EXPECT_GT(split.begin(1000, 1), 500u);
  EXPECT_LT(split.begin(1000, 1), 1000u);
  EXPECT_EQ(split.begin(1000, 2), 1000u);
  // Pinned: kept through rebalance(); another thread count starts over from equal shares.
  split.pin({1.0, 3.0});
  split.prepare(2);
  split.rebalance();
  split.prepare(2);
  EXPECT_EQ(split.begin(1000, 1), 250u);
  split.prepare(3);
  EXPECT_EQ(split.begin(900, 1), 300u);
  EXPECT_EQ(split.begin(900, 3), 900u);
}

namespace {
// True while some item other than thread 1's first chunk [500, 510) is not done yet.
bool runs_left_in_other(const std::vector<std::atomic<int>>& hits, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if ((i < 500 || i >= 510) && hits[i].load() == 0) return true;
  return false;
}
}  // namespace

// Every item is done exactly once, whatever thread gets there first: a thread whose run
// is empty or fast takes the chunks left in the other's run (the element loops).
TEST(StealingRuns, EveryItemOnceAndAFastThreadTakesTheSlowOnesChunks) {
  dsdem::exec::StealingRuns runs;
  constexpr std::size_t n = 1000;
  // One thread alone (what a team of one meets): both runs, own first, in chunks of 7.
  {
    const std::vector<std::size_t> bounds{0, 300, n};
    runs.reset(bounds);
    std::vector<int> hits(n, 0);
    std::vector<std::size_t> order;
    const std::size_t done = runs.run(1, 7, [&](std::size_t b, std::size_t e) {
      EXPECT_LE(e - b, 7u);
      order.push_back(b);
      for (std::size_t i = b; i < e; ++i) ++hits[i];
    });
    EXPECT_EQ(done, n);
    for (int h : hits) ASSERT_EQ(h, 1);
    EXPECT_EQ(order.front(), 300u);  // its own run [300, 1000) first
    EXPECT_EQ(order.back(), 294u);   // then thread 0's run, the last chunk cut at 300
  }
  // Two threads; thread 1 stalls on its first chunk, so thread 0 does the rest of its run.
  for (int rep = 0; rep < 20; ++rep) {
    const std::vector<std::size_t> bounds{0, n / 2, n};
    runs.reset(bounds);
    std::vector<std::atomic<int>> hits(n);
    std::atomic<bool> first_chunk_done{false};
    std::size_t done[2] = {0, 0};
#pragma omp parallel num_threads(2)
    {
#ifdef _OPENMP
      const int t = omp_get_thread_num();
      const int T = omp_get_num_threads();
#else
      const int t = 0, T = 1;
#endif
      for (int u = t; u < 2; u += T) {  // a team of one plays both threads in turn
        done[u] = runs.run(u, 10, [&](std::size_t b, std::size_t e) {
          for (std::size_t i = b; i < e; ++i) hits[i].fetch_add(1);
          if (u == 1 && T == 2 && !first_chunk_done.exchange(true)) {
            // Stall until thread 0 has done everything else (a bounded wait: no stealing
            // fails the count below instead of hanging the test).
            const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
            while (runs_left_in_other(hits, n) && std::chrono::steady_clock::now() < until) {}
          }
        });
      }
    }
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i].load(), 1) << "item " << i;
    EXPECT_EQ(done[0] + done[1], n);
#ifdef _OPENMP
    if (omp_get_max_threads() >= 2) EXPECT_EQ(done[1], 10u);  // its stalled chunk; thread 0 took the rest
#endif
  }
  // The busy time for the tuned split: the time the own run would have taken at the
  // rate shown (own 500 items, 750 done in 3 ms: 2 ms); nothing done: as measured.
  EXPECT_DOUBLE_EQ(dsdem::exec::StealingRuns::busy_for_own_run(3e-3, 500, 750), 2e-3);
  EXPECT_DOUBLE_EQ(dsdem::exec::StealingRuns::busy_for_own_run(3e-3, 500, 0), 3e-3);
}
