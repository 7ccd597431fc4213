#pragma once
// Constant-strain triangle, total Lagrangian (docs/theory.md §2): objective for any rigid
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

// The per-step kernel and its pieces are inline, the kernel always (GCC otherwise keeps it
// a call in the solver's element region): the element loops then keep them in registers and
// drop what their caller does not read (the damping forces' zeros without beta, the Cauchy
// stress and the strain of a step that does not store them).
// The library is built for the baseline x86-64 (no FMA instructions to contract into), so
// inlining leaves every result the same bits.

// Deformation gradient F = [x1-x0, x2-x0] * Dm^-1.
inline Mat2 deformation_gradient(const Vec2& x0, const Vec2& x1, const Vec2& x2, const Mat2& Dm_inv) {
  Mat2 Ds;
  Ds.col(0) = x1 - x0;
  Ds.col(1) = x2 - x0;
  return Ds * Dm_inv;
}

// Green-Lagrange strain (xx, yy, 2xy) from F.
inline Vec3 green_strain(const Mat2& F) {
  const Mat2 C = F.transpose() * F;
  return Vec3(0.5 * (C(0, 0) - 1.0), 0.5 * (C(1, 1) - 1.0), C(0, 1));
}

// Second Piola-Kirchhoff stress of St Venant-Kirchhoff, S = S0 + D E (Voigt).
inline Vec3 svk_stress(const Vec3& E, const ElasticConstants& c) {
  const double tr = E[0] + E[1];
  return Vec3(c.lambda * tr + 2.0 * c.mu * E[0], c.lambda * tr + 2.0 * c.mu * E[1], c.mu * E[2]);
}

// Green strain rate (xx, yy, 2xy) = sym(F^T Fdot) (docs/theory.md §6), in scalars: M = F^T Fdot
// and (Fdot^T F)(r, c) = M(c, r) bit for bit (two products, one addition each). Eigen's
// 0.5 * (F^T Fdot + Fdot^T F) stores the products as scalars and loads them as pairs, a
// store-forwarding stall.
inline Vec3 strain_rate(const Mat2& F, const Mat2& Fdot) {
  const double m00 = F(0, 0) * Fdot(0, 0) + F(1, 0) * Fdot(1, 0);
  const double m01 = F(0, 0) * Fdot(0, 1) + F(1, 0) * Fdot(1, 1);
  const double m10 = F(0, 1) * Fdot(0, 0) + F(1, 1) * Fdot(1, 0);
  const double m11 = F(0, 1) * Fdot(0, 1) + F(1, 1) * Fdot(1, 1);
  return Vec3(0.5 * (m00 + m00), 0.5 * (m11 + m11), 2.0 * (0.5 * (m01 + m10)));
}

namespace detail {
inline Mat2 to_tensor(const Vec3& s) {
  Mat2 m;
  m << s[0], s[2], s[2], s[1];
  return m;
}

// Nodal forces -A0 t P grad0(N): nodes 1 and 2 take the columns of P Dm_inv^T, node 0
// the negative of their sum (the shape-function gradients sum to zero).
inline void nodal_forces(const Mat2& P, const Mat2& Dm_inv, double scale, std::array<Vec2, 3>& f) {
  const Mat2 H = -scale * P * Dm_inv.transpose();
  f[1] = H.col(0);
  f[2] = H.col(1);
  f[0] = -(f[1] + f[2]);
}
}  // namespace detail

// Cauchy stress sigma = F S F^T / det F (Voigt xx, yy, xy).
inline Vec3 cauchy_from_pk2(const Mat2& F, const Vec3& S) {
  const Mat2 sigma = F * detail::to_tensor(S) * F.transpose() / F.determinant();
  return Vec3(sigma(0, 0), sigma(1, 1), 0.5 * (sigma(0, 1) + sigma(1, 0)));
}

// Result of one element evaluation.
struct TriangleResponse {
  std::array<Vec2, 3> force;  // internal force on each node (already with sign: add to f), N
  Vec3 cauchy = Vec3::Zero();  // Pa, elastic + initial stress (no damping part); zero when not asked for
  Vec3 green;                 // Green strain, Voigt with engineering shear
  double strain_energy = 0.0; // J (per thickness as given)
  double detF = 1.0;
};

// Internal forces of one CST: P = F S with S = S0 + D E + beta D Edot (stiffness-
// proportional Rayleigh damping as a viscous stress, docs/theory.md §6); the damping part is
// returned separately so the energy balance can book it as dissipation.
struct TriangleInput {
  std::array<Vec2, 3> x;  // current positions
  std::array<Vec2, 3> v{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};  // velocities (read only when beta > 0)
  Mat2 Dm_inv;
  double area0 = 0.0;      // reference area, m^2
  double thickness = 1.0;  // m
  Vec3 S0 = Vec3::Zero();  // initial stress, kept from an earlier stage (PK2 in reference frame)
  double beta = 0.0;       // Rayleigh stiffness coefficient, s
  bool cauchy = true;      // false: out.cauchy is left as it was (a solver that needs it only for output)
};
[[gnu::always_inline]] inline void triangle_internal_force(const TriangleInput& in, const ElasticConstants& c,
                                                           TriangleResponse& out, std::array<Vec2, 3>& damping_force) {
  const Mat2 F = deformation_gradient(in.x[0], in.x[1], in.x[2], in.Dm_inv);
  out.detF = F.determinant();
  const Vec3 E = green_strain(F);
  const Vec3 S = in.S0 + svk_stress(E, c);
  const double scale = in.area0 * in.thickness;
  detail::nodal_forces(F * detail::to_tensor(S), in.Dm_inv, scale, out.force);
  out.green = E;
  if (in.cauchy) out.cauchy = cauchy_from_pk2(F, S);
  const Vec3 DE = svk_stress(E, c);
  out.strain_energy = scale * (in.S0.dot(E) + 0.5 * (DE[0] * E[0] + DE[1] * E[1] + DE[2] * E[2]));

  if (in.beta > 0.0) {
    // Edot = sym(F^T Fdot); damping stress beta * D Edot (docs/theory.md §6).
    const Mat2 Fdot = deformation_gradient(in.v[0], in.v[1], in.v[2], in.Dm_inv);
    const Vec3 Sd = in.beta * svk_stress(strain_rate(F, Fdot), c);
    detail::nodal_forces(F * detail::to_tensor(Sd), in.Dm_inv, scale, damping_force);
  } else {
    damping_force = {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  }
}

// Characteristic length for the CFL limit: the smallest altitude 2A / longest edge.
double characteristic_length(const Vec2& x0, const Vec2& x1, const Vec2& x2);

// Critical time step of an element with P-wave speed cp and stiffness damping beta:
// dt = (2/omega)(sqrt(1+xi^2) - xi), omega = 2 cp / h, xi = beta omega / 2.
double critical_time_step(double h, double cp, double beta);

}  // namespace dsdem::fem
