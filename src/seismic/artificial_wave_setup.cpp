#include "seismic/artificial_wave_setup.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>  // small LDLT only

#include "model/types.hpp"
#include "seismic/accelerogram.hpp"

namespace dsdem::seismic::detail {

namespace {

Oscillator make_oscillator(double period, double zeta, double dt, std::size_t n) {
  Oscillator o;
  o.omega = 2.0 * kPi / period;
  o.m = std::max(1, static_cast<int>(std::ceil(kSpectrumPointsPerPeriod * dt / period)));
  o.step = nigam_jennings_step(o.omega, zeta, dt / o.m);
  o.pad = free_vibration_samples(period, zeta, dt);
  o.H.assign((n + o.pad + 1) * static_cast<std::size_t>(o.m) + 1, 0.0);
  double x = 0.0, xd = 0.0;
  const double c1 = 2.0 * zeta * o.omega, c2 = o.omega * o.omega;
  const auto& k = o.step;
  for (std::size_t q = 1; q < o.H.size(); ++q) {
    // Unit hat: 0 at t = 0, 1 at t = dt, 0 at t = 2 dt (sub-step times q/m in samples).
    auto hat = [&](double s) { return std::max(0.0, 1.0 - std::abs(s - 1.0)); };
    const double g0 = hat(static_cast<double>(q - 1) / o.m), g1 = hat(static_cast<double>(q) / o.m);
    const double xn = k.a11 * x + k.a12 * xd + k.b11 * g0 + k.b12 * g1;
    const double vn = k.a21 * x + k.a22 * xd + k.b21 * g0 + k.b22 * g1;
    x = xn;
    xd = vn;
    o.H[q] = -(c1 * xd + c2 * x);
  }
  return o;
}

// Hat weights in log period: a bin of period T goes to the two nearest band centres
// (a partition of unity; the last band also owns every longer period).
void band_weights(const std::vector<double>& Tc, double T, std::size_t& j0, double& w0, double& w1) {
  w1 = 0.0;
  if (T <= Tc.front()) {
    j0 = 0;
    w0 = 1.0;
    return;
  }
  if (T >= Tc.back()) {
    j0 = Tc.size() - 1;
    w0 = 1.0;
    return;
  }
  const auto it = std::upper_bound(Tc.begin(), Tc.end(), T);
  j0 = static_cast<std::size_t>(it - Tc.begin()) - 1;
  w1 = std::log(T / Tc[j0]) / std::log(Tc[j0 + 1] / Tc[j0]);
  w0 = 1.0 - w1;
}

BaselineOperator make_baseline_operator(std::size_t n, double dt, int degree) {
  BaselineOperator B;
  B.n = n;
  B.m = static_cast<std::size_t>(degree) + 1;
  const double T = dt * static_cast<double>(n - 1);
  B.Phi.resize(n * B.m);
  for (std::size_t s = 0; s < n; ++s) {
    const double x = 2.0 * dt * static_cast<double>(s) / T - 1.0;
    double p0 = 1.0, p1 = x;
    for (std::size_t k = 0; k < B.m; ++k) {
      double pk = k == 0 ? 1.0 : (k == 1 ? x : 0.0);
      if (k >= 2) {
        pk = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / static_cast<double>(k);
        p0 = p1;
        p1 = pk;
      }
      B.Phi[s * B.m + k] = pk;
    }
  }
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(B.m), static_cast<Eigen::Index>(B.m));
  for (std::size_t s = 0; s < n; ++s)
    for (std::size_t i = 0; i < B.m; ++i)
      for (std::size_t j = 0; j < B.m; ++j) G(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) += B.Phi[s * B.m + i] * B.Phi[s * B.m + j];
  const auto Gf = G.ldlt();
  B.L.resize(B.m * n);
  std::vector<double> e(n, 0.0);
  for (std::size_t s = 0; s < n; ++s) {
    std::fill(e.begin(), e.end(), 0.0);
    e[s] = 1.0;
    const Accelerogram c = integrate(dt, e, BaselineOptions{true, degree});
    Eigen::VectorXd r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(B.m));
    for (std::size_t i = 0; i < n; ++i) {
      const double corr = e[i] - c.a[i];
      for (std::size_t k = 0; k < B.m; ++k) r[static_cast<Eigen::Index>(k)] += B.Phi[i * B.m + k] * corr;
    }
    const Eigen::VectorXd cs = Gf.solve(r);
    for (std::size_t k = 0; k < B.m; ++k) B.L[k * n + s] = cs[static_cast<Eigen::Index>(k)];
  }
  return B;
}

}  // namespace

std::vector<double> synthesise(const ArtificialWaveParams& P, const Setup& S, std::mt19937_64& rng) {
  const std::size_t n = S.n;
  const double T = P.dt * static_cast<double>(n - 1);
  const double df = 1.0 / (2.0 * T);
  const std::size_t K = static_cast<std::size_t>(std::floor(0.5 / P.dt / df + 1e-9));
  const double Td = P.t2 > P.t1 ? P.t2 - P.t1 : T;  // duration of the strong phase
  // Content longer than twice the longest control period is left out: nothing
  // controls it and the baseline correction would remove it anyway.
  const double longest = 2.0 * P.period_max;
  struct Term {
    double A, w, phase;
  };
  std::vector<Term> terms;
  for (std::size_t k = 1; k <= K; ++k) {
    const double f = df * static_cast<double>(k), w = 2.0 * kPi * f;
    const double phase = 2.0 * kPi * uniform01(rng);  // drawn for every k, used or not
    if (1.0 / f > longest) continue;
    const double A =
        std::sqrt(4.0 * spectrum_to_psd(P.spectrum.sa(1.0 / f), w, P.spectrum.damping, Td, P.exceedance) * 2.0 *
                  kPi * df);
    terms.push_back({A, w, phase});
  }
  // Each sample sums its cosines in frequency order, on any thread: the same bits.
  std::vector<double> a(n, 0.0);
  const auto ns = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t ii = 0; ii < ns; ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    double ai = 0.0;
    for (const Term& t : terms) ai += t.A * std::cos(t.w * P.dt * static_cast<double>(i) + t.phase);
    a[i] = ai * S.envelope[i];
  }
  return a;
}

Setup make_setup(const ArtificialWaveParams& P) {
  Setup S;
  S.n = static_cast<std::size_t>(std::floor(P.duration / P.dt + 1e-9)) + 1;
  const double T = P.dt * static_cast<double>(S.n - 1);
  S.base = make_baseline_operator(S.n, P.dt, P.baseline_degree);
  for (std::size_t i = 0; i < S.n; ++i)
    S.envelope.push_back(intensity_envelope(P.dt * static_cast<double>(i), P.t1, P.t2, P.c));
  // The control periods reach beyond period_max so that the last judged period is not
  // the edge of the matched band (where the fit is loosest).
  const double tmax = kControlReach * P.period_max;
  S.Tc = log_spaced(2.0 * P.dt, tmax, P.control_periods);
  for (double t : S.Tc) {
    S.target.push_back(P.spectrum.sa(t));
    S.osc.push_back(make_oscillator(t, P.spectrum.damping, P.dt, S.n));
  }
  // FFT grid zero-padded to at least 2n so that the corrections do not wrap around.
  S.N = 1;
  while (S.N < 2 * S.n) S.N *= 2;
  // Band centres: down in frequency from Nyquist by 4% steps, never closer than
  // 1/(4T), up to period_max.
  for (double f = 0.5 / P.dt; f > 1.0 / tmax; f -= std::max(0.04 * f, 0.25 / T)) S.band_T.push_back(1.0 / f);
  S.band_T.push_back(tmax);
  S.bin_band.assign(S.N / 2 + 1, 0);
  S.bin_w0.assign(S.N / 2 + 1, 0.0);
  S.bin_w1.assign(S.N / 2 + 1, 0.0);
  for (std::size_t b = 1; b <= S.N / 2; ++b)
    band_weights(S.band_T, static_cast<double>(S.N) * P.dt / static_cast<double>(b), S.bin_band[b], S.bin_w0[b],
                 S.bin_w1[b]);
  return S;
}

}  // namespace dsdem::seismic::detail
