// Statistics of ensemble outputs (docs/theory.md §13).
#include <gtest/gtest.h>

#include <cmath>

#include "ensemble/sampling.hpp"
#include "ensemble/statistics.hpp"

using namespace dsdem::ensemble;

TEST(Statistics, QuantilesAsNumpy) {
  const std::vector<double> x{4, 1, 3, 2, 5};
  EXPECT_EQ(quantile(x, 0.5), 3.0);
  EXPECT_EQ(quantile(x, 0.05), 1.2);  // numpy.percentile([1..5], 5) = 1.2
  EXPECT_EQ(quantile(x, 1.0), 5.0);
  EXPECT_NEAR(standard_deviation(x), std::sqrt(2.5), 1e-15);
}

TEST(Statistics, WilsonIntervalAsPublished) {
  // Newcombe (1998), Table I: 81 of 263 -> 0.2553 to 0.3662.
  const auto w = wilson_interval(81, 263);
  EXPECT_NEAR(w.low, 0.2553, 5e-5);
  EXPECT_NEAR(w.high, 0.3662, 5e-5);
  const auto zero = wilson_interval(0, 10);
  EXPECT_EQ(zero.low, 0.0);
  EXPECT_NEAR(zero.high, 0.2775, 5e-5);
}

TEST(Statistics, SpearmanOfMonotoneAndTiedData) {
  const std::vector<double> x{1, 2, 3, 4, 5}, y{1, 8, 27, 64, 125}, z{5, 4, 3, 2, 1};
  EXPECT_NEAR(spearman(x, y), 1.0, 1e-15);
  EXPECT_NEAR(spearman(x, z), -1.0, 1e-15);
  EXPECT_EQ(ranks({10, 20, 20, 30}), (std::vector<double>{1, 2.5, 2.5, 4}));
}

TEST(Statistics, BootstrapCoversTheMeanAndIsSeeded) {
  std::mt19937_64 rng(3);
  std::vector<double> x(200);
  for (auto& v : x) v = normal_quantile(uniform01(rng));
  const auto a = bootstrap(x, {0.05, 0.5, 0.95}, 1000, 42);
  const auto b = bootstrap(x, {0.05, 0.5, 0.95}, 1000, 42);
  EXPECT_EQ(a.mean.low, b.mean.low);
  EXPECT_EQ(a.quantiles[2].high, b.quantiles[2].high);
  const double m = mean(x), se = standard_deviation(x) / std::sqrt(200.0);
  EXPECT_NEAR(a.mean.low, m - 1.96 * se, 0.3 * se);
  EXPECT_NEAR(a.mean.high, m + 1.96 * se, 0.3 * se);
  EXPECT_LT(a.quantiles[1].low, quantile(x, 0.5));
  EXPECT_GT(a.quantiles[1].high, quantile(x, 0.5));
}
