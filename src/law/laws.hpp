#pragma once
// The declarations of the registered laws (one function per law, registered in
// registry.cpp), the parameter and state positions a kernel reads them at, and the
// quantities several declarations and kernels derive from the same parameters.
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string_view>

#include "law/registry.hpp"

namespace dsdem::law {

// Bulk materials (docs/theory.md §2, §10).
LawDecl linear_elastic_decl();
LawDecl mohr_coulomb_decl();
LawDecl drucker_prager_decl();
// Joints (docs/theory.md §3; paper eqs. 6-9).
LawDecl cohesive_joint_decl();
// Contacts (docs/theory.md §4; paper eqs. 1-5).
LawDecl spring_dashpot_coulomb_decl();

// An angle of the scenario (degrees) in radians, as the kernels take it, and back.
inline double radians(double deg) { return deg * (std::numbers::pi / 180.0); }
inline double degrees(double rad) { return rad / (std::numbers::pi / 180.0); }
// The apex c / tan(phi) of a Mohr-Coulomb envelope (phi in radians): the mean stress where
// its shear strength is gone, so a tension cut-off at or above it removes nothing.
// Infinite for phi = 0.
inline double envelope_apex(double c, double phi) {
  return phi > 0.0 ? c / std::tan(phi) : std::numeric_limits<double>::infinity();
}

// Positions in Material::params (declaration order); a test checks them against the
// declarations. Angles are in degrees, as the scenario gives them.
namespace linear_elastic {
inline constexpr std::string_view kName = "linear_elastic";
enum Param : int { E, nu, rho, kParams };
}  // namespace linear_elastic
// The state of the plane-strain plastic laws: the plastic Green strain and the plastic
// work (positions among the law's declared state variables, Material::state_columns).
namespace plastic_state {
enum State : int { plastic_strain_xx, plastic_strain_yy, plastic_strain_xy, plastic_strain_zz, plastic_dissipation, kStates };
inline constexpr std::array<StateVariable, kStates> kVariables{{
    {"plastic_strain_xx", "", "Plastic strain xx (additive part of the Green strain)."},
    {"plastic_strain_yy", "", "Plastic strain yy."},
    {"plastic_strain_xy", "", "Plastic engineering shear strain (2 E_xy)."},
    {"plastic_strain_zz", "", "Plastic strain zz (out of plane; in plane strain the total stays zero)."},
    {"plastic_dissipation", "J/m^3", "Plastic work per unit reference volume, accumulated (never negative)."},
}};
}  // namespace plastic_state
namespace mohr_coulomb {
inline constexpr std::string_view kName = "mohr_coulomb";
enum Param : int { E, nu, rho, cohesion, friction_angle, dilation_angle, tensile_strength, kParams };
using enum plastic_state::State;
}  // namespace mohr_coulomb
namespace drucker_prager {
inline constexpr std::string_view kName = "drucker_prager";
enum Param : int { E, nu, rho, cohesion, friction_angle, dilation_angle, kParams };
using enum plastic_state::State;
}  // namespace drucker_prager

// The Mohr-Coulomb envelope of a plastic law's parameter values (declaration order), angles
// in radians: cohesion, friction and dilation angle stand at the same positions in each.
struct Envelope {
  double c, phi, psi;
};
inline Envelope envelope(std::span<const double> v) {
  return {v[mohr_coulomb::cohesion], radians(v[mohr_coulomb::friction_angle]), radians(v[mohr_coulomb::dilation_angle])};
}

}  // namespace dsdem::law
