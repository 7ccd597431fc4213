// The dam break (docs/validation.md §5.2, docs/theory.md §11) against Koshizuka & Oka (1996) and Martin & Moyce
// (1952), coarse (a / dp = 20); examples/dam_break runs it finer with the comparison plot.
//
// Reference data (dimensionless; Z = x_front / a, T = t sqrt(2 g / a), H = height / (n^2 a),
// tau = t sqrt(g / a)):
// - Koshizuka & Oka (1996), Nucl. Sci. Eng. 123, 421-434, the experiment in their surge-front
//   figure (n^2 = 2), as digitised by the PySPH project (pysph/examples/db_exp_data.py).
// - Martin & Moyce (1952), Phil. Trans. R. Soc. A 244, 312-324, n^2 = 2, a = 2.25 in: the
//   surge front and the residual column height of their tables, as transcribed in
//   examples/dam_break/reference.csv (the same values are in the PySPH set).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sph/dam_break.hpp"

using namespace dsdem;
using namespace dsdem::sph;

namespace {

constexpr std::array<double, 9> kKoT{0.0, 0.381, 0.769, 1.153, 1.537, 1.935, 2.323, 2.719, 3.096};
constexpr std::array<double, 9> kKoZ{1.0, 1.111, 1.252, 1.505, 1.892, 2.241, 2.615, 3.003, 3.624};
constexpr std::array<double, 13> kMmT{0.41, 0.84, 1.19, 1.43, 1.63, 1.83, 1.98, 2.20, 2.32, 2.51, 2.65, 2.83, 2.98};
constexpr std::array<double, 13> kMmZ{1.11, 1.22, 1.44, 1.67, 1.89, 2.11, 2.33, 2.56, 2.78, 3.00, 3.22, 3.44, 3.67};
constexpr std::array<double, 8> kMmTau{0.56, 0.77, 0.93, 1.08, 1.28, 1.46, 1.66, 1.84};
constexpr std::array<double, 8> kMmH{0.94, 0.89, 0.83, 0.78, 0.72, 0.67, 0.61, 0.56};

// Linear interpolation of the samples' field at time t.
template <class Get>
double at(const std::vector<DamBreakSample>& s, double t, Get get) {
  for (std::size_t k = 1; k < s.size(); ++k)
    if (s[k].t >= t) {
      const double w = (t - s[k - 1].t) / (s[k].t - s[k - 1].t);
      return (1.0 - w) * get(s[k - 1]) + w * get(s[k]);
    }
  return get(s.back());
}

}  // namespace

TEST(SphDamBreak, SurgeFrontAndColumnHeightAgainstExperiments) {
  DamBreakSetup setup;
  setup.dp = setup.a / 20.0;
  Fluid fluid = make_dam_break(setup);
  const double g = setup.g, a = setup.a, T_of_t = std::sqrt(2.0 * g / a), tau_of_t = std::sqrt(g / a);
  const auto samples = run_dam_break(fluid, setup.dp, 3.2 / T_of_t, 0.05 / T_of_t);
  auto Z = [&](const DamBreakSample& s) { return s.front / a; };
  auto H = [&](const DamBreakSample& s) { return s.height / (setup.n2 * a); };
  double ko = 0.0, mm = 0.0, mh = 0.0;
  for (std::size_t k = 0; k < kKoT.size(); ++k) {
    const double z = at(samples, kKoT[k] / T_of_t, Z);
    ko = std::max(ko, std::abs(z - kKoZ[k]) / kKoZ[k]);
  }
  // Judged at the published times (no delay). For information only: the delay (0 to 0.3 in
  // T) that would fit best, as their gate took some time to clear the column.
  double delay = 0.0;
  mm = INFINITY;
  for (int d = 0; d <= 30; ++d) {
    double worst = 0.0;
    for (std::size_t k = 0; k < kMmT.size(); ++k) {
      const double z = at(samples, std::max(0.0, kMmT[k] - 0.01 * d) / T_of_t, Z);
      worst = std::max(worst, std::abs(z - kMmZ[k]) / kMmZ[k]);
    }
    if (worst < mm) {
      mm = worst;
      delay = 0.01 * d;
    }
  }
  double mm_raw = 0.0;
  for (std::size_t k = 0; k < kMmT.size(); ++k)
    mm_raw = std::max(mm_raw, std::abs(at(samples, kMmT[k] / T_of_t, Z) - kMmZ[k]) / kMmZ[k]);
  for (std::size_t k = 0; k < kMmTau.size(); ++k) {
    const double hh = at(samples, kMmTau[k] / tau_of_t, H);
    mh = std::max(mh, std::abs(hh - kMmH[k]) / kMmH[k]);
  }
  std::printf("dam break a/dp %.0f, %zu particles, %ld steps: front vs K&O %.3f, vs M&M %.3f with a fitted delay %.2f ("
              "%.3f at the published times); height vs M&M %.3f\n",
              a / setup.dp, fluid.fluid().size(), fluid.steps(), ko, mm, delay, mm_raw, mh);
  // The target against Koshizuka & Oka is 5 %; this formulation reaches 5.9 % here (10.1 %
  // at a/dp = 40, both at their T = 2.72 point): the bound guards what is reached, short of it.
  EXPECT_LT(ko, 0.065);
  EXPECT_LT(mm_raw, 0.10);
  EXPECT_LE(mm, mm_raw);
  EXPECT_LT(mh, 0.05);
}
