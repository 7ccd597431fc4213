#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include <fmt/format.h>

#include "model/types.hpp"
#include "seismic/response_spectrum.hpp"

using namespace dsdem;
using namespace dsdem::seismic;

namespace {

// A broadband test record: a few sines plus seeded noise, dt = 0.02 s, 10 s.
std::vector<double> test_record() {
  std::mt19937_64 rng(42);
  std::vector<double> a(501);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double t = 0.02 * i;
    const double noise = static_cast<double>(rng() >> 11) * 0x1.0p-53 - 0.5;
    a[i] = std::sin(3.1 * t) + 0.5 * std::sin(17.0 * t + 0.3) + 0.3 * std::cos(61.0 * t) + 0.8 * noise;
  }
  return a;
}

// Reference: classical RK4 with 1000 sub-steps per sample on the same piecewise-linear
// input. Returns x, x', absolute acceleration at the samples and the max |abs acc|
// over every sub-step.
struct Reference {
  std::vector<double> x, xd, acc;
  double max_acc_fine = 0;
};
Reference rk4(const std::vector<double>& ag, double dt, double w, double z) {
  Reference r;
  const int m = 1000;
  const double h = dt / m;
  double x = 0, v = 0;
  r.x.push_back(0);
  r.xd.push_back(0);
  r.acc.push_back(0);
  for (std::size_t i = 0; i + 1 < ag.size(); ++i) {
    auto f = [&](double s, double xx, double vv) { return -(ag[i] + (ag[i + 1] - ag[i]) * s / dt) - 2 * z * w * vv - w * w * xx; };
    for (int k = 0; k < m; ++k) {
      const double s = k * h;
      const double k1x = v, k1v = f(s, x, v);
      const double k2x = v + h / 2 * k1v, k2v = f(s + h / 2, x + h / 2 * k1x, v + h / 2 * k1v);
      const double k3x = v + h / 2 * k2v, k3v = f(s + h / 2, x + h / 2 * k2x, v + h / 2 * k2v);
      const double k4x = v + h * k3v, k4v = f(s + h, x + h * k3x, v + h * k3v);
      x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
      r.max_acc_fine = std::max(r.max_acc_fine, std::abs(2 * z * w * v + w * w * x));
    }
    r.x.push_back(x);
    r.xd.push_back(v);
    r.acc.push_back(-(2 * z * w * v + w * w * x));
  }
  return r;
}

double rel_err(const std::vector<double>& a, const std::vector<double>& b) {
  double e = 0, m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    e = std::max(e, std::abs(a[i] - b[i]));
    m = std::max(m, std::abs(b[i]));
  }
  return e / m;
}

}  // namespace

// The Nigam-Jennings recurrence is exact for piecewise-linear input: it agrees with a
// 1000-sub-step RK4 (error ~1e-12) to 1e-6 relative, the bound.
TEST(ResponseSpectrum, NigamJenningsMatchesSubSteppedRk4) {
  const std::vector<double> ag = test_record();
  const double dt = 0.02;
  double worst = 0;
  for (double T : {0.04, 0.1, 0.35, 1.0, 6.0}) {
    for (double z : {0.0, 0.05, 0.2}) {
      const double w = 2 * kPi / T;
      const SdofHistory h = sdof_response(ag, dt, w, z);
      const Reference r = rk4(ag, dt, w, z);
      const double e = std::max({rel_err(h.x, r.x), rel_err(h.xd, r.xd), rel_err(h.abs_acc, r.acc)});
      EXPECT_LT(e, 1e-6) << "T = " << T << " zeta = " << z;
      worst = std::max(worst, e);
      // The spectral value looks at >= 50 points per period: its peak is the
      // continuous one to within 1 - cos(pi/50) = 0.2%.
      const SpectralValue sv = spectral_value(ag, dt, T, z);
      EXPECT_LE(sv.Sa, r.max_acc_fine * (1 + 1e-6)) << "T = " << T;
      EXPECT_GE(sv.Sa, r.max_acc_fine * (1 - 1 + std::cos(kPi / 50) - 1e-6)) << "T = " << T;
    }
  }
  RecordProperty("worst_relative_error", fmt::format("{:.3e}", worst));
}

// Harmonic ground motion a_g = A sin(W t) started on the steady state: the response
// is the steady state throughout. The only error is the linear interpolation of the
// sampled sine (1000 samples per cycle): (W dt)^2/12 ~ 3.3e-6 relative; 1e-5 asserted.
TEST(ResponseSpectrum, HarmonicSteadyState) {
  const double A = 0.7, W = 2 * kPi * 2.0, dt = (2 * kPi / W) / 1000;
  std::vector<double> ag(5001);
  for (std::size_t i = 0; i < ag.size(); ++i) ag[i] = A * std::sin(W * dt * i);
  for (double r : {0.5, 1.0, 2.0}) {
    for (double z : {0.05, 0.2}) {
      const double w = W / r;
      const std::complex<double> H = 1.0 / std::complex<double>(w * w - W * W, 2 * z * w * W);
      const std::complex<double> I(0, 1);
      auto x_ss = [&](double t) { return std::real(I * A * H * std::exp(I * W * t)); };
      auto v_ss = [&](double t) { return std::real(-A * H * W * std::exp(I * W * t)); };
      const SdofHistory h = sdof_response(ag, dt, w, z, x_ss(0), v_ss(0));
      const double amp_x = A * std::abs(H);
      const double amp_acc = A * std::abs(H) * std::sqrt(std::pow(w, 4) + 4 * z * z * w * w * W * W);
      double ex = 0, macc = 0;
      for (std::size_t i = 0; i < ag.size(); ++i) {
        ex = std::max(ex, std::abs(h.x[i] - x_ss(dt * i)));
        macc = std::max(macc, std::abs(h.abs_acc[i]));
      }
      EXPECT_LT(ex / amp_x, 1e-5) << "r = " << r << " zeta = " << z;
      EXPECT_NEAR(macc / amp_acc, 1.0, 1e-5) << "r = " << r << " zeta = " << z;
    }
  }
}

TEST(ResponseSpectrum, LimitsAndShape) {
  const std::vector<double> ag = test_record();
  double pga = 0;
  for (double a : ag) pga = std::max(pga, std::abs(a));
  const SpectralValue zero = spectral_value(ag, 0.02, 0.0, 0.05);
  EXPECT_DOUBLE_EQ(zero.Sa, pga);
  EXPECT_EQ(zero.Sd, 0.0);
  // A very stiff oscillator (T = dt/10) follows the ground: Sa -> PGA.
  EXPECT_NEAR(spectral_value(ag, 0.02, 0.002, 0.05).Sa / pga, 1.0, 0.02);
  const std::vector<double> T = log_spaced(0.05, 5.0, 30);
  ASSERT_EQ(T.size(), 30u);
  EXPECT_DOUBLE_EQ(T.front(), 0.05);
  EXPECT_DOUBLE_EQ(T.back(), 5.0);
  EXPECT_NEAR(T[1] / T[0], std::pow(100.0, 1.0 / 29), 1e-12);
  const ResponseSpectrum s = response_spectrum(ag, 0.02, T, 0.05);
  for (std::size_t j = 0; j < T.size(); ++j) {
    EXPECT_GT(s.Sa[j], 0);
    // At the peak of x, x' = 0 and the absolute acceleration is w^2 x: so w^2 Sd <= Sa,
    // up to the 0.2% sampling of the peaks.
    const double w = 2 * kPi / T[j];
    EXPECT_LE(w * w * s.Sd[j], s.Sa[j] * 1.002);
  }
}

// The free vibration after the record (SpectrumSpan::WithFreeVibration, Boore & Bommer
// 2005): a half-sine ground pulse a_g = A sin(W t), 0 <= t <= td = pi/W, on an undamped
// oscillator of period T > 2 td peaks after the pulse (Chopra, Dynamics of Structures,
// §4.8), at
//   Sa = w^2 u0 = 2 A W w |cos(w td / 2)| / |w^2 - W^2|,
// the free-vibration amplitude from x(td), x'(td). Over the record alone the peak is
// lower. The only errors: the sampled sine (1000 samples, (W dt)^2/12 ~ 1e-6) and the
// sub-step grid (<= 1 - cos(pi/50) = 0.2%, from below).
TEST(ResponseSpectrum, FreeVibrationOfAHalfSinePulse) {
  const double A = 0.8, td = 0.25, W = kPi / td, dt = td / 1000;
  std::vector<double> ag(1001);
  for (std::size_t i = 0; i < ag.size(); ++i) ag[i] = A * std::sin(W * dt * i);
  for (double T : {0.8, 1.0, 2.0, 6.0}) {
    const double w = 2 * kPi / T;
    const double exact = 2 * A * W * w * std::abs(std::cos(w * td / 2)) / std::abs(w * w - W * W);
    const SpectralValue free = spectral_value(ag, dt, T, 0.0, SpectrumSpan::WithFreeVibration);
    EXPECT_LE(free.Sa, exact * (1 + 1e-5)) << "T = " << T;
    EXPECT_GE(free.Sa, exact * (std::cos(kPi / 50) - 1e-5)) << "T = " << T;
    EXPECT_NEAR(free.Sd * w * w / exact, 1.0, 2.5e-3) << "T = " << T;  // undamped: Sa = w^2 Sd
    const SpectralValue record = spectral_value(ag, dt, T, 0.0);
    EXPECT_LT(record.Sa, 0.99 * free.Sa) << "T = " << T;
  }
  // The span is the record padded with free_vibration_samples() zeros: the same numbers as
  // a record padded by hand with five periods of zeros (with damping the later peaks are
  // lower), and the same spectrum through response_spectrum().
  const double T = 1.5, zeta = 0.05;
  EXPECT_EQ(free_vibration_samples(T, zeta, dt), 1 + static_cast<std::size_t>(std::ceil(T / std::sqrt(1 - zeta * zeta) / dt)));
  std::vector<double> padded = ag;
  padded.resize(ag.size() + static_cast<std::size_t>(5 * T / dt), 0.0);
  const SpectralValue by_hand = spectral_value(padded, dt, T, zeta);
  const SpectralValue span = spectral_value(ag, dt, T, zeta, SpectrumSpan::WithFreeVibration);
  EXPECT_EQ(span.Sa, by_hand.Sa);
  EXPECT_EQ(span.Sv, by_hand.Sv);
  EXPECT_EQ(span.Sd, by_hand.Sd);
  const std::vector<double> periods{0.0, 0.5, T};
  const ResponseSpectrum s = response_spectrum(ag, dt, periods, zeta, SpectrumSpan::WithFreeVibration);
  EXPECT_EQ(s.Sa[2], span.Sa);
  EXPECT_EQ(s.Sa[0], spectral_value(ag, dt, 0.0, zeta).Sa);  // period 0: the PGA either way
}

TEST(ResponseSpectrum, BadInputThrows) {
  const std::vector<double> ag = test_record();
  EXPECT_THROW(nigam_jennings_step(-1.0, 0.05, 0.01), std::runtime_error);
  EXPECT_THROW(nigam_jennings_step(1.0, 1.0, 0.01), std::runtime_error);
  EXPECT_THROW(nigam_jennings_step(1.0, 0.05, 0.0), std::runtime_error);
  EXPECT_THROW(spectral_value(ag, 0.02, -1.0, 0.05), std::runtime_error);
  EXPECT_THROW(log_spaced(1.0, 0.5, 10), std::runtime_error);
}
