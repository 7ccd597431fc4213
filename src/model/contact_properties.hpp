#pragma once
// Contact parameters of a pair of surface groups as the user gives them (docs/theory.md §4;
// 2D: per unit thickness). Data only: the contact law (contact/contact_law.hpp) reads them.
namespace dsdem {

struct ContactProperties {
  double kn = 0.0;           // normal stiffness, Pa (N/m per m of thickness)
  double ks = 0.0;           // tangential stiffness, Pa
  double mu = 0.0;           // Coulomb friction coefficient
  double restitution = 1.0;  // normal coefficient of restitution e in (0, 1]; 1 = no dashpot
};

}  // namespace dsdem
