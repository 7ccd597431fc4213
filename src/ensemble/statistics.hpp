#pragma once
// Statistics of an ensemble's outputs (docs/theory.md §13): sample quantiles, bootstrap confidence
// intervals, Wilson intervals for event probabilities, Spearman rank correlation. Pure
// functions, seeded and deterministic.
#include <cstdint>
#include <vector>

namespace dsdem::ensemble {

double mean(const std::vector<double>& x);
// Sample standard deviation (n - 1); 0 for fewer than two values.
double standard_deviation(const std::vector<double>& x);
// Sample quantile at p in [0, 1], linear between order statistics (Hyndman & Fan type 7,
// the default of R and numpy). `x` need not be sorted.
double quantile(std::vector<double> x, double p);
double quantile_sorted(const std::vector<double>& sorted, double p);

struct Interval {
  double low = 0.0, high = 0.0;
};

// Percentile-bootstrap intervals (Efron) at `level` for the mean, the standard deviation and
// the quantiles `ps`, from `resamples` resamples drawn with a generator seeded by `seed`.
struct BootstrapResult {
  Interval mean, sd;
  std::vector<Interval> quantiles;  // one per p
};
BootstrapResult bootstrap(const std::vector<double>& x, const std::vector<double>& ps, int resamples,
                          std::uint64_t seed, double level = 0.95);

// Wilson score interval for a proportion of `successes` out of `n` at `level` (two-sided).
Interval wilson_interval(std::size_t successes, std::size_t n, double level = 0.95);

// Ranks 1..n, ties given their average rank.
std::vector<double> ranks(const std::vector<double>& x);
// Spearman's rank correlation (Pearson correlation of the ranks); 0 when either is constant.
double spearman(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace dsdem::ensemble
