#include "ensemble/sampling.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace dsdem::ensemble {

namespace {

constexpr double kPi = 3.14159265358979323846;

template <std::size_t N>
double poly(const double (&c)[N], double x) {
  double s = 0.0;
  for (std::size_t i = N; i-- > 0;) s = s * x + c[i];
  return s;
}

struct LognormalParams {
  double mu, sigma;
};
// ln X ~ N(mu, sigma^2) with E[X] = mean, sd[X] = sd.
LognormalParams lognormal_params(double mean, double sd) {
  const double s2 = std::log1p((sd / mean) * (sd / mean));
  return {std::log(mean) - 0.5 * s2, std::sqrt(s2)};
}

}  // namespace

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// Wichura, M. J. (1988), Algorithm AS241: the percentage points of the normal distribution.
double normal_quantile(double p) {
  if (!(p > 0.0)) return -std::numeric_limits<double>::infinity();
  if (!(p < 1.0)) return std::numeric_limits<double>::infinity();
  static const double a[] = {3.387132872796366608,   133.14166789178437745, 1971.5909503065514427,
                             13731.693765509461125,  45921.953931549871457, 67265.770927008700853,
                             33430.575583588128105,  2509.0809287301226727};
  static const double b[] = {1.0,                    42.313330701600911252, 687.1870074920579083,
                             5394.1960214247511077,  21213.794301586595867, 39307.89580009271061,
                             28729.085735721942674,  5226.495278852545925};
  static const double c[] = {1.42343711074968357734,  4.6303378461565452959,   5.7694972214606914055,
                             3.64784832476320460504,  1.27045825245236838258,  0.24178072517745061177,
                             0.0227238449892691845833, 7.7454501427834140764e-4};
  static const double d[] = {1.0,                     2.05319162663775882187,  1.6763848301838038494,
                             0.68976733498510000455,  0.14810397642748007459,  0.0151986665636164571966,
                             5.475938084995344946e-4, 1.05075007164441684324e-9};
  static const double e[] = {6.6579046435011037772,    5.4637849111641143699,    1.7848265399172913358,
                             0.29656057182850489123,   0.026532189526576123093,  0.0012426609473880784386,
                             2.71155556874348757815e-5, 2.01033439929228813265e-7};
  static const double f[] = {1.0,                       0.59983220655588793769,   0.13692988092273580531,
                             0.0148753612908506148525,  7.868691311456132591e-4,  1.8463183175100546818e-5,
                             1.4215117583164458887e-7,  2.04426310338993978564e-15};
  const double q = p - 0.5;
  if (std::fabs(q) <= 0.425) {
    const double r = 0.180625 - q * q;
    return q * poly(a, r) / poly(b, r);
  }
  double r = std::sqrt(-std::log(q < 0.0 ? p : 1.0 - p));
  double v;
  if (r <= 5.0) {
    r -= 1.6;
    v = poly(c, r) / poly(d, r);
  } else {
    r -= 5.0;
    v = poly(e, r) / poly(f, r);
  }
  return q < 0.0 ? -v : v;
}

double uniform01(std::mt19937_64& rng) {
  // (k + 0.5) / 2^53: the midpoints of 2^53 equal cells, never 0 or 1.
  return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
}

std::vector<std::size_t> permutation(std::size_t n, std::mt19937_64& rng) {
  std::vector<std::size_t> p(n);
  std::iota(p.begin(), p.end(), std::size_t{0});
  for (std::size_t i = n; i > 1; --i) {
    const auto j = std::min(i - 1, static_cast<std::size_t>(uniform01(rng) * static_cast<double>(i)));
    std::swap(p[i - 1], p[j]);
  }
  return p;
}

double Distribution::quantile(double u) const {
  switch (kind) {
    case DistributionKind::Uniform: return lower + u * (upper - lower);
    case DistributionKind::Normal: {
      const double pl = std::isfinite(lower) ? normal_cdf((lower - mean) / sd) : 0.0;
      const double ph = std::isfinite(upper) ? normal_cdf((upper - mean) / sd) : 1.0;
      const double x = mean + sd * normal_quantile(pl + u * (ph - pl));
      return std::clamp(x, lower, upper);
    }
    case DistributionKind::Lognormal: {
      const auto lp = lognormal_params(mean, sd);
      return std::exp(lp.mu + lp.sigma * normal_quantile(u));
    }
    case DistributionKind::Triangular: {
      const double w = upper - lower;
      const double fc = (mode - lower) / w;
      return u < fc ? lower + std::sqrt(u * w * (mode - lower)) : upper - std::sqrt((1.0 - u) * w * (upper - mode));
    }
    case DistributionKind::List: {
      double total = 0.0;
      for (std::size_t k = 0; k < choices; ++k) total += weights.empty() ? 1.0 : weights[k];
      double cum = 0.0;
      for (std::size_t k = 0; k < choices; ++k) {
        cum += weights.empty() ? 1.0 : weights[k];
        if (u * total < cum) return static_cast<double>(k);
      }
      return static_cast<double>(choices - 1);
    }
    case DistributionKind::Integer: {
      const double v = lower + std::floor(u * (upper - lower + 1.0));
      return std::min(v, upper);
    }
  }
  return 0.0;
}

double Distribution::exact_mean() const {
  switch (kind) {
    case DistributionKind::Uniform:
    case DistributionKind::Integer: return 0.5 * (lower + upper);
    case DistributionKind::Normal:
    case DistributionKind::Lognormal: return mean;
    case DistributionKind::Triangular: return (lower + mode + upper) / 3.0;
    case DistributionKind::List: {
      double total = 0.0, s = 0.0;
      for (std::size_t k = 0; k < choices; ++k) {
        const double w = weights.empty() ? 1.0 : weights[k];
        total += w;
        s += w * static_cast<double>(k);
      }
      return s / total;
    }
  }
  return 0.0;
}

double Distribution::exact_variance() const {
  switch (kind) {
    case DistributionKind::Uniform: return (upper - lower) * (upper - lower) / 12.0;
    case DistributionKind::Integer: {
      const double m = upper - lower + 1.0;
      return (m * m - 1.0) / 12.0;
    }
    case DistributionKind::Normal:
    case DistributionKind::Lognormal: return sd * sd;
    case DistributionKind::Triangular: {
      const double a = lower, b = upper, c = mode;
      return (a * a + b * b + c * c - a * b - a * c - b * c) / 18.0;
    }
    case DistributionKind::List: {
      const double m = exact_mean();
      double total = 0.0, s = 0.0;
      for (std::size_t k = 0; k < choices; ++k) {
        const double w = weights.empty() ? 1.0 : weights[k];
        total += w;
        s += w * (static_cast<double>(k) - m) * (static_cast<double>(k) - m);
      }
      return s / total;
    }
  }
  return 0.0;
}

std::string Distribution::check() const {
  auto finite = [](double v) { return std::isfinite(v); };
  switch (kind) {
    case DistributionKind::Uniform:
      if (!finite(lower) || !finite(upper)) return "lower and upper must be finite numbers";
      if (!(lower < upper)) return fmt::format("lower ({}) must be below upper ({})", lower, upper);
      return "";
    case DistributionKind::Integer:
      if (!finite(lower) || !finite(upper)) return "lower and upper must be finite integers";
      if (std::floor(lower) != lower || std::floor(upper) != upper)
        return fmt::format("lower ({}) and upper ({}) must be integers", lower, upper);
      if (!(lower <= upper)) return fmt::format("lower ({}) must not be above upper ({})", lower, upper);
      return "";
    case DistributionKind::Normal:
      if (!finite(mean)) return "mean must be a finite number";
      if (!(sd > 0.0) || !finite(sd)) return fmt::format("sd must be > 0, got {}", sd);
      if (!(lower < upper)) return fmt::format("lower ({}) must be below upper ({})", lower, upper);
      if (normal_cdf((upper - mean) / sd) - normal_cdf((lower - mean) / sd) < 1e-12)
        return fmt::format("[lower, upper] = [{}, {}] holds no probability of N({}, {}^2)", lower, upper, mean, sd);
      return "";
    case DistributionKind::Lognormal:
      if (!(mean > 0.0) || !finite(mean)) return fmt::format("mean must be > 0 (a lognormal value is positive), got {}", mean);
      if (!(sd > 0.0) || !finite(sd)) return fmt::format("sd must be > 0, got {}", sd);
      return "";
    case DistributionKind::Triangular:
      if (!finite(lower) || !finite(upper) || !finite(mode)) return "lower, mode and upper must be finite numbers";
      if (!(lower < upper)) return fmt::format("lower ({}) must be below upper ({})", lower, upper);
      if (mode < lower || mode > upper) return fmt::format("mode ({}) must lie in [lower, upper] = [{}, {}]", mode, lower, upper);
      return "";
    case DistributionKind::List: {
      if (choices == 0) return "values must list at least one choice";
      if (!weights.empty()) {
        if (weights.size() != choices)
          return fmt::format("weights has {} entries for {} values", weights.size(), choices);
        double total = 0.0;
        for (double w : weights) {
          if (!(w >= 0.0) || !finite(w)) return fmt::format("weights must be >= 0, got {}", w);
          total += w;
        }
        if (!(total > 0.0)) return "weights must not all be zero";
      }
      return "";
    }
  }
  return "";
}

std::string check_correlation(const std::vector<std::vector<double>>& c) {
  const std::size_t k = c.size();
  Eigen::MatrixXd m(k, k);
  for (std::size_t i = 0; i < k; ++i) {
    if (c[i].size() != k) return "the correlation matrix is not square";
    for (std::size_t j = 0; j < k; ++j) {
      if (!(std::fabs(c[i][j]) <= 1.0)) return fmt::format("a rank correlation must lie in [-1, 1], got {}", c[i][j]);
      if (c[i][j] != c[j][i]) return "the correlation matrix is not symmetric";
      m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = 2.0 * std::sin(kPi / 6.0 * c[i][j]);
    }
    if (c[i][i] != 1.0) return "the correlation matrix needs 1 on its diagonal";
  }
  Eigen::LLT<Eigen::MatrixXd> llt(m);
  if (llt.info() != Eigen::Success) return "the correlations are inconsistent (the matrix is not positive definite)";
  return "";
}

namespace {

// Iman & Conover (1982): scores with the target correlation, then each column of u put in
// the rank order of its scores.
void impose_rank_correlation(std::vector<std::vector<double>>& u, const std::vector<std::vector<double>>& target,
                             std::mt19937_64& rng) {
  const auto n = static_cast<Eigen::Index>(u.size());
  const auto k = static_cast<Eigen::Index>(target.size());
  if (n < k + 2) return;  // too few members to shape k columns (the file check says so)
  Eigen::MatrixXd r(n, k);
  for (Eigen::Index j = 0; j < k; ++j) {
    const auto p = permutation(static_cast<std::size_t>(n), rng);
    for (Eigen::Index i = 0; i < n; ++i)
      r(i, j) = normal_quantile(static_cast<double>(p[static_cast<std::size_t>(i)] + 1) / static_cast<double>(n + 1));
  }
  Eigen::MatrixXd centred = r.rowwise() - r.colwise().mean();
  Eigen::MatrixXd cov = centred.transpose() * centred / static_cast<double>(n - 1);
  Eigen::VectorXd inv_sd = cov.diagonal().cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd t = inv_sd.asDiagonal() * cov * inv_sd.asDiagonal();
  // Scores with Pearson correlation r have Spearman correlation (6/pi) asin(r/2) (Pearson 1907):
  // aim the scores at r = 2 sin(pi rho_s / 6).
  Eigen::MatrixXd c(k, k);
  for (Eigen::Index i = 0; i < k; ++i)
    for (Eigen::Index j = 0; j < k; ++j)
      c(i, j) = 2.0 * std::sin(kPi / 6.0 * target[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]);
  Eigen::LLT<Eigen::MatrixXd> lt(t), lc(c);
  if (lt.info() != Eigen::Success || lc.info() != Eigen::Success) return;
  const Eigen::MatrixXd q = lt.matrixL();
  const Eigen::MatrixXd p = lc.matrixL();
  const Eigen::MatrixXd s = p * q.inverse();
  const Eigen::MatrixXd scores = r * s.transpose();
  for (Eigen::Index j = 0; j < k; ++j) {
    std::vector<double> col(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i) col[static_cast<std::size_t>(i)] = u[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
    std::sort(col.begin(), col.end());
    std::vector<std::size_t> order(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return scores(static_cast<Eigen::Index>(a), j) < scores(static_cast<Eigen::Index>(b), j);
    });
    for (std::size_t rank = 0; rank < order.size(); ++rank) u[order[rank]][static_cast<std::size_t>(j)] = col[rank];
  }
}

}  // namespace

std::vector<std::vector<double>> sample_probabilities(std::size_t members, std::size_t variables,
                                                      SamplingMethod method, std::uint64_t seed,
                                                      const std::vector<std::vector<double>>& rank_correlation) {
  std::mt19937_64 rng(seed);
  std::vector<std::vector<double>> u(members, std::vector<double>(variables, 0.5));
  if (method == SamplingMethod::MonteCarlo) {
    for (auto& row : u)
      for (auto& x : row) x = uniform01(rng);
  } else {
    const double n = static_cast<double>(members);
    for (std::size_t j = 0; j < variables; ++j) {
      const auto p = permutation(members, rng);
      for (std::size_t i = 0; i < members; ++i) u[i][j] = (static_cast<double>(p[i]) + uniform01(rng)) / n;
    }
  }
  if (!rank_correlation.empty() && variables > 1) impose_rank_correlation(u, rank_correlation, rng);
  return u;
}

}  // namespace dsdem::ensemble
