#pragma once
// Sampling of an ensemble's varied values (docs/theory.md §13): distributions by their inverse
// CDF, Monte Carlo or Latin hypercube on (0, 1), rank correlation by Iman-Conover.
// Pure functions, no I/O. Reproducible bit for bit from the seed on every platform: the
// generator is std::mt19937_64 (fully specified by the standard) and every transform is
// written here (std::*_distribution and std::shuffle are implementation-defined).
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace dsdem::ensemble {

enum class DistributionKind { Uniform, Normal, Lognormal, Triangular, List, Integer };

struct Distribution {
  DistributionKind kind = DistributionKind::Uniform;
  // Uniform, Triangular, Integer: [lower, upper]; Normal: optional truncation to [lower, upper].
  double lower = 0.0, upper = 1.0;
  double mode = 0.0;            // Triangular
  double mean = 0.0, sd = 1.0;  // Normal, Lognormal (of the value itself, not of its logarithm)
  std::vector<double> weights;  // List: one per choice (all 1 when not given)
  std::size_t choices = 0;      // List: number of choices

  // The value at probability u in (0, 1): x = F^-1(u). A List gives the index of its choice.
  double quantile(double u) const;
  // Exact mean and variance (truncated normal: of the untruncated one), for tests and reports.
  double exact_mean() const;
  double exact_variance() const;
  // "" when the parameters are possible, else what is wrong (e.g. "sd must be > 0").
  std::string check() const;
};

// Standard normal: CDF and its inverse (Wichura's AS241, about 1e-16 relative).
double normal_cdf(double z);
double normal_quantile(double p);

// A uniform double in (0, 1) from 53 random bits, never 0 or 1.
double uniform01(std::mt19937_64& rng);
// Fisher-Yates with uniform01: the same permutation on every platform.
std::vector<std::size_t> permutation(std::size_t n, std::mt19937_64& rng);

enum class SamplingMethod { MonteCarlo, LatinHypercube };

// Probabilities u[member][variable] in (0, 1). Latin hypercube: every variable has exactly one
// member in each of the n strata [k/n, (k+1)/n). `rank_correlation` (variables x variables,
// symmetric, unit diagonal, positive definite) or empty: the columns are rearranged by
// Iman-Conover (1982) so that their Spearman correlation approaches it; each column keeps its
// values, so the marginals and the Latin hypercube stratification are untouched.
std::vector<std::vector<double>> sample_probabilities(std::size_t members, std::size_t variables,
                                                      SamplingMethod method, std::uint64_t seed,
                                                      const std::vector<std::vector<double>>& rank_correlation = {});

// "" when `c` is a valid correlation matrix (symmetric, unit diagonal, |c| <= 1, positive definite).
std::string check_correlation(const std::vector<std::vector<double>>& c);

}  // namespace dsdem::ensemble
