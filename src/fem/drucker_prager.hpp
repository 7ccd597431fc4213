#pragma once
// Drucker-Prager plasticity of the bulk (docs/theory.md §10): the smooth cone
// sqrt(J2) + alpha I1 <= k on the plastic point of plastic_point.hpp, with the plastic
// potential sqrt(J2) + beta I1 (non-associated for psi < phi). Its constants are matched
// to the Mohr-Coulomb envelope (c, phi, psi) in plane strain (Drucker & Prager 1952):
//   alpha = tan(phi) / sqrt(9 + 12 tan^2 phi),  k = 3 c / sqrt(9 + 12 tan^2 phi),
//   beta  = tan(psi) / sqrt(9 + 12 tan^2 psi),
// so that with associated flow a plane-strain limit load is Mohr-Coulomb's; for phi = 0 it
// is von Mises with k = c, which in plane strain is Tresca's c. Plane strain only: the
// out-of-plane stress is a stress of the return. Tension positive.
//
// Return mapping (closed form, isotropic elasticity: K the bulk, G the shear modulus): to
// the cone, dlambda = f / (G + 9 K alpha beta), sqrt(J2) -= G dlambda, I1 -= 9 K beta
// dlambda; when that would leave sqrt(J2) < 0 the trial lies beyond the apex and returns
// to it, I1 = k / alpha, s = 0.
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>

#include "fem/cst.hpp"
#include "fem/plastic_point.hpp"
#include "fem/plastic_point3d.hpp"
#include "law/laws.hpp"

namespace dsdem::fem {

// Where the trial stress returned to.
enum class DruckerPragerRegion : std::uint8_t {
  Elastic = 0,
  Cone,  // sqrt(J2) + alpha I1 = k with sqrt(J2) > 0
  Apex,  // s = 0, I1 = k / alpha
};
const char* to_string(DruckerPragerRegion r);

// The cone's constants, built once per material and shared read-only by threads.
struct DruckerPragerModel {
  ElasticConstants elastic;
  Compliance compliance;  // D^-1
  double alpha = 0.0;     // friction of the cone (dimensionless)
  double k = 0.0;         // its strength in shear, Pa
  double beta = 0.0;      // dilation of the potential (dimensionless), 0 <= beta <= alpha
  double bulk = 0.0;      // K = lambda + 2 mu / 3, Pa
};
// c in Pa, phi and psi in radians (0 <= psi <= phi < pi/2). Empty when admissible, else
// a message naming the offending values.
std::string validate_drucker_prager(double c, double phi, double psi, bool plane_stress);
DruckerPragerModel make_drucker_prager(double c, double phi, double psi, const ElasticConstants& elastic);

// sqrt(J2) + alpha I1 - k of the stress (xx, yy, xy) and S_zz, in Pa; <= 0 admissible.
double drucker_prager_yield(const DruckerPragerModel& m, const Vec3& S, double S_zz);

using DruckerPragerResult = PlasticResult<DruckerPragerRegion>;

namespace detail {
// sqrt(J2) of the plane-strain stress (xx, yy, xy) and S_zz with its mean I1 / 3.
inline double sqrt_j2(const Vec3& S, double S_zz, double mean) {
  const double sxx = S[0] - mean, syy = S[1] - mean, szz = S_zz - mean;
  return std::sqrt(0.5 * (sxx * sxx + syy * syy + szz * szz) + S[2] * S[2]);
}
// The plastic branch of drucker_prager_update from the elastic trial t.
DruckerPragerResult drucker_prager_return(const DruckerPragerModel& m, const Vec3& E, const Vec3& S0, double S0_zz,
                                          const ElasticTrial& t, double I1, double J, const PlasticState& start,
                                          PlasticState& end);
}  // namespace detail

// The stress at the end of a step from the total Green strain E (xx, yy, 2xy), the initial
// stress (S0, S0_zz) and the state at the step's start; the state at its end into `end`
// (`end` may be `start`). Below the cone: the elastic trial's stress and energy, the bits
// of the elastic kernel when Ep = 0.
inline DruckerPragerResult drucker_prager_update(const DruckerPragerModel& m, const Vec3& E, const Vec3& S0,
                                                 double S0_zz, const PlasticState& start, PlasticState& end) {
  const ElasticTrial t = elastic_trial(m.elastic, E, S0, S0_zz, start);
  const double I1 = t.S[0] + t.S[1] + t.S_zz;
  const double J = detail::sqrt_j2(t.S, t.S_zz, I1 / 3.0);
  if (J + m.alpha * I1 - m.k <= 0.0) return elastic_result<DruckerPragerResult>(t, S0, S0_zz, start, end);
  return detail::drucker_prager_return(m, E, S0, S0_zz, t, I1, J, start, end);
}

// The 3D update of the tetrahedron's point (plastic_point3d.hpp): the same cone and return
// on the six stress components. The state at the step's end goes to `end` (may be `start`).
using DruckerPragerResult3D = PlasticResult3D<DruckerPragerRegion>;
DruckerPragerResult3D drucker_prager_update_3d(const DruckerPragerModel& m, const Vec6& E, const Vec6& S0,
                                               const PlasticState3D& start, PlasticState3D& end);
// sqrt(J2) + alpha I1 - k of a 3D stress, in Pa.
double drucker_prager_yield(const DruckerPragerModel& m, const Vec6& S);

// The law's kernel for the element loop (bulk_law.hpp).
struct DruckerPragerKernel : PlasticKernel<DruckerPragerModel, DruckerPragerResult, drucker_prager_update>,
                             PlasticKernel3D<DruckerPragerModel, DruckerPragerResult3D, drucker_prager_update_3d> {
  static constexpr std::string_view name = law::drucker_prager::kName;
  static Model make(std::span<const double> params, const ElasticConstants& elastic, bool plane_stress);
};

}  // namespace dsdem::fem
