#pragma once
// The declarations of the registered laws (one function per law, registered in
// registry.cpp), and the parameter and state positions a kernel reads them at.
#include "law/registry.hpp"

namespace dsdem::law {

// Bulk materials (DESIGN.md §2, §12).
LawDecl linear_elastic_decl();
LawDecl mohr_coulomb_decl();
// Joints (DESIGN.md §3; paper eqs. 6-9).
LawDecl cohesive_joint_decl();
// Contacts (DESIGN.md §4; paper eqs. 1-5).
LawDecl spring_dashpot_coulomb_decl();

// Positions in Material::params (declaration order); a test checks them against the
// declarations. Angles are in degrees, as the scenario gives them.
namespace linear_elastic {
enum Param : int { E, nu, rho, kParams };
}
namespace mohr_coulomb {
enum Param : int { E, nu, rho, cohesion, friction_angle, dilation_angle, tensile_strength, kParams };
// Positions among the law's declared state variables (Material::state_columns).
enum State : int { plastic_strain_xx, plastic_strain_yy, plastic_strain_xy, plastic_strain_zz, plastic_dissipation, kStates };
}  // namespace mohr_coulomb

}  // namespace dsdem::law
