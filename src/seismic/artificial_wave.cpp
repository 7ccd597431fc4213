#include "seismic/artificial_wave.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <complex>
#include <unsupported/Eigen/FFT>

#include <fmt/format.h>

#include "model/types.hpp"
#include "seismic/response_spectrum.hpp"

namespace dsdem::seismic {

void ArtificialWaveParams::validate() const {
  spectrum.validate();
  auto bad = [](const char* what, double value, const char* rule) {
    throw std::runtime_error(fmt::format("artificial wave: {} {}, got {}", what, rule, value));
  };
  if (!(dt > 0.0) || !std::isfinite(dt)) bad("dt", dt, "must be positive");
  if (!(duration >= 20.0 * dt) || !std::isfinite(duration)) bad("duration", duration, "must be at least 20 dt");
  if (!(t1 > 0.0)) bad("t1", t1, "must be positive");
  if (!(t2 >= t1)) bad("t2", t2, "must be >= t1");
  if (!(t2 <= duration)) bad("t2", t2, "must be <= the duration");
  if (!(c >= 0.0) || !std::isfinite(c)) bad("c", c, "must be >= 0");
  if (iterations < 0) bad("iterations", iterations, "must be >= 0");
  if (!(tolerance > 0.0)) bad("tolerance", tolerance, "must be positive");
  if (!(short_tolerance > 0.0)) bad("short_tolerance", short_tolerance, "must be positive");
  if (control_periods < 2) bad("control_periods", control_periods, "must be >= 2");
  if (!(period_max > 2.0 * dt)) bad("period_max", period_max, "must exceed 2 dt");
  if (!(exceedance > 0.0 && exceedance < 1.0)) bad("exceedance", exceedance, "must be in (0, 1)");
  if (baseline_degree < 1) bad("baseline_degree", baseline_degree, "must be >= 1");
}

double intensity_envelope(double t, double t1, double t2, double c) {
  if (t < 0.0) return 0.0;
  if (t < t1) return (t / t1) * (t / t1);
  if (t <= t2) return 1.0;
  return std::exp(-c * (t - t2));
}

double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

double spectrum_to_psd(double sa, double omega, double zeta, double Td, double p) {
  // The inner log is negative while pi/(w Td) * -ln(1-p) < 1; at the lowest frequencies
  // the formula breaks down, so the denominator is kept >= 1 (only a starting value:
  // the iteration corrects the amplitudes).
  const double x = -kPi / (omega * Td) * std::log(1.0 - p);
  const double denom = x < std::exp(-1.0) ? -std::log(x) : 1.0;
  return zeta / (kPi * omega) * sa * sa / denom;
}

namespace {

// Log-linear interpolation of the ratio r(T) at period T (held constant outside).
double interpolate_log(const std::vector<double>& T, const std::vector<double>& r, double t) {
  if (t <= T.front()) return r.front();
  if (t >= T.back()) return r.back();
  const auto it = std::upper_bound(T.begin(), T.end(), t);
  const std::size_t j = static_cast<std::size_t>(it - T.begin());
  const double s = std::log(t / T[j - 1]) / std::log(T[j] / T[j - 1]);
  return r[j - 1] + s * (r[j] - r[j - 1]);
}

// Scale down every half cycle (run of samples of one sign) whose peak exceeds limit so
// that its peak equals limit: a local, smooth way to bring the PGA to the target
// without flattening the peaks (which would add high-frequency content).
void limit_half_cycles(std::vector<double>& a, double limit) {
  std::size_t i = 0;
  const std::size_t n = a.size();
  while (i < n) {
    std::size_t j = i;
    double peak = 0.0;
    const bool positive = a[i] >= 0.0;
    while (j < n && (a[j] >= 0.0) == positive) {
      peak = std::max(peak, std::abs(a[j]));
      ++j;
    }
    if (peak > limit) {
      const double f = limit / peak;
      for (std::size_t k = i; k < j; ++k) a[k] *= f;
    }
    i = j;
  }
}

}  // namespace

ArtificialWave generate_artificial_wave(const ArtificialWaveParams& P) {
  P.validate();
  const std::size_t n = static_cast<std::size_t>(std::floor(P.duration / P.dt + 1e-9)) + 1;
  const double T = P.dt * static_cast<double>(n - 1);
  const double zeta = P.spectrum.damping;

  // Frequencies f_k = k df up to Nyquist; df = 1/(2T) gives twice as many amplitudes
  // to adjust as an FFT grid, which helps the long periods of a short record.
  const double df = 1.0 / ((std::getenv("AW_OS") ? std::atof(std::getenv("AW_OS")) : 2.0) * T);
  const std::size_t K = static_cast<std::size_t>(std::floor(0.5 / P.dt / df + 1e-9));
  std::mt19937_64 rng(P.seed);
  std::vector<double> omega(K), amp(K), period(K);
  // Basis: envelope * cos(w_k t + phase_k), one row per frequency.
  std::vector<double> basis(K * n);
  for (std::size_t k = 0; k < K; ++k) {
    const double f = df * static_cast<double>(k + 1);
    omega[k] = 2.0 * kPi * f;
    period[k] = 1.0 / f;
    const double phase = 2.0 * kPi * uniform01(rng);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = P.dt * static_cast<double>(i);
      basis[k * n + i] = intensity_envelope(t, P.t1, P.t2, P.c) * std::cos(omega[k] * t + phase);
    }
    // Stationary amplitude from the PSD over the strong phase: A = sqrt(4 S dw).
    const double Td = P.t2 - P.t1 > 0.0 ? P.t2 - P.t1 : T;
    const double cut = std::getenv("AW_CUT") ? std::atof(std::getenv("AW_CUT")) : 1e9;
    if (period[k] > cut * P.period_max) { amp[k] = 0.0; continue; }
    amp[k] = std::sqrt(4.0 * spectrum_to_psd(P.spectrum.sa(period[k]), omega[k], zeta, Td, P.exceedance) *
                       2.0 * kPi * df);
  }

  ArtificialWave out;
  out.control_period = log_spaced(2.0 * P.dt, P.period_max, P.control_periods);
  out.target_sa.resize(out.control_period.size());
  for (std::size_t j = 0; j < out.control_period.size(); ++j)
    out.target_sa[j] = P.spectrum.sa(out.control_period[j]);

  const BaselineOptions baseline{true, P.baseline_degree};
  std::vector<double> a(n), ratio(out.control_period.size());
  double best_score = std::numeric_limits<double>::infinity();
  std::vector<double> last_a;
  const bool use_fft = std::getenv("AW_FFT") != nullptr;
  std::size_t N = 1; while (N < 2 * n) N *= 2;
  Eigen::FFT<double> fft;
  std::vector<double> env(n);
  for (std::size_t i = 0; i < n; ++i) env[i] = intensity_envelope(P.dt * i, P.t1, P.t2, P.c);
  for (int it = 0;; ++it) {
    if (!use_fft || it == 0) {
    std::fill(a.begin(), a.end(), 0.0);
    for (std::size_t k = 0; k < K; ++k) {
      const double A = amp[k];
      const double* b = &basis[k * n];
      for (std::size_t i = 0; i < n; ++i) a[i] += A * b[i];
    }
    }
    if (!std::getenv("AW_NOCLIP")) limit_half_cycles(a, P.spectrum.pga);
    Accelerogram rec = integrate(P.dt, a, std::getenv("AW_NOBL") ? BaselineOptions{false, 3} : baseline);
    const double factor = std::getenv("AW_NOSCALE") ? 1.0 : P.spectrum.pga / rec.pga();
    scale(rec, factor);
    last_a = rec.a;
    const ResponseSpectrum s = response_spectrum(rec.a, P.dt, out.control_period, zeta);
    double mis = 0.0, mis_short = 0.0;
    for (std::size_t j = 0; j < ratio.size(); ++j) {
      ratio[j] = out.target_sa[j] / s.Sa[j];
      const double e = std::abs(s.Sa[j] / out.target_sa[j] - 1.0);
      (out.control_period[j] < 0.1 ? mis_short : mis) = std::max(out.control_period[j] < 0.1 ? mis_short : mis, e);
    }
    const double score = std::max(mis / P.tolerance, mis_short / P.short_tolerance);
    if (std::getenv("AW_DEBUG")) { std::fprintf(stderr, "it %d mis %.3f short %.3f factor %.3f\n", it, mis, mis_short, factor); for (std::size_t j = 0; j < ratio.size(); j += 6) std::fprintf(stderr, " %.2f", 1.0/ratio[j]); std::fprintf(stderr, "\n"); }
    if (score < best_score) {
      best_score = score;
      out.wave = std::move(rec);
      out.sa = s.Sa;
      out.max_misfit = mis;
      out.max_short_misfit = mis_short;
      out.iterations = it;
    }
    if (score <= 1.0 || it >= P.iterations) break;
    if (use_fft) {
      std::vector<double> x(N, 0.0);
      for (std::size_t i = 0; i < n; ++i) x[i] = out.wave.size() && false ? 0 : 0;
      const std::vector<double>& cur = (score == best_score) ? out.wave.a : a;  // placeholder
      (void)cur;
      for (std::size_t i = 0; i < n; ++i) x[i] = last_a[i];
      std::vector<std::complex<double>> X;
      fft.fwd(X, x);
      const double g = std::getenv("AW_G") ? std::atof(std::getenv("AW_G")) : 1.0;
      for (std::size_t b = 1; b < X.size(); ++b) {
        const std::size_t kk = b <= N / 2 ? b : N - b;
        const double Tb = N * P.dt / static_cast<double>(kk);
        const double r = Tb > P.period_max * (std::getenv("AW_CUT") ? std::atof(std::getenv("AW_CUT")) : 1.0) ? 0.0 : std::pow(interpolate_log(out.control_period, ratio, Tb), g);
        X[b] *= r;
      }
      X[0] = 0.0;
      std::vector<double> y;
      fft.inv(y, X);
      for (std::size_t i = 0; i < n; ++i) a[i] = y[i] * (std::getenv("AW_ENV") ? env[i] : 1.0);
      continue;
    }
    for (std::size_t k = 0; k < K; ++k) {
      // Beyond the longest control period nothing is measured: leave those amplitudes
      // (boosting them would only feed the drift that the baseline correction removes).
      const double r = period[k] > P.period_max && !std::getenv("AW_CUT") ? 1.0 : interpolate_log(out.control_period, ratio, period[k]);
      amp[k] *= factor * std::pow(r, std::getenv("AW_G") ? std::atof(std::getenv("AW_G")) : 1.0);
    }
  }
  return out;
}

}  // namespace dsdem::seismic
