#include "seismic/response_spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "model/types.hpp"

namespace dsdem::seismic {

NigamJenningsStep nigam_jennings_step(double omega, double zeta, double dt) {
  if (!(omega > 0.0) || !std::isfinite(omega))
    throw std::runtime_error(fmt::format("response spectrum: circular frequency must be positive, got {}", omega));
  if (!(zeta >= 0.0 && zeta < 1.0))
    throw std::runtime_error(fmt::format("response spectrum: damping ratio must be in [0, 1), got {}", zeta));
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw std::runtime_error(fmt::format("response spectrum: time step must be positive, got {}", dt));
  // Closed form of Nigam & Jennings (1969) for an under-damped SDOF and a ground
  // acceleration linear over the step.
  const double s1 = std::sqrt(1.0 - zeta * zeta);
  const double wd = omega * s1;
  const double E = std::exp(-zeta * omega * dt);
  const double S = std::sin(wd * dt);
  const double C = std::cos(wd * dt);
  const double w2 = omega * omega, w3 = w2 * omega;
  NigamJenningsStep k{};
  k.a11 = E * (zeta / s1 * S + C);
  k.a12 = E * S / wd;
  k.a21 = -omega / s1 * E * S;
  k.a22 = E * (C - zeta / s1 * S);
  const double p = (2.0 * zeta * zeta - 1.0) / (w2 * dt);
  const double q = 2.0 * zeta / (w3 * dt);
  k.b11 = E * ((p + zeta / omega) * S / wd + (q + 1.0 / w2) * C) - q;
  k.b12 = -E * (p * S / wd + q * C) - 1.0 / w2 + q;
  k.b21 = E * ((p + zeta / omega) * (C - zeta / s1 * S) - (q + 1.0 / w2) * (wd * S + zeta * omega * C)) +
          1.0 / (w2 * dt);
  k.b22 = -E * (p * (C - zeta / s1 * S) - q * (wd * S + zeta * omega * C)) - 1.0 / (w2 * dt);
  return k;
}

SdofHistory sdof_response(std::span<const double> ag, double dt, double omega, double zeta, double x0, double v0) {
  const NigamJenningsStep k = nigam_jennings_step(omega, zeta, dt);
  SdofHistory h;
  const std::size_t n = ag.size();
  h.x.resize(n);
  h.xd.resize(n);
  h.abs_acc.resize(n);
  double x = x0, xd = v0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) {
      const double xn = k.a11 * x + k.a12 * xd + k.b11 * ag[i - 1] + k.b12 * ag[i];
      const double vn = k.a21 * x + k.a22 * xd + k.b21 * ag[i - 1] + k.b22 * ag[i];
      x = xn;
      xd = vn;
    }
    h.x[i] = x;
    h.xd[i] = xd;
    h.abs_acc[i] = -(2.0 * zeta * omega * xd + omega * omega * x);
  }
  return h;
}

std::size_t free_vibration_samples(double period, double zeta, double dt) {
  return 1 + static_cast<std::size_t>(std::ceil(period / std::sqrt(1.0 - zeta * zeta) / dt));
}

SpectralValue spectral_value(std::span<const double> ag, double dt, double period, double zeta, SpectrumSpan span) {
  SpectralValue r;
  if (period < 0.0 || !std::isfinite(period))
    throw std::runtime_error(fmt::format("response spectrum: period must be >= 0, got {}", period));
  if (period == 0.0) {  // infinitely stiff oscillator moves with the ground
    for (double a : ag) r.Sa = std::max(r.Sa, std::abs(a));
    return r;
  }
  const double omega = 2.0 * kPi / period;
  // The recurrence is exact at any step, but the peak between two samples is missed
  // when T is a few dt (at T = 2 dt the samples can fall on the zeros of the
  // response): sub-step with the same linear input so that every period has at least
  // kSpectrumPointsPerPeriod points (peak error <= 1 - cos(pi/50) = 0.2%).
  const int m = std::max(1, static_cast<int>(std::ceil(kSpectrumPointsPerPeriod * dt / period)));
  const double h = dt / m;
  const NigamJenningsStep k = nigam_jennings_step(omega, zeta, h);
  double x = 0.0, xd = 0.0;
  const double c1 = 2.0 * zeta * omega, c2 = omega * omega;
  const std::size_t n = ag.size();
  const std::size_t end = span == SpectrumSpan::Record || n == 0 ? n : n + free_vibration_samples(period, zeta, dt);
  auto at = [&](std::size_t i) { return i < n ? ag[i] : 0.0; };
  for (std::size_t i = 1; i < end; ++i) {
    const double a0 = at(i - 1), da = (at(i) - at(i - 1)) / m;
    for (int s = 0; s < m; ++s) {
      const double g0 = a0 + da * s, g1 = a0 + da * (s + 1);
      const double xn = k.a11 * x + k.a12 * xd + k.b11 * g0 + k.b12 * g1;
      const double vn = k.a21 * x + k.a22 * xd + k.b21 * g0 + k.b22 * g1;
      x = xn;
      xd = vn;
      r.Sd = std::max(r.Sd, std::abs(x));
      r.Sv = std::max(r.Sv, std::abs(xd));
      r.Sa = std::max(r.Sa, std::abs(c1 * xd + c2 * x));
    }
  }
  return r;
}

ResponseSpectrum response_spectrum(std::span<const double> ag, double dt, std::span<const double> periods,
                                   double zeta, SpectrumSpan span) {
  ResponseSpectrum s;
  s.damping = zeta;
  s.period.assign(periods.begin(), periods.end());
  s.Sa.resize(periods.size());
  s.Sv.resize(periods.size());
  s.Sd.resize(periods.size());
  // Each period on its own, on any thread: the same bits (the artificial wave's set-up
  // judges every attempt on 600 periods).
  const auto np = static_cast<std::ptrdiff_t>(periods.size());
#pragma omp parallel for schedule(dynamic, 8)
  for (std::ptrdiff_t jj = 0; jj < np; ++jj) {
    const auto j = static_cast<std::size_t>(jj);
    const SpectralValue v = spectral_value(ag, dt, periods[j], zeta, span);
    s.Sa[j] = v.Sa;
    s.Sv[j] = v.Sv;
    s.Sd[j] = v.Sd;
  }
  return s;
}

std::vector<double> log_spaced(double first, double last, int n) {
  if (n < 2 || !(first > 0.0) || !(last > first))
    throw std::runtime_error(fmt::format("log_spaced: need n >= 2 and 0 < first < last, got n = {}, [{}, {}]", n,
                                         first, last));
  std::vector<double> out(static_cast<std::size_t>(n));
  const double l0 = std::log(first), l1 = std::log(last);
  for (int i = 0; i < n; ++i) out[i] = std::exp(l0 + (l1 - l0) * i / (n - 1));
  out.front() = first;
  out.back() = last;
  return out;
}

void write_spectrum_csv(const std::string& path, const ResponseSpectrum& s, std::span<const double> target) {
  if (!target.empty() && target.size() != s.period.size())
    throw std::runtime_error(fmt::format("{}: target spectrum has {} values for {} periods", path, target.size(),
                                         s.period.size()));
  std::ofstream out(path);
  if (!out) throw std::runtime_error(fmt::format("{}: cannot open for writing", path));
  out << "period_s,Sa_mps2,Sv_mps,Sd_m" << (target.empty() ? "" : ",target_Sa_mps2") << "\n";
  for (std::size_t j = 0; j < s.period.size(); ++j) {
    out << fmt::format("{:.9g},{:.9e},{:.9e},{:.9e}", s.period[j], s.Sa[j], s.Sv[j], s.Sd[j]);
    if (!target.empty()) out << fmt::format(",{:.9e}", target[j]);
    out << "\n";
  }
  if (!out) throw std::runtime_error(fmt::format("{}: write failed", path));
}

}  // namespace dsdem::seismic
