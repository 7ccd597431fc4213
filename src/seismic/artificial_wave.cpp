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
#include "seismic/artificial_wave_setup.hpp"
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
  if (stall_iterations < 1) bad("stall_iterations", stall_iterations, "must be >= 1");
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

SpectralFit spectral_fit(const ResponseSpectrum& s, const DesignSpectrum& target, double t_min) {
  SpectralFit f;
  bool first = true;
  for (std::size_t j = 0; j < s.period.size(); ++j) {
    if (s.period[j] < t_min) continue;
    const double e = s.Sa[j] / target.sa(s.period[j]) - 1.0;
    if (first || e < f.low) f.low = e, f.T_low = s.period[j];
    if (first || e > f.high) f.high = e, f.T_high = s.period[j];
    first = false;
  }
  return f;
}

namespace {

using detail::Oscillator;

// A free-vibration peak above this fraction of the target is aimed at too.
constexpr double kTailAim = 0.95;
// Free-vibration peaks above this fraction of the target are bounded by it.
constexpr double kTailBound = 0.5;
constexpr int kBoundRounds = 3;
using detail::Setup;

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

// Peak of |absolute acceleration| (= Sa), its sub-step index and sign.
struct Peak {
  double sa = 0.0;
  std::size_t q = 0;
  double sign = 1.0;
};

// The peaks over the record and over the free vibration after it (the record padded
// with o.pad zeros, as spectral_value() with SpectrumSpan::WithFreeVibration).
struct Peaks {
  Peak record, tail;
};

Peaks peak_response(const Oscillator& o, const std::vector<double>& ag, double zeta) {
  Peaks p;
  double x = 0.0, xd = 0.0;
  const double c1 = 2.0 * zeta * o.omega, c2 = o.omega * o.omega;
  const auto& k = o.step;
  const std::size_t n = ag.size();
  auto at = [&](std::size_t i) { return i < n ? ag[i] : 0.0; };
  for (std::size_t i = 1; i < n + o.pad; ++i) {
    Peak& pk = i < n ? p.record : p.tail;
    const double a0 = at(i - 1), da = (at(i) - at(i - 1)) / o.m;
    for (int s = 0; s < o.m; ++s) {
      const double g0 = a0 + da * s, g1 = a0 + da * (s + 1);
      const double xn = k.a11 * x + k.a12 * xd + k.b11 * g0 + k.b12 * g1;
      const double vn = k.a21 * x + k.a22 * xd + k.b21 * g0 + k.b22 * g1;
      x = xn;
      xd = vn;
      const double y = -(c1 * xd + c2 * x);
      if (std::abs(y) > pk.sa) {
        pk.sa = std::abs(y);
        pk.q = (i - 1) * static_cast<std::size_t>(o.m) + static_cast<std::size_t>(s) + 1;
        pk.sign = y >= 0.0 ? 1.0 : -1.0;
      }
    }
  }
  return p;
}

// A peak the correction aims at: oscillator j's peak p brought to goal, or, for a bound,
// kept at or below it (the free vibration's peaks). A wavelet is placed on the aims that
// own one.
struct Aim {
  std::size_t j = 0;
  Peak p;
  double goal = 0.0;
  bool bound = false;
  bool wavelet = true;
};

// Sensitivity of oscillator o's response at sub-step q to each input sample.
void kernel_row(const Oscillator& o, std::size_t q, std::size_t n, double* row) {
  for (std::size_t s = 0; s < n; ++s) {
    const long idx = static_cast<long>(q) - (static_cast<long>(s) - 1) * o.m;
    row[s] = idx >= 0 && idx < static_cast<long>(o.H.size()) ? o.H[static_cast<std::size_t>(idx)] : 0.0;
  }
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

struct Wavelet {
  std::size_t s0 = 0;    // first sample
  std::vector<double> v;  // values from s0 on
};

// Buffers of one attempt, reused from iteration to iteration.
struct Workspace {
  Eigen::FFT<double> fft;
  std::vector<double> sa, sa_free, sa_eff, x, y;  // at the control periods: record, with free vibration, aimed
  std::vector<Peaks> peaks;
  std::vector<Aim> aims;
  std::vector<std::complex<double>> X, Xb;
  std::vector<std::vector<double>> K;
  Columns basis;
  std::vector<std::vector<double>> rows;
  std::vector<double> rhs, weight, x0;
  std::vector<Wavelet> wav;
  std::vector<double> wav_c;  // M x m baseline coefficients of the wavelets
  explicit Workspace(const Setup& S)
      : sa(S.Tc.size()), sa_free(S.Tc.size()), sa_eff(S.Tc.size()), x(S.N), peaks(S.Tc.size()) {}
};

// Response spectra of rec at the control periods, over the record and with the free
// vibration after it, and their misfits (long, short periods; the worse of the two
// spans). Each oscillator on its own (any thread, the same bits); the misfit in period
// order. Oscillators differ in sub-steps, hence dynamic chunks.
void measure(const ArtificialWaveParams& P, const Setup& S, const Accelerogram& rec, Workspace& ws, double& mis,
             double& mis_short) {
  const std::size_t M = S.Tc.size();
  const auto Ms = static_cast<std::ptrdiff_t>(M);
#pragma omp parallel for schedule(dynamic, 4)
  for (std::ptrdiff_t j = 0; j < Ms; ++j) ws.peaks[j] = peak_response(S.osc[j], rec.a, P.spectrum.damping);
  mis = 0.0;
  mis_short = 0.0;
  ws.aims.clear();
  for (std::size_t j = 0; j < M; ++j) {
    const Peaks& pk = ws.peaks[j];
    const double t = S.target[j];
    ws.sa[j] = pk.record.sa;
    ws.sa_free[j] = std::max(pk.record.sa, pk.tail.sa);
    const double e = std::max(std::abs(ws.sa[j] / t - 1.0), std::abs(ws.sa_free[j] / t - 1.0));
    if (S.Tc[j] <= P.period_max * (1 + 1e-12))
      (S.Tc[j] < 0.1 ? mis_short : mis) = std::max(S.Tc[j] < 0.1 ? mis_short : mis, e);
    // The record's peak is brought to the target; the free vibration's, from half the
    // target on, is bounded by it (and gets a wavelet of its own once near it). The ratio
    // for the Fourier gains is the padded peak's if it is above the target, the record's
    // if both are below, and their geometric mean if they straddle it.
    ws.aims.push_back({j, pk.record, t, false, true});
    if (pk.tail.sa > kTailBound * t) ws.aims.push_back({j, pk.tail, t, true, pk.tail.sa > kTailAim * t});
    const double R = ws.sa[j], F = ws.sa_free[j];
    ws.sa_eff[j] = F <= t ? R : (R >= t ? F : std::sqrt(R * F));
  }
}

// Fourier-amplitude correction (GB 17741): the amplitudes of band j (phases kept) are
// multiplied by a gain g_j. The classical gain is target_j / Sa_j; since the peak at one
// period also sees the neighbouring bands, the gains are solved together from
// s_i sum_j g_j y_i(band_j) = target_i, regularised towards the classical ratios.
// Fills the band signals y(band_j) as the columns; returns their number.
std::size_t band_columns(const Setup& S, const Accelerogram& rec, Workspace& ws) {
  const std::size_t n = S.n, N = S.N, Mb = S.band_T.size();
  std::fill(ws.x.begin(), ws.x.end(), 0.0);
  std::copy(rec.a.begin(), rec.a.end(), ws.x.begin());
  ws.fft.fwd(ws.X, ws.x);
  ws.basis.resize(n, Mb);
  for (std::size_t j = 0; j < Mb; ++j) {
    ws.Xb.assign(ws.X.size(), {0.0, 0.0});
    if (j == Mb - 1) ws.Xb[0] = ws.X[0];
    for (std::size_t b = 1; b <= N / 2; ++b) {
      double w = 0.0;
      if (S.bin_band[b] == j) w += S.bin_w0[b];
      if (S.bin_band[b] + 1 == j) w += S.bin_w1[b];
      if (w == 0.0) continue;
      ws.Xb[b] = w * ws.X[b];
      if (b != N - b) ws.Xb[N - b] = std::conj(ws.Xb[b]);
    }
    ws.fft.inv(ws.y, ws.Xb);
    std::copy(ws.y.begin(), ws.y.begin() + static_cast<std::ptrdiff_t>(n), ws.basis.col(j));
  }
  ws.x0.resize(Mb);
  for (std::size_t j = 0; j < Mb; ++j) ws.x0[j] = interpolate_ratio(S.Tc, S.target, ws.sa_eff, S.band_T[j]);
  return Mb;
}

// Refinement in time (after Abrahamson 1992, RspMatch): tapered-cosine wavelets, one per
// control period, placed to act on that oscillator's peak (cut where the taper is below
// e^-16). Each is baseline-corrected (psi - Phi L psi, the correction being linear), so
// the wave stays corrected and the solve sees what the wave will get. Returns the
// number of wavelets.
std::size_t wavelet_columns(const ArtificialWaveParams& P, const Setup& S, Workspace& ws) {
  const std::size_t n = S.n, m = S.base.m;
  const double zeta = P.spectrum.damping;
  const double s1 = std::sqrt(1.0 - zeta * zeta);
  ws.wav.clear();
  for (const Aim& aim : ws.aims) {
    if (!aim.wavelet) continue;
    const std::size_t r = ws.wav.size(), j = aim.j;
    ws.wav.emplace_back();
    ws.wav_c.resize(ws.wav.size() * m);
    const double wd = 2.0 * kPi / S.Tc[j] * s1;
    const double gamma = 1.178 * std::pow(S.Tc[j], 0.93);
    const double shift = std::atan(s1 / zeta) / wd;  // the response peak lags the wavelet
    const double tc = static_cast<double>(aim.p.q) / S.osc[j].m * P.dt - shift;
    const double lo = std::max(0.0, std::ceil((tc - 4.0 * gamma) / P.dt));
    const double hi = std::min(static_cast<double>(n - 1), std::floor((tc + 4.0 * gamma) / P.dt));
    Wavelet& W = ws.wav[r];
    W.s0 = static_cast<std::size_t>(lo);
    for (double si = lo; si <= hi; si += 1.0) {
      const double tau = P.dt * si - tc;
      W.v.push_back(std::cos(wd * tau) *
                    std::exp(-(tau / gamma) * (tau / gamma)));
    }
    for (std::size_t k = 0; k < m; ++k)
      ws.wav_c[r * m + k] = dot(&S.base.L[k * n + W.s0], W.v.data(), W.v.size());
  }
  ws.x0.assign(ws.wav.size(), 0.0);
  return ws.wav.size();
}

// Rows: the spectral peaks (relative to the target); in the refinement also the samples
// near the PGA, kept in place so that the rescaling to the PGA stays ~1. The kernels
// are causal: only samples up to the peak time count.
void build_rows(const ArtificialWaveParams& P, const Setup& S, const Accelerogram& rec, bool fourier,
                std::size_t cols, Workspace& ws) {
  const std::size_t n = S.n, M = ws.aims.size(), m = S.base.m;
  const auto Ms = static_cast<std::ptrdiff_t>(M);
  ws.rows.assign(M, std::vector<double>(cols));
  ws.rhs.assign(M, 0.0);
  ws.weight.assign(M, 0.0);
#pragma omp parallel for schedule(dynamic, 4)
  for (std::ptrdiff_t ii = 0; ii < Ms; ++ii) {  // each row on its own: the same bits on any thread
    const auto i = static_cast<std::size_t>(ii);
    const Aim& aim = ws.aims[i];
    const std::size_t last = std::min(n, aim.p.q / static_cast<std::size_t>(S.osc[aim.j].m) + 2);
    std::vector<double>& row = ws.rows[i];
    const double* Ki = ws.K[i].data();
    if (fourier) {
      std::size_t j = 0;
      for (; j + 4 <= cols; j += 4) {
        const double* const b[4] = {ws.basis.col(j), ws.basis.col(j + 1), ws.basis.col(j + 2), ws.basis.col(j + 3)};
        dot4(Ki, b, last, &row[j]);
      }
      for (; j < cols; ++j) row[j] = dot(Ki, ws.basis.col(j), last);
    } else {
      double kphi[8] = {0, 0, 0, 0, 0, 0, 0, 0};
      for (std::size_t s = 0; s < last; ++s)
        for (std::size_t k = 0; k < m && k < 8; ++k) kphi[k] += Ki[s] * S.base.Phi[s * m + k];
      for (std::size_t j = 0; j < cols; ++j) {
        const Wavelet& W = ws.wav[j];
        const std::size_t e = std::min(last, W.s0 + W.v.size());
        double d = W.s0 < e ? dot(Ki + W.s0, W.v.data(), e - W.s0) : 0.0;
        for (std::size_t k = 0; k < m && k < 8; ++k) d -= kphi[k] * ws.wav_c[j * m + k];
        row[j] = d;
      }
    }
    ws.rhs[i] = aim.p.sign * (fourier ? aim.goal : aim.goal - aim.p.sa);
    // A bound counts only while it is broken (see correct()).
    ws.weight[i] = aim.bound && aim.p.sa <= aim.goal ? 0.0 : 1.0 / S.target[aim.j];
  }
  if (fourier) return;
  const double pga = P.spectrum.pga;
  for (std::size_t s = 0; s < n; ++s) {
    if (std::abs(rec.a[s]) <= 0.9 * pga) continue;
    std::vector<double> row(cols);
    for (std::size_t j = 0; j < cols; ++j) {
      const Wavelet& W = ws.wav[j];
      double v = s >= W.s0 && s < W.s0 + W.v.size() ? W.v[s - W.s0] : 0.0;
      for (std::size_t k = 0; k < m; ++k) v -= S.base.Phi[s * m + k] * ws.wav_c[j * m + k];
      row[j] = v;
    }
    ws.rows.push_back(std::move(row));
    ws.rhs.push_back(0.0);
    ws.weight.push_back(3.0 / pga);
  }
}

// The band gains g applied to rec's spectrum; the next iterate into a.
void apply_band_gains(const Setup& S, const Accelerogram& rec, Eigen::VectorXd& g, Workspace& ws,
                      std::vector<double>& a) {
  const std::size_t n = S.n, N = S.N, Mb = S.band_T.size();
  // A poor linearisation (the peak moved) falls back to the plain ratio.
  for (std::size_t j = 0; j < Mb; ++j) {
    double& gj = g[static_cast<Eigen::Index>(j)];
    if (!std::isfinite(gj) || gj < 0.25 * ws.x0[j] || gj > 4.0 * ws.x0[j]) gj = ws.x0[j];
  }
  ws.X[0] *= g[static_cast<Eigen::Index>(Mb - 1)];
  for (std::size_t b = 1; b <= N / 2; ++b) {
    const std::size_t j = S.bin_band[b];
    double gain = S.bin_w0[b] * g[static_cast<Eigen::Index>(j)];
    if (S.bin_w1[b] > 0.0) gain += S.bin_w1[b] * g[static_cast<Eigen::Index>(j + 1)];
    ws.X[b] *= gain;
    if (b != N - b) ws.X[N - b] = std::conj(ws.X[b]);
  }
  ws.fft.inv(ws.y, ws.X);
  // The change is windowed by the intensity envelope so that the wave keeps its
  // shape in time (the band gains would otherwise spread energy to the ends).
  for (std::size_t i = 0; i < n; ++i) a[i] = rec.a[i] + S.envelope[i] * (ws.y[i] - rec.a[i]);
}

// The wavelets, weighted by g, added to rec with their baseline correction; the next
// iterate into a.
void apply_wavelets(const Setup& S, Accelerogram& rec, const Eigen::VectorXd& g, const Workspace& ws,
                    std::vector<double>& a) {
  const std::size_t n = S.n, m = S.base.m, cols = ws.wav.size();
  std::vector<double> cb(m, 0.0);
  for (std::size_t j = 0; j < cols; ++j) {
    const double bj = g[static_cast<Eigen::Index>(j)];
    const Wavelet& W = ws.wav[j];
    for (std::size_t k = 0; k < W.v.size(); ++k) rec.a[W.s0 + k] += bj * W.v[k];
    for (std::size_t k = 0; k < m; ++k) cb[k] += bj * ws.wav_c[j * m + k];
  }
  for (std::size_t s = 0; s < n; ++s) {
    double p = 0.0;
    for (std::size_t k = 0; k < m; ++k) p += S.base.Phi[s * m + k] * cb[k];
    a[s] = rec.a[s] - p;
  }
}

// One spectral correction of the iterate rec (its peaks measured): the next iterate into a.
void correct(const ArtificialWaveParams& P, const Setup& S, bool fourier, Accelerogram& rec, Workspace& ws,
             std::vector<double>& a) {
  // Linearised peaks: Sa_i ~ s_i sum_s K_i[s] a[s] at the current peak times.
  const auto Ms = static_cast<std::ptrdiff_t>(ws.aims.size());
  if (ws.K.size() < ws.aims.size()) ws.K.resize(ws.aims.size(), std::vector<double>(S.n));
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < Ms; ++i) kernel_row(S.osc[ws.aims[i].j], ws.aims[i].p.q, S.n, ws.K[i].data());
  const std::size_t cols = fourier ? band_columns(S, rec, ws) : wavelet_columns(P, S, ws);
  build_rows(P, S, rec, fourier, cols, ws);
  // The bounds as an active set: a bound that the solution would break joins the
  // equations as an equality, and the system is solved again (a few rounds at most).
  Eigen::VectorXd g;
  for (int round = 0;; ++round) {
    g = regularised_solve(ws.rows, ws.rhs, ws.weight, fourier ? 0.3 : 0.03, ws.x0);
    if (round == kBoundRounds) break;
    bool added = false;
    for (std::size_t i = 0; i < ws.aims.size(); ++i) {
      const Aim& aim = ws.aims[i];
      if (!aim.bound || ws.weight[i] != 0.0) continue;
      double y = 0.0;
      for (std::size_t c = 0; c < cols; ++c) y += ws.rows[i][c] * g[static_cast<Eigen::Index>(c)];
      const double predicted = fourier ? aim.p.sign * y : aim.p.sa + aim.p.sign * y;
      if (predicted > aim.goal) {
        ws.weight[i] = 1.0 / S.target[aim.j];
        added = true;
      }
    }
    if (!added) break;
  }
  if (fourier)
    apply_band_gains(S, rec, g, ws, a);
  else
    apply_wavelets(S, rec, g, ws, a);
}

// One attempt from one set of phases: iterate, return the best iterate.
ArtificialWave attempt(const ArtificialWaveParams& P, const Setup& S, std::vector<double> a) {
  const double pga = P.spectrum.pga;
  const BaselineOptions baseline{true, P.baseline_degree};
  Workspace ws(S);
  ArtificialWave out;
  out.control_period = S.Tc;
  out.target_sa = S.target;
  double best_score = std::numeric_limits<double>::infinity();
  for (int it = 0;; ++it) {
    // Peak adjustment, baseline correction, exact PGA: every iterate is a valid wave.
    limit_half_cycles(a, pga);
    Accelerogram rec = integrate(P.dt, a, baseline);
    scale(rec, pga / rec.pga());
    double mis = 0.0, mis_short = 0.0;
    measure(P, S, rec, ws, mis, mis_short);
    const double score = std::max(mis / P.tolerance, mis_short / P.short_tolerance);
    if (score < best_score) {
      best_score = score;
      out.wave = rec;
      out.sa = ws.sa;
      out.max_misfit = mis;
      out.max_short_misfit = mis_short;
      out.iterations = it;
    }
    // Converged, out of corrections, or stalled: no better iterate for stall_iterations
    // corrections of the refinement in time.
    if (score <= 1.0 || it >= P.iterations) break;
    if (it >= P.fourier_iterations + P.stall_iterations && it - out.iterations >= P.stall_iterations) break;
    correct(P, S, it < P.fourier_iterations, rec, ws, a);
  }
  return out;
}

}  // namespace

ArtificialWave generate_artificial_wave(const ArtificialWaveParams& P) {
  P.validate();
  const detail::Setup S = detail::make_setup(P);
  // Attempts draw successive phase sets from one seeded stream; the first that meets
  // the acceptance tolerances is kept, else the best of all.
  std::mt19937_64 rng(P.seed);
  ArtificialWave best;
  double best_score = std::numeric_limits<double>::infinity();
  for (int k = 0; k < P.attempts; ++k) {
    ArtificialWave w = attempt(P, S, detail::synthesise(P, S, rng));
    w.attempts = k + 1;
    // The misfit reported and judged is measured on a grid three times denser than
    // the control periods, so that narrow dips between them count too.
    const std::vector<double> dense = log_spaced(2.0 * P.dt, P.period_max, 3 * P.control_periods);
    // Both spans count: the record alone and with the oscillator's free vibration after it.
    const ResponseSpectrum ds = response_spectrum(w.wave.a, P.dt, dense, P.spectrum.damping);
    const ResponseSpectrum df =
        response_spectrum(w.wave.a, P.dt, dense, P.spectrum.damping, SpectrumSpan::WithFreeVibration);
    w.max_misfit = w.max_short_misfit = 0.0;
    for (std::size_t j = 0; j < dense.size(); ++j) {
      const double t = P.spectrum.sa(dense[j]);
      const double e = std::max(std::abs(ds.Sa[j] / t - 1.0), std::abs(df.Sa[j] / t - 1.0));
      double& m = dense[j] < 0.1 ? w.max_short_misfit : w.max_misfit;
      m = std::max(m, e);
    }
    w.fit_record = spectral_fit(ds, P.spectrum, 0.1);
    w.fit_free_vibration = spectral_fit(df, P.spectrum, 0.1);
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
