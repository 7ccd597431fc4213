#include "seismic/design_spectrum.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "model/types.hpp"

namespace dsdem::seismic {

DesignSpectrumKind parse_design_spectrum_kind(const std::string& text) {
  std::string s = text;
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (s == "beta" || s == "hydraulic") return DesignSpectrumKind::HydraulicBeta;
  if (s == "alpha" || s == "gb50011") return DesignSpectrumKind::Gb50011Alpha;
  throw std::runtime_error(
      fmt::format("unknown design spectrum '{}' (valid: beta, hydraulic, alpha, gb50011)", text));
}

const char* to_string(DesignSpectrumKind kind) {
  return kind == DesignSpectrumKind::HydraulicBeta ? "hydraulic beta" : "GB 50011 alpha";
}

double hydraulic_beta(double T, double beta_max, double Tg) {
  if (T <= 0.1) return 1.0 + 10.0 * (beta_max - 1.0) * std::max(T, 0.0);
  if (T <= Tg) return beta_max;
  return std::max(beta_max * std::pow(Tg / T, 0.6), 0.2 * beta_max);
}

Gb50011Coefficients gb50011_coefficients(double damping) {
  const double z = damping;
  Gb50011Coefficients c{};
  c.gamma = 0.9 + (0.05 - z) / (0.3 + 6.0 * z);
  c.eta1 = std::max(0.02 + (0.05 - z) / (4.0 + 32.0 * z), 0.0);
  c.eta2 = std::max(1.0 + (0.05 - z) / (0.08 + 1.6 * z), 0.55);
  return c;
}

double gb50011_alpha(double T, double alpha_max, double Tg, double damping) {
  const Gb50011Coefficients c = gb50011_coefficients(damping);
  T = std::clamp(T, 0.0, 6.0);  // the code's spectrum ends at 6 s; hold that value beyond
  double f;
  if (T < 0.1) f = 0.45 + 10.0 * (c.eta2 - 0.45) * T;
  else if (T <= Tg) f = c.eta2;
  else if (T <= 5.0 * Tg) f = std::pow(Tg / T, c.gamma) * c.eta2;
  else f = c.eta2 * std::pow(0.2, c.gamma) - c.eta1 * (T - 5.0 * Tg);
  return std::max(f, 0.0) * alpha_max;
}

void DesignSpectrum::validate() const {
  if (!(pga > 0.0) || !std::isfinite(pga))
    throw std::runtime_error(fmt::format("design spectrum: PGA must be positive, got {} m/s^2", pga));
  if (!(Tg > 0.1 && Tg <= 10.0))
    throw std::runtime_error(fmt::format("design spectrum: Tg must be in (0.1, 10] s, got {}", Tg));
  if (!(beta_max >= 1.0) || !std::isfinite(beta_max))
    throw std::runtime_error(fmt::format("design spectrum: beta_max must be >= 1, got {}", beta_max));
  if (!(damping > 0.0 && damping < 1.0))
    throw std::runtime_error(fmt::format("design spectrum: damping ratio must be in (0, 1), got {}", damping));
  if (kind == DesignSpectrumKind::HydraulicBeta && std::abs(damping - 0.05) > 1e-12)
    throw std::runtime_error(fmt::format(
        "design spectrum: the hydraulic beta spectrum is defined at 5% damping only, got {}; use the "
        "GB 50011 alpha spectrum for other damping ratios",
        damping));
}

double DesignSpectrum::sa(double T) const {
  if (kind == DesignSpectrumKind::HydraulicBeta) return hydraulic_beta(T, beta_max, Tg) * pga;
  const double alpha_max = beta_max * pga / kStandardGravity;
  return gb50011_alpha(T, alpha_max, Tg, damping) * kStandardGravity;
}

}  // namespace dsdem::seismic
