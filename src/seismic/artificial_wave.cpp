#include "seismic/artificial_wave.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>  // small LDLT only: no parallel GEMM, so results do not depend on threads
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
  if (fourier_iterations < 0) bad("fourier_iterations", fourier_iterations, "must be >= 0");
  if (attempts < 1) bad("attempts", attempts, "must be >= 1");
  if (!(accept_tolerance > 0.0)) bad("accept_tolerance", accept_tolerance, "must be positive");
  if (!(accept_short_tolerance > 0.0)) bad("accept_short_tolerance", accept_short_tolerance, "must be positive");
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

// Scale down every half cycle (run of samples of one sign) whose peak exceeds limit so
// that its peak equals limit: a local way to bring the PGA to the target without
// flattening peaks (clipping would add high-frequency content).
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

// One SDOF oscillator sub-stepped as in spectral_value(): its Nigam-Jennings step and
// the absolute-acceleration response H[q] (sub-step q) to a unit hat input at sample
// 1. By linearity the response at sub-step q to any input a is
// sum_s H[q - (s - 1) m] a[s], which gives the sensitivity of Sa to each band.
struct Oscillator {
  double omega = 0.0;
  int m = 1;  // sub-steps per sample
  NigamJenningsStep step{};
  std::vector<double> H;
};

Oscillator make_oscillator(double period, double zeta, double dt, std::size_t n) {
  Oscillator o;
  o.omega = 2.0 * kPi / period;
  o.m = std::max(1, static_cast<int>(std::ceil(kSpectrumPointsPerPeriod * dt / period)));
  o.step = nigam_jennings_step(o.omega, zeta, dt / o.m);
  o.H.assign((n + 1) * static_cast<std::size_t>(o.m) + 1, 0.0);
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

// Peak of |absolute acceleration| (= Sa), its sub-step index and sign.
struct Peak {
  double sa = 0.0;
  std::size_t q = 0;
  double sign = 1.0;
};

Peak peak_response(const Oscillator& o, const std::vector<double>& ag, double zeta) {
  Peak p;
  double x = 0.0, xd = 0.0;
  const double c1 = 2.0 * zeta * o.omega, c2 = o.omega * o.omega;
  const auto& k = o.step;
  for (std::size_t i = 1; i < ag.size(); ++i) {
    const double a0 = ag[i - 1], da = (ag[i] - ag[i - 1]) / o.m;
    for (int s = 0; s < o.m; ++s) {
      const double g0 = a0 + da * s, g1 = a0 + da * (s + 1);
      const double xn = k.a11 * x + k.a12 * xd + k.b11 * g0 + k.b12 * g1;
      const double vn = k.a21 * x + k.a22 * xd + k.b21 * g0 + k.b22 * g1;
      x = xn;
      xd = vn;
      const double y = -(c1 * xd + c2 * x);
      if (std::abs(y) > p.sa) {
        p.sa = std::abs(y);
        p.q = (i - 1) * static_cast<std::size_t>(o.m) + static_cast<std::size_t>(s) + 1;
        p.sign = y >= 0.0 ? 1.0 : -1.0;
      }
    }
  }
  return p;
}

// Sensitivity of oscillator o's response at sub-step q to each input sample.
void kernel_row(const Oscillator& o, std::size_t q, std::size_t n, double* row) {
  for (std::size_t s = 0; s < n; ++s) {
    const long idx = static_cast<long>(q) - (static_cast<long>(s) - 1) * o.m;
    row[s] = idx >= 0 && idx < static_cast<long>(o.H.size()) ? o.H[static_cast<std::size_t>(idx)] : 0.0;
  }
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

// target/Sa interpolated log-linearly at period T (held outside the control range).
double interpolate_ratio(const std::vector<double>& Tc, const std::vector<double>& target,
                         const std::vector<double>& sa, double T) {
  if (T <= Tc.front()) return target.front() / sa.front();
  if (T >= Tc.back()) return target.back() / sa.back();
  const auto it = std::upper_bound(Tc.begin(), Tc.end(), T);
  const std::size_t j = static_cast<std::size_t>(it - Tc.begin());
  const double s = std::log(T / Tc[j - 1]) / std::log(Tc[j] / Tc[j - 1]);
  return (1 - s) * target[j - 1] / sa[j - 1] + s * target[j] / sa[j];
}

// Dense column-major matrix with plain loops: the products here are done without
// Eigen's (OpenMP-parallel) GEMM so that the wave is bit-identical for any thread count.
struct Columns {
  std::size_t rows = 0, cols = 0;
  std::vector<double> v;
  void resize(std::size_t r, std::size_t c) {
    rows = r;
    cols = c;
    v.assign(r * c, 0.0);
  }
  double* col(std::size_t j) { return v.data() + j * rows; }
  const double* col(std::size_t j) const { return v.data() + j * rows; }
};

double dot(const double* a, const double* b, std::size_t n) {
  double s = 0.0;
  for (std::size_t i = 0; i < n; ++i) s += a[i] * b[i];
  return s;
}

// a . b[c] for four columns c, each summed in index order as dot() sums (the same bits):
// one chain of adds waits on itself, four independent chains do not (dot() dominates
// the wave's set-up).
void dot4(const double* a, const double* const b[4], std::size_t n, double out[4]) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double ai = a[i];
    s0 += ai * b[0][i];
    s1 += ai * b[1][i];
    s2 += ai * b[2][i];
    s3 += ai * b[3][i];
  }
  out[0] = s0;
  out[1] = s1;
  out[2] = s2;
  out[3] = s3;
}

// Least squares with Tikhonov regularisation:
//   min sum_r w_r^2 (A_r x - b_r)^2 + sum_j (mu d_j)^2 (x_j - x0_j)^2,
// d_j = the weighted column norm of A, by the normal equations and LDLT (small sizes).
Eigen::VectorXd regularised_solve(const std::vector<std::vector<double>>& A, const std::vector<double>& b,
                                  const std::vector<double>& w, double mu, const std::vector<double>& x0) {
  const std::size_t m = x0.size();
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(m));
  Eigen::VectorXd r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m));
  // Column i of the lower triangle (contiguous in column-major N; the upper triangle
  // along row i would stride by m) gets the rows' terms in row order: each column whole
  // on one thread, so any thread count gives the same bits.
  const auto ms = static_cast<std::ptrdiff_t>(m);
#pragma omp parallel for schedule(dynamic, 4)
  for (std::ptrdiff_t ci = 0; ci < ms; ++ci) {
    const auto i = static_cast<std::size_t>(ci);
    double* col_i = N.data() + ci * ms;
    double r_i = 0.0;
    for (std::size_t k = 0; k < A.size(); ++k) {
      const std::vector<double>& row = A[k];
      const double ri = w[k] * w[k] * row[i];
      if (ri == 0.0) continue;
      r_i += ri * b[k];
      for (std::size_t j = i; j < m; ++j) col_i[j] += ri * row[j];
    }
    r[ci] = r_i;
  }
  for (std::size_t i = 0; i < m; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    for (std::size_t j = i + 1; j < m; ++j) N(ii, static_cast<Eigen::Index>(j)) = N(static_cast<Eigen::Index>(j), ii);
    const double reg = mu * mu * std::max(N(ii, ii), 1e-300);
    N(ii, ii) += reg;
    r[ii] += reg * x0[i];
  }
  return N.ldlt().solve(r);
}

// The baseline correction is linear: a_c = a - Phi (L a), Phi the n x m polynomial
// basis, L (m x n) found once by correcting unit impulses. Lets the refinement correct
// its wavelets at the cost of m numbers each.
struct BaselineOperator {
  std::size_t n = 0, m = 0;
  std::vector<double> Phi;  // n x m, row s = basis at sample s
  std::vector<double> L;    // m x n, column s = coefficients for a unit impulse at s
};

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

// Constant data of one generation: control periods, oscillators, FFT bands.
struct Setup {
  BaselineOperator base;
  std::vector<double> envelope;  // intensity envelope at the samples
  std::size_t n = 0, N = 0;
  std::vector<double> Tc, target;
  std::vector<Oscillator> osc;
  std::vector<double> band_T;
  std::vector<std::size_t> bin_band;
  std::vector<double> bin_w0, bin_w1;
};

// Stationary sum of cosines with the target's PSD and seeded phases, times the
// intensity envelope; frequencies f_k = k/(2T) up to Nyquist (DESIGN.md §5).
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

struct Wavelet {
  std::size_t s0 = 0;    // first sample
  std::vector<double> v;  // values from s0 on
};

// One attempt from one set of phases: iterate, return the best iterate.
ArtificialWave attempt(const ArtificialWaveParams& P, const Setup& S, std::vector<double> a) {
  const std::size_t n = S.n, N = S.N, M = S.Tc.size(), Mb = S.band_T.size();
  const double zeta = P.spectrum.damping, pga = P.spectrum.pga;
  const BaselineOptions baseline{true, P.baseline_degree};
  Eigen::FFT<double> fft;
  ArtificialWave out;
  out.control_period = S.Tc;
  out.target_sa = S.target;
  double best_score = std::numeric_limits<double>::infinity();
  std::vector<double> sa(M), x(N), y;
  std::vector<Peak> peaks(M);
  std::vector<std::complex<double>> X, Xb;
  std::vector<std::vector<double>> K(M, std::vector<double>(n));
  Columns basis;
  std::vector<std::vector<double>> rows;
  std::vector<double> rhs, weight, x0;
  std::vector<Wavelet> wav;
  std::vector<double> wav_c;  // M x m baseline coefficients of the wavelets
  for (int it = 0;; ++it) {
    // Peak adjustment, baseline correction, exact PGA: every iterate is a valid wave.
    limit_half_cycles(a, pga);
    Accelerogram rec = integrate(P.dt, a, baseline);
    scale(rec, pga / rec.pga());

    // Response spectrum at the control periods and misfit.
    // Each oscillator on its own (any thread, the same bits); the misfit in period order.
    // Oscillators differ in sub-steps, hence dynamic chunks.
    const auto Ms = static_cast<std::ptrdiff_t>(M);
#pragma omp parallel for schedule(dynamic, 4)
    for (std::ptrdiff_t j = 0; j < Ms; ++j) peaks[j] = peak_response(S.osc[j], rec.a, zeta);
    double mis = 0.0, mis_short = 0.0;
    for (std::size_t j = 0; j < M; ++j) {
      sa[j] = peaks[j].sa;
      const double e = std::abs(sa[j] / S.target[j] - 1.0);
      (S.Tc[j] < 0.1 ? mis_short : mis) = std::max(S.Tc[j] < 0.1 ? mis_short : mis, e);
    }
    const double score = std::max(mis / P.tolerance, mis_short / P.short_tolerance);
    if (score < best_score) {
      best_score = score;
      out.wave = rec;
      out.sa = sa;
      out.max_misfit = mis;
      out.max_short_misfit = mis_short;
      out.iterations = it;
    }
    if (score <= 1.0 || it >= P.iterations) break;

    // Linearised peaks: Sa_i ~ s_i sum_s K_i[s] a[s] at the current peak times.
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < Ms; ++i) kernel_row(S.osc[i], peaks[i].q, n, K[i].data());

    const bool fourier = it < P.fourier_iterations;
    std::size_t cols = 0;
    if (fourier) {
      // Fourier-amplitude correction (GB 17741): the amplitudes of band j (phases
      // kept) are multiplied by a gain g_j. The classical gain is target_j / Sa_j;
      // since the peak at one period also sees the neighbouring bands, the gains are
      // solved together from s_i sum_j g_j y_i(band_j) = target_i, regularised
      // towards the classical ratios.
      cols = Mb;
      std::fill(x.begin(), x.end(), 0.0);
      std::copy(rec.a.begin(), rec.a.end(), x.begin());
      fft.fwd(X, x);
      basis.resize(n, Mb);
      for (std::size_t j = 0; j < Mb; ++j) {
        Xb.assign(X.size(), {0.0, 0.0});
        if (j == Mb - 1) Xb[0] = X[0];
        for (std::size_t b = 1; b <= N / 2; ++b) {
          double w = 0.0;
          if (S.bin_band[b] == j) w += S.bin_w0[b];
          if (S.bin_band[b] + 1 == j) w += S.bin_w1[b];
          if (w == 0.0) continue;
          Xb[b] = w * X[b];
          if (b != N - b) Xb[N - b] = std::conj(Xb[b]);
        }
        fft.inv(y, Xb);
        std::copy(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(n), basis.col(j));
      }
      x0.resize(Mb);
      for (std::size_t j = 0; j < Mb; ++j) x0[j] = interpolate_ratio(S.Tc, S.target, sa, S.band_T[j]);
    } else {
      // Refinement in time (after Abrahamson 1992, RspMatch): tapered-cosine wavelets,
      // one per control period, placed to act on that oscillator's peak (cut where
      // the taper is below e^-16). Each is baseline-corrected (psi - Phi L psi, the
      // correction being linear), so the wave stays corrected and the solve sees
      // what the wave will get.
      cols = M;
      const std::size_t m = S.base.m;
      const double s1 = std::sqrt(1.0 - zeta * zeta);
      wav.assign(M, {});
      wav_c.assign(M * m, 0.0);
      for (std::size_t j = 0; j < M; ++j) {
        const double wd = 2.0 * kPi / S.Tc[j] * s1;
        const double gamma = 1.178 * std::pow(S.Tc[j], 0.93);
        const double shift = std::atan(s1 / zeta) / wd;  // the response peak lags the wavelet
        const double tc = static_cast<double>(peaks[j].q) / S.osc[j].m * P.dt - shift;
        const double lo = std::max(0.0, std::ceil((tc - 4.0 * gamma) / P.dt));
        const double hi = std::min(static_cast<double>(n - 1), std::floor((tc + 4.0 * gamma) / P.dt));
        Wavelet& W = wav[j];
        W.s0 = static_cast<std::size_t>(lo);
        for (double si = lo; si <= hi; si += 1.0) {
          const double tau = P.dt * si - tc;
          W.v.push_back(std::cos(wd * tau) *
                        std::exp(-(tau / gamma) * (tau / gamma)));
        }
        for (std::size_t k = 0; k < m; ++k)
          wav_c[j * m + k] = dot(&S.base.L[k * n + W.s0], W.v.data(), W.v.size());
      }
      x0.assign(M, 0.0);
    }
    // Rows: the spectral peaks (relative to the target); in the refinement also the
    // samples near the PGA, kept in place so that the rescaling to the PGA stays ~1.
    // The kernels are causal: only samples up to the peak time count.
    rows.assign(M, std::vector<double>(cols));
    rhs.assign(M, 0.0);
    weight.assign(M, 0.0);
    const std::size_t m = S.base.m;
#pragma omp parallel for schedule(dynamic, 4)
    for (std::ptrdiff_t ii = 0; ii < Ms; ++ii) {  // each row on its own: the same bits on any thread
      const auto i = static_cast<std::size_t>(ii);
      const std::size_t last = std::min(n, peaks[i].q / static_cast<std::size_t>(S.osc[i].m) + 2);
      if (fourier) {
        std::size_t j = 0;
        for (; j + 4 <= cols; j += 4) {
          const double* const b[4] = {basis.col(j), basis.col(j + 1), basis.col(j + 2), basis.col(j + 3)};
          dot4(K[i].data(), b, last, &rows[i][j]);
        }
        for (; j < cols; ++j) rows[i][j] = dot(K[i].data(), basis.col(j), last);
      } else {
        double kphi[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        for (std::size_t s = 0; s < last; ++s)
          for (std::size_t k = 0; k < m && k < 8; ++k) kphi[k] += K[i][s] * S.base.Phi[s * m + k];
        for (std::size_t j = 0; j < cols; ++j) {
          const Wavelet& W = wav[j];
          const std::size_t e = std::min(last, W.s0 + W.v.size());
          double d = W.s0 < e ? dot(K[i].data() + W.s0, W.v.data(), e - W.s0) : 0.0;
          for (std::size_t k = 0; k < m && k < 8; ++k) d -= kphi[k] * wav_c[j * m + k];
          rows[i][j] = d;
        }
      }
      rhs[i] = fourier ? peaks[i].sign * S.target[i] : peaks[i].sign * (S.target[i] - sa[i]);
      weight[i] = 1.0 / S.target[i];
    }
    if (!fourier) {
      for (std::size_t s = 0; s < n; ++s) {
        if (std::abs(rec.a[s]) <= 0.9 * pga) continue;
        std::vector<double> row(cols);
        for (std::size_t j = 0; j < cols; ++j) {
          const Wavelet& W = wav[j];
          double v = s >= W.s0 && s < W.s0 + W.v.size() ? W.v[s - W.s0] : 0.0;
          for (std::size_t k = 0; k < m; ++k) v -= S.base.Phi[s * m + k] * wav_c[j * m + k];
          row[j] = v;
        }
        rows.push_back(std::move(row));
        rhs.push_back(0.0);
        weight.push_back(3.0 / pga);
      }
    }
    Eigen::VectorXd g = regularised_solve(rows, rhs, weight, fourier ? 0.3 : 0.03, x0);
    if (fourier) {
      // A poor linearisation (the peak moved) falls back to the plain ratio.
      for (std::size_t j = 0; j < Mb; ++j) {
        double& gj = g[static_cast<Eigen::Index>(j)];
        if (!std::isfinite(gj) || gj < 0.25 * x0[j] || gj > 4.0 * x0[j]) gj = x0[j];
      }
      X[0] *= g[static_cast<Eigen::Index>(Mb - 1)];
      for (std::size_t b = 1; b <= N / 2; ++b) {
        const std::size_t j = S.bin_band[b];
        double gain = S.bin_w0[b] * g[static_cast<Eigen::Index>(j)];
        if (S.bin_w1[b] > 0.0) gain += S.bin_w1[b] * g[static_cast<Eigen::Index>(j + 1)];
        X[b] *= gain;
        if (b != N - b) X[N - b] = std::conj(X[b]);
      }
      fft.inv(y, X);
      // The change is windowed by the intensity envelope so that the wave keeps its
      // shape in time (the band gains would otherwise spread energy to the ends).
      for (std::size_t i = 0; i < n; ++i) a[i] = rec.a[i] + S.envelope[i] * (y[i] - rec.a[i]);
    } else {
      std::vector<double> cb(m, 0.0);
      for (std::size_t j = 0; j < cols; ++j) {
        const double bj = g[static_cast<Eigen::Index>(j)];
        const Wavelet& W = wav[j];
        for (std::size_t k = 0; k < W.v.size(); ++k) rec.a[W.s0 + k] += bj * W.v[k];
        for (std::size_t k = 0; k < m; ++k) cb[k] += bj * wav_c[j * m + k];
      }
      for (std::size_t s = 0; s < n; ++s) {
        double p = 0.0;
        for (std::size_t k = 0; k < m; ++k) p += S.base.Phi[s * m + k] * cb[k];
        a[s] = rec.a[s] - p;
      }
    }
  }
  return out;
}

}  // namespace

ArtificialWave generate_artificial_wave(const ArtificialWaveParams& P) {
  P.validate();
  Setup S;
  S.n = static_cast<std::size_t>(std::floor(P.duration / P.dt + 1e-9)) + 1;
  const double T = P.dt * static_cast<double>(S.n - 1);
  S.base = make_baseline_operator(S.n, P.dt, P.baseline_degree);
  for (std::size_t i = 0; i < S.n; ++i)
    S.envelope.push_back(intensity_envelope(P.dt * static_cast<double>(i), P.t1, P.t2, P.c));
  S.Tc = log_spaced(2.0 * P.dt, P.period_max, P.control_periods);
  for (double t : S.Tc) {
    S.target.push_back(P.spectrum.sa(t));
    S.osc.push_back(make_oscillator(t, P.spectrum.damping, P.dt, S.n));
  }
  // FFT grid zero-padded to at least 2n so that the corrections do not wrap around.
  S.N = 1;
  while (S.N < 2 * S.n) S.N *= 2;
  // Band centres: down in frequency from Nyquist by 4% steps, never closer than
  // 1/(4T), up to period_max.
  for (double f = 0.5 / P.dt; f > 1.0 / P.period_max; f -= std::max(0.04 * f, 0.25 / T)) S.band_T.push_back(1.0 / f);
  S.band_T.push_back(P.period_max);
  S.bin_band.assign(S.N / 2 + 1, 0);
  S.bin_w0.assign(S.N / 2 + 1, 0.0);
  S.bin_w1.assign(S.N / 2 + 1, 0.0);
  for (std::size_t b = 1; b <= S.N / 2; ++b)
    band_weights(S.band_T, static_cast<double>(S.N) * P.dt / static_cast<double>(b), S.bin_band[b], S.bin_w0[b],
                 S.bin_w1[b]);

  // Attempts draw successive phase sets from one seeded stream; the first that meets
  // the acceptance tolerances is kept, else the best of all.
  std::mt19937_64 rng(P.seed);
  ArtificialWave best;
  double best_score = std::numeric_limits<double>::infinity();
  for (int k = 0; k < P.attempts; ++k) {
    ArtificialWave w = attempt(P, S, synthesise(P, S, rng));
    w.attempts = k + 1;
    // The misfit reported and judged is measured on a grid three times denser than
    // the control periods, so that narrow dips between them count too.
    const std::vector<double> dense = log_spaced(2.0 * P.dt, P.period_max, 3 * P.control_periods);
    const ResponseSpectrum ds = response_spectrum(w.wave.a, P.dt, dense, P.spectrum.damping);
    w.max_misfit = w.max_short_misfit = 0.0;
    for (std::size_t j = 0; j < dense.size(); ++j) {
      const double e = std::abs(ds.Sa[j] / P.spectrum.sa(dense[j]) - 1.0);
      double& m = dense[j] < 0.1 ? w.max_short_misfit : w.max_misfit;
      m = std::max(m, e);
    }
    const double score = std::max(w.max_misfit / P.accept_tolerance, w.max_short_misfit / P.accept_short_tolerance);
    if (score < best_score) {
      best_score = score;
      best = std::move(w);
    }
    if (best_score <= 1.0) break;
  }
  best.attempts = std::max(best.attempts, 1);
  return best;
}

}  // namespace dsdem::seismic
