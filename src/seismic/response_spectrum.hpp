#pragma once
// Elastic response spectra of a ground acceleration (docs/theory.md §5) by the exact
// piecewise-linear recurrence of Nigam & Jennings (1969): the ground acceleration is
// taken linear between samples and the SDOF equation
//   x'' + 2 zeta omega x' + omega^2 x = -a_g(t)
// is integrated exactly over each step, so the result has no time-step error.
#include <span>
#include <string>
#include <vector>

namespace dsdem::seismic {

// [x, x']_{i+1} = A [x, x']_i + B [a_i, a_{i+1}]  (Nigam & Jennings 1969, eq. 26-27).
struct NigamJenningsStep {
  double a11, a12, a21, a22;
  double b11, b12, b21, b22;
};
// omega > 0 (rad/s), 0 <= zeta < 1, dt > 0; throws otherwise. Loses accuracy only when
// omega*dt is below ~1e-4 (cancellation in the b coefficients).
NigamJenningsStep nigam_jennings_step(double omega, double zeta, double dt);

// Relative displacement x, relative velocity x' and absolute acceleration
// x'' + a_g = -(2 zeta omega x' + omega^2 x) at every sample.
struct SdofHistory {
  std::vector<double> x, xd, abs_acc;
};
SdofHistory sdof_response(std::span<const double> ag, double dt, double omega, double zeta, double x0 = 0.0,
                          double v0 = 0.0);

// Sub-steps per period used by spectral_value() so that peaks between samples count.
constexpr double kSpectrumPointsPerPeriod = 50.0;

// Over what the peaks are taken: the record alone, or the record padded with zeros
// long enough for the oscillator's free vibration after it to count (Boore & Bommer
// 2005, §4: a structure, or a slope, goes on moving after the shaking stops).
enum class SpectrumSpan { Record, WithFreeVibration };

// Zero samples appended for SpectrumSpan::WithFreeVibration: one to bring the input
// linearly back to zero, then one damped period T / sqrt(1 - zeta^2). The free response
// is a decaying sinusoid, so its largest |value| comes within the first half period.
std::size_t free_vibration_samples(double period, double zeta, double dt);

// Peaks over the span, taken on a grid of at least kSpectrumPointsPerPeriod points per
// period (the input stays linear between samples, so sub-stepping changes nothing but
// where the response is looked at): Sa = max |absolute acceleration|, Sv = max
// |relative velocity|, Sd = max |relative displacement|. Period 0 gives Sa = PGA,
// Sv = Sd = 0.
struct SpectralValue {
  double Sa = 0.0;  // m/s^2
  double Sv = 0.0;  // m/s
  double Sd = 0.0;  // m
};
SpectralValue spectral_value(std::span<const double> ag, double dt, double period, double zeta,
                             SpectrumSpan span = SpectrumSpan::Record);

struct ResponseSpectrum {
  double damping = 0.05;
  std::vector<double> period;  // s
  std::vector<double> Sa, Sv, Sd;
};
ResponseSpectrum response_spectrum(std::span<const double> ag, double dt, std::span<const double> periods,
                                   double zeta, SpectrumSpan span = SpectrumSpan::Record);

// n periods spaced evenly in log between first and last (inclusive); n >= 2, 0 < first < last.
std::vector<double> log_spaced(double first, double last, int n);

// Write period_s,Sa_mps2,Sv_mps,Sd_m (and target_Sa_mps2 when target is non-empty).
void write_spectrum_csv(const std::string& path, const ResponseSpectrum& s, std::span<const double> target = {});

}  // namespace dsdem::seismic
