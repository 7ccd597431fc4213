#include "fem/plastic_point.hpp"

#include <cmath>

namespace dsdem::fem {

void check_envelope(std::ostream& err, double c, double phi, double psi, bool plane_stress) {
  if (plane_stress)
    err << "plane stress is not supported (plane strain only: the return mapping moves sigma_zz as a stress of its "
           "own); ";
  if (!(c >= 0.0) || !std::isfinite(c)) err << "c must be >= 0 (got " << c << "); ";
  if (!(phi >= 0.0 && phi < 0.5 * kPi)) err << "phi must be in [0, 90) deg (got " << phi * 180.0 / kPi << " deg); ";
  if (!(psi >= 0.0) || !(psi <= phi))
    err << "psi must be in [0, phi] (got psi = " << psi * 180.0 / kPi << " deg, phi = " << phi * 180.0 / kPi
        << " deg); ";
  if (c == 0.0 && phi == 0.0) err << "c and phi are both 0: the material has no strength; ";
}

std::string validation_text(std::string_view law, const std::ostringstream& err) {
  const std::string s = err.str();
  return s.empty() ? s : std::string(law) + ": " + s.substr(0, s.size() - 2);
}

}  // namespace dsdem::fem
