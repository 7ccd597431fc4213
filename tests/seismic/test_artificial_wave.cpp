#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <random>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "common/same_bits.hpp"
#include "model/types.hpp"
#include "seismic/artificial_wave.hpp"
#include "seismic/response_spectrum.hpp"

using namespace dsdem;
using namespace dsdem::seismic;

namespace {

// The paper's case (docs/theory.md §5): beta spectrum, 0.05 g, Tg 0.35 s, dt 0.02 s, 10 s.
// Waves for seeds 1..3 are generated once for all tests of this file.
const ArtificialWave& wave(std::uint64_t seed) {
  static std::map<std::uint64_t, ArtificialWave> cache;
  auto it = cache.find(seed);
  if (it == cache.end()) {
    ArtificialWaveParams p;
    p.seed = seed;
    it = cache.emplace(seed, generate_artificial_wave(p)).first;
  }
  return it->second;
}

double worst_misfit(const ArtificialWave& w, const std::vector<double>& periods,
                    SpectrumSpan span = SpectrumSpan::Record) {
  const DesignSpectrum target;
  const ResponseSpectrum s = response_spectrum(w.wave.a, w.wave.dt, periods, 0.05, span);
  double e = 0;
  for (std::size_t j = 0; j < periods.size(); ++j) e = std::max(e, std::abs(s.Sa[j] / target.sa(periods[j]) - 1.0));
  return e;
}

}  // namespace

// The response spectrum is within +-10% of the target at 200 log-spaced periods from 0.1
// to 6 s and within +-20% from 0.04 to 0.1 s (20 log-spaced periods; dt = 0.02 s limits
// the shortest), PGA exact, for seeds 1..3 (1 is the Dr2 wave's): both over the record
// alone and with the oscillator's free vibration after it (the record padded with zeros,
// Boore & Bommer 2005), since a slope goes on moving after the shaking.
// scripts/wave_seeds.sh checks seeds 1..100 the same way (docs/artificial-wave-seeds.md).
TEST(ArtificialWave, MatchesTargetSpectrumForSeeds1To3WithAndWithoutFreeVibration) {
  const std::vector<double> mid = log_spaced(0.1, 6.0, 200), shortp = log_spaced(0.04, 0.1, 20);
  const double pga = 0.05 * kStandardGravity;
  double worst_mid = 0, worst_mid_free = 0, worst_short = 0;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const ArtificialWave& w = wave(seed);
    ASSERT_EQ(w.wave.size(), 501u);
    EXPECT_DOUBLE_EQ(w.wave.dt, 0.02);
    const double e_mid = worst_misfit(w, mid), e_short = worst_misfit(w, shortp);
    const double e_mid_free = worst_misfit(w, mid, SpectrumSpan::WithFreeVibration);
    EXPECT_LE(e_mid, 0.10) << "seed " << seed;
    EXPECT_LE(e_mid_free, 0.10) << "seed " << seed;
    EXPECT_LE(e_short, 0.20) << "seed " << seed;
    EXPECT_LE(worst_misfit(w, shortp, SpectrumSpan::WithFreeVibration), 0.20) << "seed " << seed;
    EXPECT_NEAR(w.wave.pga(), pga, 1e-12 * pga) << "seed " << seed;
    // The fit the generator reports is that of both spans on its dense grid.
    EXPECT_LE(std::max(w.fit_record.worst(), w.fit_free_vibration.worst()), 0.10) << "seed " << seed;
    EXPECT_LE(w.max_misfit, 0.10) << "seed " << seed;
    EXPECT_GE(w.fit_free_vibration.high, w.fit_record.high - 1e-15) << "seed " << seed;
    worst_mid = std::max(worst_mid, e_mid);
    worst_mid_free = std::max(worst_mid_free, e_mid_free);
    worst_short = std::max(worst_short, e_short);
  }
  RecordProperty("worst_misfit_0.1_6s", std::to_string(worst_mid));
  RecordProperty("worst_misfit_0.1_6s_free_vibration", std::to_string(worst_mid_free));
  RecordProperty("worst_misfit_0.04_0.1s", std::to_string(worst_short));
}

// The seed whose first four phase sets all missed 9 % (it ended at -10.6 % at 6 s with
// four): the generator draws phase sets until one fits, up to 8, and its 7th does.
TEST(ArtificialWave, ASeedThatNeedsMorePhaseSetsStillFits) {
  const ArtificialWave& w = wave(19);
  EXPECT_GT(w.attempts, 4);
  EXPECT_LE(w.max_misfit, ArtificialWaveParams{}.accept_tolerance);
  EXPECT_LE(std::max(w.fit_record.worst(), w.fit_free_vibration.worst()), 0.10);
}

// The wave is baseline-corrected: it ends at rest where it started, v and d consistent.
TEST(ArtificialWave, EndsAtRest) {
  for (std::uint64_t seed : {1u, 2u}) {
    const Accelerogram& r = wave(seed).wave;
    double vmax = 0, dmax = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      vmax = std::max(vmax, std::abs(r.v[i]));
      dmax = std::max(dmax, std::abs(r.d[i]));
    }
    EXPECT_LT(std::abs(r.v.back()), 1e-10 * vmax);
    EXPECT_LT(std::abs(r.d.back()), 1e-10 * dmax);
    // v is the trapezoidal integral of a.
    for (std::size_t i = 1; i < r.size(); ++i)
      ASSERT_NEAR(r.v[i] - r.v[i - 1], 0.5 * r.dt * (r.a[i] + r.a[i - 1]), 1e-12 * vmax);
  }
}

TEST(ArtificialWave, SameSeedSameWaveOtherSeedOtherWave) {
  ArtificialWaveParams p;
  p.seed = 3;
  const ArtificialWave again = generate_artificial_wave(p);
  ASSERT_EQ(again.wave.a.size(), wave(3).wave.a.size());
  for (std::size_t i = 0; i < again.wave.a.size(); ++i) ASSERT_EQ(again.wave.a[i], wave(3).wave.a[i]);  // bit-identical
  double diff = 0, norm = 0;
  for (std::size_t i = 0; i < again.wave.a.size(); ++i) {
    diff = std::max(diff, std::abs(wave(3).wave.a[i] - wave(2).wave.a[i]));
    norm = std::max(norm, std::abs(wave(3).wave.a[i]));
  }
  EXPECT_GT(diff, 0.2 * norm);
}

// The phases' cosines, the oscillators, the linearised rows, the normal equations and
// the dense misfit check run on OpenMP threads (the wave is generated at every
// run's set-up and restart). Each item is computed whole by one thread, so the wave is
// the same bit for bit on 1 and 2 threads.
TEST(ArtificialWave, SameWaveOnOneAndTwoThreads) {
  ArtificialWaveParams p;
  p.seed = 2;
#ifdef _OPENMP
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
#endif
  const ArtificialWave one = generate_artificial_wave(p);
#ifdef _OPENMP
  omp_set_num_threads(2);
#endif
  const ArtificialWave two = generate_artificial_wave(p);
#ifdef _OPENMP
  omp_set_num_threads(before);
#endif
  ASSERT_EQ(one.wave.a.size(), two.wave.a.size());
  for (std::size_t i = 0; i < one.wave.a.size(); ++i)
    ASSERT_TRUE(test::same_bits(one.wave.a[i], two.wave.a[i])) << "sample " << i << ": " << one.wave.a[i] << " / "
                                                               << two.wave.a[i];
  EXPECT_EQ(one.iterations, two.iterations);
  EXPECT_EQ(one.attempts, two.attempts);
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a of the bits, printed to compare builds
  for (double a : one.wave.a) {
    std::uint64_t u;
    std::memcpy(&u, &a, sizeof u);
    h = (h ^ u) * 1099511628211ull;
  }
  std::printf("seed-2 wave: %zu samples, bits hash %016llx\n", one.wave.a.size(), static_cast<unsigned long long>(h));
}

TEST(ArtificialWave, GbSpectrumAndOtherDamping) {
  ArtificialWaveParams p;
  p.spectrum.kind = DesignSpectrumKind::Gb50011Alpha;
  p.spectrum.damping = 0.03;
  p.seed = 7;
  const ArtificialWave w = generate_artificial_wave(p);
  const std::vector<double> mid = log_spaced(0.1, 6.0, 50);
  const ResponseSpectrum s = response_spectrum(w.wave.a, w.wave.dt, mid, 0.03);
  for (std::size_t j = 0; j < mid.size(); ++j) EXPECT_NEAR(s.Sa[j] / p.spectrum.sa(mid[j]), 1.0, 0.10) << mid[j];
  EXPECT_NEAR(w.wave.pga(), p.spectrum.pga, 1e-12 * p.spectrum.pga);
}

TEST(ArtificialWave, Kernels) {
  EXPECT_EQ(intensity_envelope(-1.0, 1.5, 6.5, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(intensity_envelope(0.75, 1.5, 6.5, 1.0), 0.25);
  EXPECT_DOUBLE_EQ(intensity_envelope(3.0, 1.5, 6.5, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(intensity_envelope(8.5, 1.5, 6.5, 1.0), std::exp(-2.0));
  // uniform01 uses the raw 64-bit output: the top 53 bits over 2^53.
  std::mt19937_64 a(11), b(11);
  for (int i = 0; i < 100; ++i) {
    const double u = uniform01(a);
    const std::uint64_t raw = b();
    EXPECT_EQ(u, static_cast<double>(raw >> 11) / 9007199254740992.0);
    EXPECT_GE(u, 0.0);
    EXPECT_LT(u, 1.0);
  }
  // PSD: zeta/(pi w) Sa^2 / (-ln(-pi/(w Td) ln(1-p))), by hand for w = 10, Td = 5, p = 0.15.
  const double x = -kPi / 50.0 * std::log(0.85);
  EXPECT_NEAR(spectrum_to_psd(2.0, 10.0, 0.05, 5.0, 0.15), 0.05 / (kPi * 10.0) * 4.0 / (-std::log(x)), 1e-15);
}

TEST(ArtificialWave, BadParametersThrow) {
  ArtificialWaveParams p;
  p.dt = -0.02;
  EXPECT_THROW(generate_artificial_wave(p), std::runtime_error);
  p = ArtificialWaveParams{};
  p.t2 = 0.5;  // before t1
  EXPECT_THROW(generate_artificial_wave(p), std::runtime_error);
  p = ArtificialWaveParams{};
  p.spectrum.pga = 0.0;
  EXPECT_THROW(generate_artificial_wave(p), std::runtime_error);
}
