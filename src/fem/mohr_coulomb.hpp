#pragma once
// Mohr-Coulomb plasticity of the bulk with a tension cut-off (docs/theory.md §10): a pure
// material-point kernel for the total Lagrangian CST (cst.hpp) on the plastic point of
// plastic_point.hpp: E = Ee + Ep, and the yield criterion acts on the second
// Piola-Kirchhoff stress S = S0 + D (E - Ep). Plane strain only: the total E_zz is 0, the
// out-of-plane plastic strain is state, and S_zz is a principal stress of the return
// mapping. Tension positive.
//
// Return mapping in principal stresses for linear yield planes (Clausen, Damkilde &
// Andersen 2006, IJNME 66, associated; 2007, Comput. Struct. 85, non-associated): the
// trial stress returns to a plane, a line or a point of the yield surface along the
// elastic image D b of the plastic potential gradients, with multipliers >= 0.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>

#include "fem/bulk_kernel.hpp"
#include "fem/cst.hpp"
#include "fem/plastic_point.hpp"
#include "fem/plastic_point3d.hpp"
#include "law/laws.hpp"
#include "model/types.hpp"

namespace dsdem::fem {

// Material parameters. Angles in radians inside (the scenario gives degrees).
struct MohrCoulombParameters {
  double c = 0.0;    // cohesion, Pa
  double phi = 0.0;  // friction angle, rad, in [0, pi/2)
  double psi = 0.0;  // dilation angle, rad, in [0, phi]
  // Tension cut-off on the major principal stress, Pa (>= 0). Infinity means "none": the
  // cone's apex c / tan(phi) for phi > 0, no cut-off for phi = 0. A finite value may not
  // exceed the apex.
  double ft = std::numeric_limits<double>::infinity();
};

// Empty when the parameters are admissible, else a message naming the offending fields.
// plane_stress = true is refused: sigma_zz = 0 would be a constraint on the return, not a
// principal stress the return may move.
std::string validate(const MohrCoulombParameters& p, bool plane_stress = false);

// The state of one element (one CST = one material point): the plastic point's, as the
// law declares it (law::plastic_state).
using MohrCoulombState = PlasticState;
using StateVariable = law::StateVariable;
inline constexpr const std::array<StateVariable, law::plastic_state::kStates>& kMohrCoulombStateVariables =
    law::plastic_state::kVariables;

// Where the trial stress returned to. Principal stresses s1 >= s2 >= s3 (tension positive).
enum class MohrCoulombRegion : std::uint8_t {
  Elastic = 0,
  ShearPlane,              // k s1 - s3 = sc
  ShearEdgeCompression,    // ... and s1 = s2 (triaxial compression edge)
  ShearEdgeExtension,      // ... and s2 = s3 (triaxial extension edge)
  ShearApex,               // s1 = s2 = s3 = c / tan(phi) (no cut-off below it)
  TensionPlane,            // s1 = ft
  TensionEdge,             // s1 = s2 = ft
  TensionApex,             // s1 = s2 = s3 = ft
  ShearTensionLine,        // s1 = ft and k s1 - s3 = sc
  ShearTensionCompression, // s1 = s2 = ft, s3 = k ft - sc
  ShearTensionExtension,   // s1 = ft, s2 = s3 = k ft - sc
};
const char* to_string(MohrCoulombRegion r);

// One linear yield or cut-off plane in principal space, a . s <= rhs, with its return
// direction r = D b (b the plastic potential gradient).
struct PrincipalPlane {
  std::array<double, 3> a;
  std::array<double, 3> r;
  double rhs;
  double inv_ar;  // 1 / (a . r): the multiplier of a return to this plane alone is f / (a . r)
};

// Parameters and elastic constants turned into what the return needs; build once per
// material (make_mohr_coulomb) and share read-only between threads.
struct MohrCoulombModel {
  ElasticConstants elastic;
  double k = 1.0;         // (1 + sin phi) / (1 - sin phi)
  double m = 1.0;         // (1 + sin psi) / (1 - sin psi)
  double sc = 0.0;        // 2 c cos phi / (1 - sin phi): uniaxial compressive strength, Pa
  double ft = 0.0;        // effective cut-off, Pa (infinity without one)
  double apex = 0.0;      // c / tan(phi), Pa (infinity for phi = 0)
  double mc_scale = 0.5;  // (1 - sin phi) / 2: (k s1 - s3 - sc) times this is in Pa
  bool cutoff = false;    // ft < apex: the cut-off is a surface of its own
  Compliance compliance;  // D^-1
  // Planes: 0 = k s1 - s3, 1 = k s2 - s3, 2 = k s1 - s2 (shear, potential with m),
  // 3, 4, 5 = s1, s2, s3 (cut-off, associated).
  std::array<PrincipalPlane, 6> plane;
};
MohrCoulombModel make_mohr_coulomb(const MohrCoulombParameters& p, const ElasticConstants& elastic);

// Principal stresses sorted s1 >= s2 >= s3 of the plane-strain stress (S_xx, S_yy, S_xy)
// and S_zz.
std::array<double, 3> principal_stresses(const Vec3& S, double S_zz);

// Yield function in Pa, max(Mohr circle radius - shear strength, s1 - ft); <= 0 admissible.
double yield_function(const MohrCoulombModel& mc, const std::array<double, 3>& s);

// Result of one update.
using MohrCoulombResult = PlasticResult<MohrCoulombRegion>;

namespace detail {
// The plastic branch of mohr_coulomb_update: S, S_zz hold the trial stress on entry.
MohrCoulombResult mohr_coulomb_return(const MohrCoulombModel& mc, const Vec3& E, const Vec3& S0, double S0_zz,
                                      const Vec3& S, double S_zz, const MohrCoulombState& start,
                                      MohrCoulombState& end);
}  // namespace detail

// The stress at the end of a step from the total Green strain E (xx, yy, 2xy) at its end,
// the initial stress (S0, S0_zz) and the state at its start; writes the state at its end
// (`end` may be `start`). Elastic trial S = S0 + D (E - Ep) with Ee_zz = -ep_zz, principal
// stresses, return, rotation back; Ep += D^-1 (S_trial - S) (Voigt, engineering shear).
// The elastic path costs one square root. With Ep = 0 and no yield, S and the energy are
// the bits of the elastic kernel's S0 + svk_stress(E) and its strain energy density.
inline MohrCoulombResult mohr_coulomb_update(const MohrCoulombModel& mc, const Vec3& E, const Vec3& S0,
                                             double S0_zz, const MohrCoulombState& start, MohrCoulombState& end) {
  const ElasticTrial t = elastic_trial(mc.elastic, E, S0, S0_zz, start);
  // Largest and smallest principal stress: in-plane pair C +- R and S_zz.
  const double C = 0.5 * (t.S[0] + t.S[1]);
  const double d = 0.5 * (t.S[0] - t.S[1]);
  const double R = std::sqrt(d * d + t.S[2] * t.S[2]);
  const double s1 = std::max(C + R, t.S_zz);
  const double s3 = std::min(C - R, t.S_zz);
  if (mc.k * s1 - s3 - mc.sc <= 0.0 && s1 <= mc.ft) return elastic_result<MohrCoulombResult>(t, S0, S0_zz, start, end);
  return detail::mohr_coulomb_return(mc, E, S0, S0_zz, t.S, t.S_zz, start, end);
}

// The 3D update of the tetrahedron's point (plastic_point3d.hpp): the trial's principal
// stresses and directions (the stress tensor's eigensystem), the same return in principal
// space as plane strain, and the returned stresses rotated back onto the trial's directions
// (isotropic D keeps them). The state at the step's end goes to `end` (may be `start`).
using MohrCoulombResult3D = PlasticResult3D<MohrCoulombRegion>;
MohrCoulombResult3D mohr_coulomb_update_3d(const MohrCoulombModel& mc, const Vec6& E, const Vec6& S0,
                                           const PlasticState3D& start, PlasticState3D& end);

// The law's kernel for the element loop (bulk_law.hpp): its model from the parameters
// law/laws.cpp declares, and its update.
struct MohrCoulombKernel : PlasticKernel<MohrCoulombModel, MohrCoulombResult, mohr_coulomb_update>,
                           PlasticKernel3D<MohrCoulombModel, MohrCoulombResult3D, mohr_coulomb_update_3d> {
  static constexpr std::string_view name = law::mohr_coulomb::kName;
  static Model make(std::span<const double> params, const ElasticConstants& elastic, bool plane_stress);
};

}  // namespace dsdem::fem
