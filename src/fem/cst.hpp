#pragma once
// Constant-strain triangle, total Lagrangian (DESIGN.md §2): objective for any rigid
// rotation, unlike the paper's incremental tau + D*B*du update.
#include "model/types.hpp"

namespace dsdem::fem {

// Elastic constants in the form the kernel needs (plane strain or plane stress).
struct ElasticConstants {
  double lambda = 0.0;  // Pa (plane-stress lambda when plane stress)
  double mu = 0.0;      // Pa
};

// Reference geometry of a triangle: inverse edge matrix and signed area.
struct ReferenceGeometry {
  Mat2 Dm_inv;
  double area = 0.0;  // signed; > 0 for counter-clockwise
};
ReferenceGeometry reference_geometry(const Vec2& X0, const Vec2& X1, const Vec2& X2);

// Deformation gradient F = [x1-x0, x2-x0] * Dm^-1.
Mat2 deformation_gradient(const Vec2& x0, const Vec2& x1, const Vec2& x2, const Mat2& Dm_inv);

// Green-Lagrange strain (xx, yy, 2xy) from F.
Vec3 green_strain(const Mat2& F);

// Second Piola-Kirchhoff stress of St Venant-Kirchhoff, S = S0 + D E (Voigt).
Vec3 svk_stress(const Vec3& green_voigt, const ElasticConstants& c);

// Cauchy stress sigma = F S F^T / det F (Voigt xx, yy, xy).
Vec3 cauchy_from_pk2(const Mat2& F, const Vec3& S);

// Result of one element evaluation.
struct TriangleResponse {
  std::array<Vec2, 3> force;  // internal force on each node (already with sign: add to f), N
  Vec3 cauchy;                // Pa, elastic + initial stress (no damping part)
  Vec3 green;                 // Green strain, Voigt with engineering shear
  double strain_energy = 0.0; // J (per thickness as given)
  double detF = 1.0;
};

// Internal forces of one CST: P = F S with S = S0 + D E + beta D Edot (stiffness-
// proportional Rayleigh damping as a viscous stress, DESIGN.md §6); the damping part is
// returned separately so the energy balance can book it as dissipation.
struct TriangleInput {
  std::array<Vec2, 3> x;  // current positions
  std::array<Vec2, 3> v;  // velocities (used only when beta > 0)
  Mat2 Dm_inv;
  double area0 = 0.0;      // reference area, m^2
  double thickness = 1.0;  // m
  Vec3 S0 = Vec3::Zero();  // initial stress, kept from an earlier stage (PK2 in reference frame)
  double beta = 0.0;       // Rayleigh stiffness coefficient, s
  bool cauchy = true;      // false: out.cauchy is left as it was (a solver that needs it only for output)
};
void triangle_internal_force(const TriangleInput& in, const ElasticConstants& c,
                             TriangleResponse& out, std::array<Vec2, 3>& damping_force);

// Characteristic length for the CFL limit: the smallest altitude 2A / longest edge.
double characteristic_length(const Vec2& x0, const Vec2& x1, const Vec2& x2);

// Critical time step of an element with P-wave speed cp and stiffness damping beta:
// dt = (2/omega)(sqrt(1+xi^2) - xi), omega = 2 cp / h, xi = beta omega / 2.
double critical_time_step(double h, double cp, double beta);

}  // namespace dsdem::fem
