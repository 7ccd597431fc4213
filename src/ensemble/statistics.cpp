#include "ensemble/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "ensemble/sampling.hpp"

namespace dsdem::ensemble {

double mean(const std::vector<double>& x) {
  if (x.empty()) return 0.0;
  double s = 0.0;
  for (double v : x) s += v;
  return s / static_cast<double>(x.size());
}

double standard_deviation(const std::vector<double>& x) {
  if (x.size() < 2) return 0.0;
  const double m = mean(x);
  double s = 0.0;
  for (double v : x) s += (v - m) * (v - m);
  return std::sqrt(s / static_cast<double>(x.size() - 1));
}

double quantile_sorted(const std::vector<double>& s, double p) {
  if (s.empty()) return 0.0;
  const double h = p * static_cast<double>(s.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, s.size() - 1);
  return s[lo] + (h - static_cast<double>(lo)) * (s[hi] - s[lo]);
}

double quantile(std::vector<double> x, double p) {
  std::sort(x.begin(), x.end());
  return quantile_sorted(x, p);
}

BootstrapResult bootstrap(const std::vector<double>& x, const std::vector<double>& ps, int resamples,
                          std::uint64_t seed, double level) {
  BootstrapResult r;
  r.quantiles.resize(ps.size());
  if (x.empty() || resamples < 2) return r;
  std::mt19937_64 rng(seed);
  const std::size_t n = x.size();
  std::vector<double> means, sds;
  std::vector<std::vector<double>> qs(ps.size());
  std::vector<double> s(n);
  for (int b = 0; b < resamples; ++b) {
    for (std::size_t i = 0; i < n; ++i)
      s[i] = x[std::min(n - 1, static_cast<std::size_t>(uniform01(rng) * static_cast<double>(n)))];
    means.push_back(mean(s));
    sds.push_back(standard_deviation(s));
    std::sort(s.begin(), s.end());
    for (std::size_t k = 0; k < ps.size(); ++k) qs[k].push_back(quantile_sorted(s, ps[k]));
  }
  const double a = 0.5 * (1.0 - level);
  auto interval = [&](std::vector<double>& v) { return Interval{quantile(v, a), quantile(v, 1.0 - a)}; };
  r.mean = interval(means);
  r.sd = interval(sds);
  for (std::size_t k = 0; k < ps.size(); ++k) r.quantiles[k] = interval(qs[k]);
  return r;
}

Interval wilson_interval(std::size_t successes, std::size_t n, double level) {
  if (n == 0) return {0.0, 1.0};
  const double z = normal_quantile(0.5 + 0.5 * level);
  const double nn = static_cast<double>(n);
  const double p = static_cast<double>(successes) / nn;
  const double denom = 1.0 + z * z / nn;
  const double centre = (p + z * z / (2.0 * nn)) / denom;
  const double half = z * std::sqrt(p * (1.0 - p) / nn + z * z / (4.0 * nn * nn)) / denom;
  if (successes == 0) return {0.0, std::min(1.0, centre + half)};
  if (successes == n) return {std::max(0.0, centre - half), 1.0};
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

std::vector<double> ranks(const std::vector<double>& x) {
  std::vector<std::size_t> order(x.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return x[a] < x[b]; });
  std::vector<double> r(x.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && x[order[j + 1]] == x[order[i]]) ++j;
    const double avg = 0.5 * static_cast<double>(i + j) + 1.0;
    for (std::size_t k = i; k <= j; ++k) r[order[k]] = avg;
    i = j + 1;
  }
  return r;
}

double spearman(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size() || x.size() < 2) return 0.0;
  const auto rx = ranks(x), ry = ranks(y);
  const double mx = mean(rx), my = mean(ry);
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < rx.size(); ++i) {
    sxy += (rx[i] - mx) * (ry[i] - my);
    sxx += (rx[i] - mx) * (rx[i] - mx);
    syy += (ry[i] - my) * (ry[i] - my);
  }
  if (sxx <= 0.0 || syy <= 0.0) return 0.0;
  return sxy / std::sqrt(sxx * syy);
}

}  // namespace dsdem::ensemble
