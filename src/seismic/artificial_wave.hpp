#pragma once
// Spectrum-compatible artificial accelerograms by the method of GB 17741-2005 (docs/theory.md
// §5, paper §2.2): target spectrum -> power spectral density -> sum of cosines with
// seeded random phases -> intensity envelope -> iterative correction of the Fourier
// amplitudes by the ratio target / computed response spectrum -> baseline correction ->
// scaling to the PGA. Deterministic: the same parameters give the same wave, bit for bit.
//
// Beyond the textbook method, because a plain ratio iteration stalls at 15-40% misfit
// on a 10 s record (the peak at one period also depends on the neighbouring bands):
// - the band gains are solved together from the linearised peak responses,
//   regularised towards the classical ratios, and the change is windowed by the
//   intensity envelope so that the wave keeps its shape in time;
// - after `fourier_iterations`, tapered-cosine wavelets refine the wave in time
//   (after Abrahamson 1992, RspMatch), baseline-corrected before use;
// - every iterate is peak-adjusted (half cycles above the PGA scaled down),
//   baseline-corrected and scaled to the PGA, so the wave returned is all three;
// - the fit counts both over the record alone and with the oscillator's free vibration
//   after it (the record padded with zeros, Boore & Bommer 2005; SpectrumSpan): the
//   record's peaks are brought to the target and the free vibration's peaks are kept
//   at or below it (bounds, as an active set of the linearised solve);
// - the control periods reach 10% beyond period_max, so that the edge of the matched
//   band (where the fit is loosest) lies outside the periods judged;
// - an attempt stops when converged, after `iterations`, or when `stall_iterations`
//   refinements found no better wave;
// - if an attempt ends above accept_tolerance, the next phase set is drawn from the
//   same seeded stream (at most `attempts`), and the best attempt is kept.
#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "seismic/accelerogram.hpp"
#include "seismic/design_spectrum.hpp"
#include "seismic/response_spectrum.hpp"

namespace dsdem::seismic {

struct ArtificialWaveParams {
  DesignSpectrum spectrum;  // kind, beta_max, PGA, Tg, damping; default = the paper's case
  double dt = 0.02;         // s
  double duration = 10.0;   // s
  // Intensity envelope f(t): (t/t1)^2 before t1, 1 to t2, exp(-c (t - t2)) after. The
  // paper gives none; these suit a 10 s record (strong phase 1.5-6.5 s, f(10) = 0.03).
  double t1 = 1.5;   // s
  double t2 = 6.5;   // s
  double c = 1.0;    // 1/s
  std::uint64_t seed = 1;
  int iterations = 32;            // spectral corrections per attempt, at most
  int fourier_iterations = 8;     // the first ones correct Fourier amplitudes, the rest refine in time
  int stall_iterations = 8;       // an attempt stops when that many refinements found no better wave
  double tolerance = 0.05;        // an attempt stops when every control period >= 0.1 s is within this
                                  // (over the record and with the free vibration after it)...
  double short_tolerance = 0.10;  // ...and those below 0.1 s within this (dt limits them)
  int attempts = 8;                      // phase sets tried, at most
  double accept_tolerance = 0.09;        // a new phase set is drawn while the best misfit exceeds
  double accept_short_tolerance = 0.15;  // these (both bands)
  int control_periods = 200;      // log-spaced control periods from 2 dt to 1.1 period_max
  double period_max = 6.0;        // s
  double exceedance = 0.15;       // probability p in the spectrum -> PSD conversion
  int baseline_degree = 3;        // see BaselineOptions

  // Throws std::runtime_error naming the bad parameter.
  void validate() const;
};

// Sa / target - 1 over the periods of a spectrum from t_min on: its lowest and highest
// value and where they are.
struct SpectralFit {
  double low = 0.0, high = 0.0;        // min and max of Sa/target - 1
  double T_low = 0.0, T_high = 0.0;    // s
  double worst() const { return std::max(-low, high); }
};
SpectralFit spectral_fit(const ResponseSpectrum& s, const DesignSpectrum& target, double t_min);

struct ArtificialWave {
  Accelerogram wave;                   // baseline-corrected, max |a| = PGA exactly
  std::vector<double> control_period;  // s
  std::vector<double> target_sa;       // m/s^2 at control_period
  std::vector<double> sa;              // m/s^2 of the wave at control_period, over the record
  double max_misfit = 0.0;        // max |Sa/target - 1| for periods >= 0.1 s, on a grid 3x denser
  double max_short_misfit = 0.0;  // the same below 0.1 s       than the control periods,
                                  // over the record and with the free vibration, the worse
  // The fit from 0.1 s to period_max on the dense grid, over the record alone and with
  // the oscillator's free vibration after it (SpectrumSpan).
  SpectralFit fit_record, fit_free_vibration;
  int iterations = 0;                  // corrections done in the kept attempt
  int attempts = 0;                    // phase sets drawn
};

ArtificialWave generate_artificial_wave(const ArtificialWaveParams& params);

// The intensity envelope of ArtificialWaveParams at time t.
double intensity_envelope(double t, double t1, double t2, double c);

// Uniform number in [0, 1) from the top 53 bits of one raw mt19937_64 output: does not
// depend on the standard library's distribution implementation.
double uniform01(std::mt19937_64& rng);

// One-sided power spectral density (m^2/s^3) compatible with a target Sa (m/s^2) at
// circular frequency omega, for a stationary motion of duration Td and non-exceedance
// 1 - p (the conversion used with GB 17741):
//   S(w) = zeta / (pi w) * Sa^2 / (-ln(-pi/(w Td) ln(1 - p))).
double spectrum_to_psd(double sa, double omega, double zeta, double Td, double p);

}  // namespace dsdem::seismic
