// Sampling of ensemble values (docs/theory.md §13): distributions, Latin hypercube, correlation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ensemble/sampling.hpp"
#include "ensemble/statistics.hpp"

using namespace dsdem::ensemble;

TEST(Sampling, NormalQuantileInvertsTheCdf) {
  for (double p : {1e-300, 1e-12, 1e-6, 0.01, 0.2, 0.5, 0.7, 0.975, 1 - 1e-9}) {
    const double z = normal_quantile(p);
    EXPECT_NEAR(normal_cdf(z) / p, 1.0, 1e-12) << p;
  }
  EXPECT_NEAR(normal_quantile(0.975), 1.959963984540054, 1e-14);
  EXPECT_EQ(normal_quantile(0.5), 0.0);
}

TEST(Sampling, SameSeedSameSamplesOtherSeedOthers) {
  const auto a = sample_probabilities(50, 3, SamplingMethod::LatinHypercube, 7);
  const auto b = sample_probabilities(50, 3, SamplingMethod::LatinHypercube, 7);
  const auto c = sample_probabilities(50, 3, SamplingMethod::LatinHypercube, 8);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  // A value fixed by the generator's specification, so a change of platform would show.
  const auto m = sample_probabilities(1, 1, SamplingMethod::MonteCarlo, 1);
  std::mt19937_64 rng(1);
  EXPECT_EQ(m[0][0], (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53);
}

TEST(Sampling, LatinHypercubeHasOneMemberInEveryStratum) {
  const std::size_t n = 37;
  const auto u = sample_probabilities(n, 4, SamplingMethod::LatinHypercube, 3);
  for (std::size_t j = 0; j < 4; ++j) {
    std::vector<int> count(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_GT(u[i][j], 0.0);
      ASSERT_LT(u[i][j], 1.0);
      ++count[static_cast<std::size_t>(u[i][j] * n)];
    }
    EXPECT_TRUE(std::all_of(count.begin(), count.end(), [](int c) { return c == 1; })) << "variable " << j;
  }
}

TEST(Sampling, MomentsOfEveryDistribution) {
  std::vector<Distribution> ds(6);
  ds[0].kind = DistributionKind::Uniform, ds[0].lower = 0.55, ds[0].upper = 0.85;
  ds[1].kind = DistributionKind::Normal, ds[1].mean = 10.0, ds[1].sd = 2.0;
  ds[1].lower = -INFINITY, ds[1].upper = INFINITY;
  ds[2].kind = DistributionKind::Lognormal, ds[2].mean = 3.0, ds[2].sd = 1.5;
  ds[3].kind = DistributionKind::Triangular, ds[3].lower = 0.1, ds[3].mode = 0.15, ds[3].upper = 0.35;
  ds[4].kind = DistributionKind::Integer, ds[4].lower = 1, ds[4].upper = 100;
  ds[5].kind = DistributionKind::List, ds[5].choices = 3, ds[5].weights = {1.0, 2.0, 1.0};
  const std::size_t n = 20000;
  const auto u = sample_probabilities(n, ds.size(), SamplingMethod::LatinHypercube, 11);
  for (std::size_t j = 0; j < ds.size(); ++j) {
    ASSERT_EQ(ds[j].check(), "");
    std::vector<double> x(n);
    for (std::size_t i = 0; i < n; ++i) x[i] = ds[j].quantile(u[i][j]);
    const double sd = std::sqrt(ds[j].exact_variance());
    // Latin hypercube: the mean's error is far below the Monte Carlo sd / sqrt(n).
    EXPECT_NEAR(mean(x), ds[j].exact_mean(), 3.0 * sd / std::sqrt(double(n))) << "distribution " << j;
    EXPECT_NEAR(standard_deviation(x) / sd, 1.0, 0.01) << "distribution " << j;
  }
  // The integer range and the list give their values only.
  for (std::size_t i = 0; i < n; ++i) {
    const double k = ds[4].quantile(u[i][4]);
    ASSERT_TRUE(k >= 1 && k <= 100 && std::floor(k) == k);
  }
}

TEST(Sampling, TruncatedNormalStaysInItsBounds) {
  Distribution d;
  d.kind = DistributionKind::Normal, d.mean = 0.3, d.sd = 0.2, d.lower = 0.0, d.upper = 1.0;
  for (double u : {1e-12, 0.01, 0.5, 0.99, 1 - 1e-12}) {
    EXPECT_GE(d.quantile(u), 0.0);
    EXPECT_LE(d.quantile(u), 1.0);
  }
  EXPECT_NEAR(d.quantile(0.5), 0.3 + 0.2 * normal_quantile(0.5 * (normal_cdf(-1.5) + normal_cdf(3.5))), 1e-15);
}

TEST(Sampling, ImpossibleParametersAreNamed) {
  Distribution d;
  d.kind = DistributionKind::Normal, d.sd = 0.0, d.lower = -INFINITY, d.upper = INFINITY;
  EXPECT_NE(d.check().find("sd must be > 0"), std::string::npos);
  d.kind = DistributionKind::Uniform, d.lower = 2, d.upper = 1;
  EXPECT_NE(d.check().find("must be below upper"), std::string::npos);
  d.kind = DistributionKind::Triangular, d.lower = 0, d.upper = 1, d.mode = 2;
  EXPECT_NE(d.check().find("mode (2) must lie in"), std::string::npos);
  d.kind = DistributionKind::Lognormal, d.mean = -1, d.sd = 1;
  EXPECT_NE(d.check().find("mean must be > 0"), std::string::npos);
  d.kind = DistributionKind::Integer, d.lower = 1.5, d.upper = 3;
  EXPECT_NE(d.check().find("integers"), std::string::npos);
  EXPECT_NE(check_correlation({{1, 0.9, -0.9}, {0.9, 1, 0.9}, {-0.9, 0.9, 1}}).find("positive definite"), std::string::npos);
}

TEST(Sampling, ImanConoverGivesTheRankCorrelationAndKeepsTheStrata) {
  const std::size_t n = 400;
  const std::vector<std::vector<double>> c{{1.0, 0.7, 0.0}, {0.7, 1.0, -0.4}, {0.0, -0.4, 1.0}};
  const auto u = sample_probabilities(n, 3, SamplingMethod::LatinHypercube, 5, c);
  std::vector<std::vector<double>> col(3, std::vector<double>(n));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < 3; ++j) col[j][i] = u[i][j];
  EXPECT_NEAR(spearman(col[0], col[1]), 0.7, 0.03);
  EXPECT_NEAR(spearman(col[1], col[2]), -0.4, 0.03);
  EXPECT_NEAR(spearman(col[0], col[2]), 0.0, 0.05);
  for (std::size_t j = 0; j < 3; ++j) {
    std::vector<int> count(n, 0);
    for (std::size_t i = 0; i < n; ++i) ++count[static_cast<std::size_t>(u[i][j] * n)];
    EXPECT_TRUE(std::all_of(count.begin(), count.end(), [](int k) { return k == 1; }));
  }
}
