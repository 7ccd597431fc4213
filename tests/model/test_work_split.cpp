#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "model/work_split.hpp"

using dsdem::balance_shares;

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
  dsdem::cumulative_shares(std::vector<double>{1.0, 3.0}, cum);
  EXPECT_EQ(cum, (std::vector<double>{0.0, 0.25, 1.0}));
  dsdem::cumulative_shares(std::vector<double>{0.2, 0.3, 0.5}, cum);
  ASSERT_EQ(cum.size(), 4u);
  EXPECT_EQ(cum[0], 0.0);
  EXPECT_NEAR(cum[1], 0.2, 1e-15);
  EXPECT_NEAR(cum[2], 0.5, 1e-15);
  EXPECT_EQ(cum[3], 1.0);
}

TEST(TunedSplit, RunsTileTheItemsAndFollowTheMeasuredTimes) {
  dsdem::TunedSplit split;
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
