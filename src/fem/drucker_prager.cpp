#include "fem/drucker_prager.hpp"

#include <sstream>
#include <stdexcept>

namespace dsdem::fem {

namespace {
// tan(angle) / sqrt(9 + 12 tan^2(angle)): the plane-strain match of a Mohr-Coulomb angle.
double plane_strain_match(double angle) {
  const double t = std::tan(angle);
  return t / std::sqrt(9.0 + 12.0 * t * t);
}
}  // namespace

const char* to_string(DruckerPragerRegion r) {
  switch (r) {
    case DruckerPragerRegion::Elastic: return "elastic";
    case DruckerPragerRegion::Cone: return "cone";
    case DruckerPragerRegion::Apex: return "apex";
  }
  return "unknown";
}

std::string validate_drucker_prager(double c, double phi, double psi, bool plane_stress) {
  std::ostringstream err;
  check_envelope(err, c, phi, psi, plane_stress);
  return validation_text(law::drucker_prager::kName, err);
}

DruckerPragerModel make_drucker_prager(double c, double phi, double psi, const ElasticConstants& elastic) {
  DruckerPragerModel m;
  m.elastic = elastic;
  m.compliance = compliance(elastic);
  m.alpha = plane_strain_match(phi);
  m.k = 3.0 * c / std::sqrt(9.0 + 12.0 * std::tan(phi) * std::tan(phi));
  m.beta = plane_strain_match(psi);
  m.bulk = elastic.lambda + 2.0 * elastic.mu / 3.0;
  return m;
}

double drucker_prager_yield(const DruckerPragerModel& m, const Vec3& S, double S_zz) {
  const double I1 = S[0] + S[1] + S_zz;
  return detail::sqrt_j2(S, S_zz, I1 / 3.0) + m.alpha * I1 - m.k;
}

namespace detail {

DruckerPragerResult drucker_prager_return(const DruckerPragerModel& m, const Vec3& E, const Vec3& S0, double S0_zz,
                                          const ElasticTrial& t, double I1, double J, const PlasticState& start,
                                          PlasticState& end) {
  const double G = m.elastic.mu;
  const double f = J + m.alpha * I1 - m.k;
  const double dlambda = f / (G + 9.0 * m.bulk * m.alpha * m.beta);
  double J_new = J - G * dlambda;
  double I1_new = I1 - 9.0 * m.bulk * m.beta * dlambda;
  DruckerPragerResult out;
  out.region = DruckerPragerRegion::Cone;
  if (J_new < 0.0) {  // beyond the apex (alpha > 0 here: with alpha = 0, J_new = k >= 0)
    J_new = 0.0;
    I1_new = m.k / m.alpha;
    out.region = DruckerPragerRegion::Apex;
  }
  // The deviator keeps its direction and scales to J_new; the mean moves to I1_new / 3.
  const double scale = J > 0.0 ? J_new / J : 0.0;
  const double mean = I1 / 3.0, mean_new = I1_new / 3.0;
  out.S = Vec3((t.S[0] - mean) * scale + mean_new, (t.S[1] - mean) * scale + mean_new, t.S[2] * scale);
  out.S_zz = (t.S_zz - mean) * scale + mean_new;
  finish_return(m.compliance, E, S0, S0_zz, t.S, t.S_zz, start, end, out,
                [&](const PlasticIncrement& dep) { return plastic_work(dep, out.S, out.S_zz); });
  return out;
}

}  // namespace detail

DruckerPragerKernel::Model DruckerPragerKernel::make(std::span<const double> params, const ElasticConstants& elastic,
                                                     bool plane_stress) {
  const auto [c, phi, psi] = law::envelope(params);
  if (const std::string why = validate_drucker_prager(c, phi, psi, plane_stress); !why.empty())
    throw std::invalid_argument(why);
  return make_drucker_prager(c, phi, psi, elastic);
}

}  // namespace dsdem::fem
