#pragma once
// Internal to src/seismic: the constant data of one artificial-wave generation
// (artificial_wave_setup.cpp), used by the spectral matching (artificial_wave.cpp).

#include <cstddef>
#include <random>
#include <vector>

#include "seismic/artificial_wave.hpp"
#include "seismic/response_spectrum.hpp"

namespace dsdem::seismic::detail {

// One SDOF oscillator sub-stepped as in spectral_value(): its Nigam-Jennings step and
// the absolute-acceleration response H[q] (sub-step q) to a unit hat input at sample
// 1, over the record and its free-vibration tail. By linearity the response at
// sub-step q to any input a is sum_s H[q - (s - 1) m] a[s], which gives the
// sensitivity of Sa to each band.
struct Oscillator {
  double omega = 0.0;
  int m = 1;             // sub-steps per sample
  std::size_t pad = 0;   // zero samples after the record (free_vibration_samples)
  NigamJenningsStep step{};
  std::vector<double> H;
};

// The baseline correction is linear: a_c = a - Phi (L a), Phi the n x m polynomial
// basis, L (m x n) found once by correcting unit impulses. Lets the refinement correct
// its wavelets at the cost of m numbers each.
struct BaselineOperator {
  std::size_t n = 0, m = 0;
  std::vector<double> Phi;  // n x m, row s = basis at sample s
  std::vector<double> L;    // m x n, column s = coefficients for a unit impulse at s
};

// The control periods run from 2 dt to kControlReach * period_max.
constexpr double kControlReach = 1.1;

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

// The set-up of a generation from its parameters (no random numbers drawn).
Setup make_setup(const ArtificialWaveParams& P);

// Stationary sum of cosines with the target's PSD and seeded phases, times the
// intensity envelope; frequencies f_k = k/(2T) up to Nyquist (docs/theory.md §5).
std::vector<double> synthesise(const ArtificialWaveParams& P, const Setup& S, std::mt19937_64& rng);

}  // namespace dsdem::seismic::detail
