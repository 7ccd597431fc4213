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

namespace {
// The return of a trial with invariants I1, sqrt(J2) = J outside the cone (f > 0): the
// deviator's scale, the new I1 and where it landed (docs/theory.md §10).
struct ConeReturn {
  double scale;  // s_new = scale s_trial
  double I1;
  DruckerPragerRegion region;
};
ConeReturn cone_return(const DruckerPragerModel& m, double I1, double J, double f) {
  const double G = m.elastic.mu;
  const double dlambda = f / (G + 9.0 * m.bulk * m.alpha * m.beta);
  const double J_new = J - G * dlambda;
  if (J_new < 0.0)  // beyond the apex (alpha > 0 here: with alpha = 0, J_new = k >= 0)
    return {0.0, m.k / m.alpha, DruckerPragerRegion::Apex};
  return {J > 0.0 ? J_new / J : 0.0, I1 - 9.0 * m.bulk * m.beta * dlambda, DruckerPragerRegion::Cone};
}
}  // namespace

namespace detail {

DruckerPragerResult drucker_prager_return(const DruckerPragerModel& m, const Vec3& E, const Vec3& S0, double S0_zz,
                                          const ElasticTrial& t, double I1, double J, const PlasticState& start,
                                          PlasticState& end) {
  const ConeReturn c = cone_return(m, I1, J, J + m.alpha * I1 - m.k);
  DruckerPragerResult out;
  out.region = c.region;
  // The deviator keeps its direction and scales; the mean moves to I1 / 3.
  const double mean = I1 / 3.0, mean_new = c.I1 / 3.0;
  out.S = Vec3((t.S[0] - mean) * c.scale + mean_new, (t.S[1] - mean) * c.scale + mean_new, t.S[2] * c.scale);
  out.S_zz = (t.S_zz - mean) * c.scale + mean_new;
  finish_return(m.compliance, E, S0, S0_zz, t.S, t.S_zz, start, end, out,
                [&](const PlasticIncrement& dep) { return plastic_work(dep, out.S, out.S_zz); });
  return out;
}

}  // namespace detail

namespace {
// sqrt(J2) of a 3D stress (tensor shears) with its mean I1 / 3.
double sqrt_j2(const Vec6& S, double mean) {
  const double sxx = S[0] - mean, syy = S[1] - mean, szz = S[2] - mean;
  return std::sqrt(0.5 * (sxx * sxx + syy * syy + szz * szz) + S[3] * S[3] + S[4] * S[4] + S[5] * S[5]);
}
}  // namespace

double drucker_prager_yield(const DruckerPragerModel& m, const Vec6& S) {
  const double I1 = S[0] + S[1] + S[2];
  return sqrt_j2(S, I1 / 3.0) + m.alpha * I1 - m.k;
}

DruckerPragerResult3D drucker_prager_update_3d(const DruckerPragerModel& m, const Vec6& E, const Vec6& S0,
                                               const PlasticState3D& start, PlasticState3D& end) {
  const ElasticTrial3D t = elastic_trial(m.elastic, E, S0, start);
  const double I1 = t.S[0] + t.S[1] + t.S[2];
  const double mean = I1 / 3.0;
  const double J = sqrt_j2(t.S, mean);
  const double f = J + m.alpha * I1 - m.k;
  if (f <= 0.0) return elastic_result<DruckerPragerResult3D>(t, S0, start, end);
  const ConeReturn c = cone_return(m, I1, J, f);
  DruckerPragerResult3D out;
  out.region = c.region;
  const double mean_new = c.I1 / 3.0;
  out.S << (t.S[0] - mean) * c.scale + mean_new, (t.S[1] - mean) * c.scale + mean_new,
      (t.S[2] - mean) * c.scale + mean_new, t.S[3] * c.scale, t.S[4] * c.scale, t.S[5] * c.scale;
  finish_return(m.compliance, E, S0, t.S, start, end, out, [&](const Vec6& dep) { return plastic_work(dep, out.S); });
  return out;
}

DruckerPragerKernel::Model DruckerPragerKernel::make(std::span<const double> params, const ElasticConstants& elastic,
                                                     bool plane_stress) {
  const auto [c, phi, psi] = law::envelope(params);
  if (const std::string why = validate_drucker_prager(c, phi, psi, plane_stress); !why.empty())
    throw std::invalid_argument(why);
  return make_drucker_prager(c, phi, psi, elastic);
}

}  // namespace dsdem::fem
