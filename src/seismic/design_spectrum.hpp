#pragma once
// Code design spectra used as targets for artificial accelerograms (docs/theory.md §5):
// the hydraulic code's dynamic amplification spectrum beta(T) (NB 35047 / DL 5073) and
// the GB 50011 seismic influence coefficient alpha(T), both scaled to a design PGA.
#include <string>

namespace dsdem::seismic {

enum class DesignSpectrumKind { HydraulicBeta, Gb50011Alpha };

// "beta" / "hydraulic" or "alpha" / "gb50011" (case-insensitive); anything else throws,
// naming the valid keys.
DesignSpectrumKind parse_design_spectrum_kind(const std::string& text);
const char* to_string(DesignSpectrumKind kind);

// Hydraulic beta spectrum (5% damping): 1 + 10(bmax - 1)T for T <= 0.1 s, bmax up to
// Tg, bmax (Tg/T)^0.6 after, never below 0.2 bmax.
double hydraulic_beta(double T, double beta_max, double Tg);

// GB 50011-2010 §5.1.5 damping adjustment: gamma (decay exponent), eta1 (slope of the
// linear tail, >= 0), eta2 (damping factor, >= 0.55). At 5%: 0.9, 0.02, 1.
struct Gb50011Coefficients {
  double gamma, eta1, eta2;
};
Gb50011Coefficients gb50011_coefficients(double damping);

// GB 50011 alpha(T) for a given alpha_max: rises linearly from 0.45 alpha_max at T = 0
// to eta2 alpha_max at 0.1 s, flat to Tg, (Tg/T)^gamma eta2 alpha_max to 5Tg, then
// [eta2 0.2^gamma - eta1 (T - 5Tg)] alpha_max to 6 s. The code stops at 6 s; beyond it we
// hold the 6 s value. Never negative.
double gb50011_alpha(double T, double alpha_max, double Tg, double damping);

// A target spectrum anchored at the design PGA. Hydraulic: Sa = beta(T) * PGA.
// GB 50011: alpha_max = beta_max * PGA / g and Sa = alpha(T) * g (so Sa(0) = 1.0125 PGA
// with beta_max = 2.25).
struct DesignSpectrum {
  DesignSpectrumKind kind = DesignSpectrumKind::HydraulicBeta;
  double beta_max = 2.25;
  double pga = 0.05 * 9.80665;  // m/s^2
  double Tg = 0.35;             // characteristic period, s
  double damping = 0.05;

  // Throws std::runtime_error naming the bad value (non-positive PGA, Tg outside
  // (0.1, 10] s, beta_max < 1, damping outside (0, 1), or a hydraulic spectrum at a
  // damping other than 5%: the beta spectrum is defined at 5% only).
  void validate() const;
  double sa(double T) const;  // m/s^2, T >= 0
};

}  // namespace dsdem::seismic
