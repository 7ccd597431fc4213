#include "water/heller_hager.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace dsdem::water {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

bool ImpulseWave::inside_validity() const {
  for (const RangeCheck& c : checks)
    if (!c.inside()) return false;
  return true;
}

ImpulseWave heller_hager(const SlideImpact& s) {
  auto positive = [](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(fmt::format("Heller & Hager: {} must be > 0, got {}", what, v));
  };
  positive(s.speed, "the slide speed");
  positive(s.thickness, "the slide thickness");
  positive(s.mass, "the slide mass");
  positive(s.depth, "the water depth");
  positive(s.water_density, "the water density");
  positive(s.gravity, "gravity");
  if (!(s.slope_deg > 0.0 && s.slope_deg <= 90.0))
    throw std::invalid_argument(fmt::format("Heller & Hager: the slope angle must be in (0, 90] deg, got {}", s.slope_deg));
  ImpulseWave w;
  const double h = s.depth;
  const double alpha = s.slope_deg * kPi / 180.0;
  w.froude = s.speed / std::sqrt(s.gravity * h);
  w.relative_thickness = s.thickness / h;
  w.relative_mass = s.mass / (s.water_density * 1.0 * h * h);  // b = 1 m in 2D
  w.impulse_product = w.froude * std::sqrt(w.relative_thickness) * std::pow(w.relative_mass, 0.25) *
                      std::sqrt(std::cos(6.0 * alpha / 7.0));
  const double p45 = std::pow(w.impulse_product, 0.8);
  w.amplitude_m = 4.0 / 9.0 * p45 * h;
  w.height_m = 5.0 / 9.0 * p45 * h;
  w.distance_m = 5.5 * std::sqrt(w.impulse_product) * h;
  // The ranges of the experiments (Heller & Hager 2010; docs/theory.md §12).
  w.checks[0] = {"F", w.froude, 0.86, 6.83};
  w.checks[1] = {"S", w.relative_thickness, 0.09, 1.64};
  w.checks[2] = {"M", w.relative_mass, 0.11, 10.02};
  w.checks[3] = {"P", w.impulse_product, 0.17, 8.13};
  w.checks[4] = {"alpha_deg", s.slope_deg, 30.0, 90.0};
  return w;
}

namespace {
// (P (x/h)^-1/3)^4/5 h, the decay laws' common factor.
double decay_factor(const ImpulseWave& w, double depth, double x) {
  if (!(x > 0.0)) throw std::invalid_argument(fmt::format("Heller & Hager: the distance must be > 0, got {}", x));
  return std::pow(w.impulse_product * std::pow(x / depth, -1.0 / 3.0), 0.8) * depth;
}
}  // namespace

double heller_hager_height_at(const ImpulseWave& w, double depth, double x) { return 0.75 * decay_factor(w, depth, x); }

double heller_hager_amplitude_at(const ImpulseWave& w, double depth, double x) { return 0.6 * decay_factor(w, depth, x); }

double heller_hager_decay_onset() { return std::pow(27.0 / 20.0, 3.75); }

}  // namespace dsdem::water
