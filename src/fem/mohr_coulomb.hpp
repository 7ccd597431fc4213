#pragma once
// Mohr-Coulomb plasticity of the bulk with a tension cut-off (DESIGN.md §12): a pure
// material-point kernel for the total Lagrangian CST (cst.hpp). Small strain and large
// rotation: the Green strain splits additively, E = Ee + Ep, and the yield criterion acts
// on the second Piola-Kirchhoff stress S = S0 + D (E - Ep). Plane strain only: the total
// E_zz is 0, the out-of-plane plastic strain is state, and S_zz is a principal stress of
// the return mapping. Tension positive.
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
#include <string>

#include "fem/cst.hpp"
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

// A state variable as the material registry declares it (name, unit, meaning).
struct StateVariable {
  const char* name;
  const char* unit;
  const char* description;
};

// State of one element (one CST = one material point), five doubles in this order.
struct MohrCoulombState {
  double ep_xx = 0.0;  // plastic Green strain
  double ep_yy = 0.0;
  double ep_xy = 0.0;  // engineering shear 2 Ep_xy
  double ep_zz = 0.0;  // out-of-plane plastic strain; the elastic part is -ep_zz
  double plastic_work = 0.0;  // accumulated dissipation per unit reference volume, J/m^3
};
static_assert(sizeof(MohrCoulombState) == 5 * sizeof(double), "the state is read as 5 doubles");

inline constexpr std::array<StateVariable, 5> kMohrCoulombStateVariables{{
    {"plastic_strain_xx", "", "plastic Green strain Ep_xx"},
    {"plastic_strain_yy", "", "plastic Green strain Ep_yy"},
    {"plastic_strain_xy", "", "plastic Green strain, engineering shear 2 Ep_xy"},
    {"plastic_strain_zz", "", "out-of-plane plastic strain (plane strain: total E_zz = 0)"},
    {"plastic_dissipation", "J/m^3", "plastic dissipation per unit reference volume"},
}};

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
  double inv_2mu = 0.0;   // D^-1 = I / (2 mu) - lambda / (2 mu (3 lambda + 2 mu)) 1 x 1
  double inv_vol = 0.0;   // lambda / (2 mu (3 lambda + 2 mu))
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
struct MohrCoulombResult {
  Vec3 S = Vec3::Zero();  // PK2 stress (xx, yy, xy), Pa
  double S_zz = 0.0;      // out-of-plane PK2 stress, Pa
  double dissipation = 0.0;  // S : dEp of this update at the returned stress, J/m^3, >= 0
  double strain_energy = 0.0;  // stored elastic energy S0 : Ee + Ee : D : Ee / 2, J/m^3
  MohrCoulombRegion region = MohrCoulombRegion::Elastic;
  bool yielded() const { return region != MohrCoulombRegion::Elastic; }
};

namespace detail {
// The plastic branch of mohr_coulomb_update: S, S_zz hold the trial stress on entry.
MohrCoulombResult mohr_coulomb_return(const MohrCoulombModel& mc, const Vec3& E, const Vec3& S0, double S0_zz,
                                      const Vec3& S, double S_zz, const MohrCoulombState& start,
                                      MohrCoulombState& end);

// Stored energy S0 : Ee + Ee : D : Ee / 2 with DEe = S - S0 given as (xx, yy, xy, zz); the
// order of the sums is the elastic kernel's (triangle_internal_force) when Ee_zz = 0.
inline double mohr_coulomb_energy(const Vec3& S0, double S0_zz, const Vec3& Ee, double ezz, const Vec3& DEe,
                                  double DEzz) {
  return S0.dot(Ee) + S0_zz * ezz + 0.5 * (DEe[0] * Ee[0] + DEe[1] * Ee[1] + DEe[2] * Ee[2] + DEzz * ezz);
}
}  // namespace detail

// The stress at the end of a step from the total Green strain E (xx, yy, 2xy) at its end,
// the initial stress (S0, S0_zz) and the state at its start; writes the state at its end
// (`end` may be `start`). Elastic trial S = S0 + D (E - Ep) with Ee_zz = -ep_zz, principal
// stresses, return, rotation back; Ep += D^-1 (S_trial - S) (Voigt, engineering shear).
// The elastic path costs one square root. With Ep = 0 and no yield, S and the energy are
// the bits of the elastic kernel's S0 + svk_stress(E) and its strain energy density.
inline MohrCoulombResult mohr_coulomb_update(const MohrCoulombModel& mc, const Vec3& E, const Vec3& S0,
                                             double S0_zz, const MohrCoulombState& start, MohrCoulombState& end) {
  const ElasticConstants& c = mc.elastic;
  const Vec3 Ee(E[0] - start.ep_xx, E[1] - start.ep_yy, E[2] - start.ep_xy);
  const double ezz = -start.ep_zz;
  const double tr = Ee[0] + Ee[1] + ezz;
  const Vec3 DEe(c.lambda * tr + 2.0 * c.mu * Ee[0], c.lambda * tr + 2.0 * c.mu * Ee[1], c.mu * Ee[2]);
  const double DEzz = c.lambda * tr + 2.0 * c.mu * ezz;
  const Vec3 S = S0 + DEe;
  const double S_zz = S0_zz + DEzz;
  // Largest and smallest principal stress: in-plane pair C +- R and S_zz.
  const double C = 0.5 * (S[0] + S[1]);
  const double d = 0.5 * (S[0] - S[1]);
  const double R = std::sqrt(d * d + S[2] * S[2]);
  const double s1 = std::max(C + R, S_zz);
  const double s3 = std::min(C - R, S_zz);
  if (mc.k * s1 - s3 - mc.sc <= 0.0 && s1 <= mc.ft) {
    end = start;
    MohrCoulombResult out;
    out.S = S;
    out.S_zz = S_zz;
    out.strain_energy = detail::mohr_coulomb_energy(S0, S0_zz, Ee, ezz, DEe, DEzz);
    return out;
  }
  return detail::mohr_coulomb_return(mc, E, S0, S0_zz, S, S_zz, start, end);
}

// The out-of-plane stress of a plane-strain elastic state reached from zero, for an
// initial stress that came from an elastic stage: S_zz = lambda / (2 (lambda + mu)) (S_xx + S_yy).
inline double plane_strain_sigma_zz(const Vec3& S, const ElasticConstants& c) {
  return c.lambda / (2.0 * (c.lambda + c.mu)) * (S[0] + S[1]);
}

}  // namespace dsdem::fem
