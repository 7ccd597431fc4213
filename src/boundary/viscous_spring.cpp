#include "boundary/viscous_spring.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace dsdem::boundary {

double ElasticMedium::cp() const { return std::sqrt((lambda + 2.0 * G) / rho); }
double ElasticMedium::cs() const { return std::sqrt(G / rho); }

namespace {
void check_medium(const ElasticMedium& m) {
  if (!(m.rho > 0.0) || !(m.G > 0.0) || !(m.lambda + 2.0 * m.G > 0.0) || !std::isfinite(m.rho) ||
      !std::isfinite(m.G) || !std::isfinite(m.lambda))
    throw std::runtime_error(fmt::format(
        "viscous-spring boundary: medium needs rho > 0, G > 0 and lambda + 2G > 0, got rho = {}, G = {}, "
        "lambda = {}",
        m.rho, m.G, m.lambda));
}
}  // namespace

ElasticMedium medium_from_material(const Material& m) {
  ElasticMedium e{m.rho, m.mu(), m.lambda()};
  check_medium(e);
  return e;
}

ViscousSpringCoefficients viscous_spring_coefficients(double A, const ElasticMedium& medium, double R,
                                                      double alpha_n, double alpha_t) {
  check_medium(medium);
  if (!(A >= 0.0) || !std::isfinite(A))
    throw std::runtime_error(fmt::format("viscous-spring boundary: tributary area must be >= 0, got {}", A));
  if (!(R > 0.0) || !std::isfinite(R))
    throw std::runtime_error(fmt::format("viscous-spring boundary: distance R must be positive, got {}", R));
  ViscousSpringCoefficients c;
  c.kn = A * alpha_n * medium.G / R;
  c.kt = A * alpha_t * medium.G / R;
  c.cn = A * medium.rho * medium.cp();
  c.ct = A * medium.rho * medium.cs();
  return c;
}

}  // namespace dsdem::boundary
