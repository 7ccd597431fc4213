#pragma once
// Linear tetrahedron, total Lagrangian (docs/theory.md §2): the 3D form of the constant-strain
// triangle of cst.hpp, objective for any rigid rotation. Pure kernels: nothing here reads the
// model, so the 3D element loop can gather and scatter as the 2D one does.
//
// Voigt order for symmetric 3D tensors, everywhere in this file: (xx, yy, zz, yz, xz, xy).
// Strains (Green strain and its rate) carry engineering shears (2 E_yz, 2 E_xz, 2 E_xy);
// stresses carry the tensor components, so S . E is the double contraction S : E.
#include "fem/cst.hpp"
#include "model/types.hpp"

namespace dsdem::fem {

using Vec6 = dsdem::Vec6;  // symmetric 3D tensor, Voigt (xx, yy, zz, yz, xz, xy)

// Reference geometry of a tetrahedron: inverse edge matrix and signed volume.
struct TetReferenceGeometry {
  Mat3 Dm_inv;
  double volume = 0.0;  // signed, det(Dm) / 6; > 0 when (X1-X0, X2-X0, X3-X0) is right-handed
};
TetReferenceGeometry tet_reference_geometry(const Vec3& X0, const Vec3& X1, const Vec3& X2, const Vec3& X3);

// The per-step kernel and its pieces are inline, the kernel always, as the triangle's are
// (cst.hpp): the element loop keeps them in registers and drops what it does not read.

// Deformation gradient F = [x1-x0, x2-x0, x3-x0] * Dm^-1.
inline Mat3 deformation_gradient(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3, const Mat3& Dm_inv) {
  Mat3 Ds;
  Ds.col(0) = x1 - x0;
  Ds.col(1) = x2 - x0;
  Ds.col(2) = x3 - x0;
  return Ds * Dm_inv;
}

// Green-Lagrange strain (F^T F - I) / 2, Voigt (xx, yy, zz, 2yz, 2xz, 2xy).
inline Vec6 green_strain(const Mat3& F) {
  const Mat3 C = F.transpose() * F;
  Vec6 E;
  E << 0.5 * (C(0, 0) - 1.0), 0.5 * (C(1, 1) - 1.0), 0.5 * (C(2, 2) - 1.0), C(1, 2), C(0, 2), C(0, 1);
  return E;
}

// St Venant-Kirchhoff D E = lambda tr(E) I + 2 mu E with the 3D Lame constants (no plane
// reduction), E in engineering shears, the result in tensor components (Voigt as above).
inline Vec6 svk_stress(const Vec6& E, const ElasticConstants& c) {
  const double tr = E[0] + E[1] + E[2];
  Vec6 S;
  S << c.lambda * tr + 2.0 * c.mu * E[0], c.lambda * tr + 2.0 * c.mu * E[1], c.lambda * tr + 2.0 * c.mu * E[2],
      c.mu * E[3], c.mu * E[4], c.mu * E[5];
  return S;
}

// Green strain rate sym(F^T Fdot), Voigt with engineering shears: with M = F^T Fdot the shear
// 2 sym(M)_ij is M_ij + M_ji, no halving and doubling.
inline Vec6 strain_rate(const Mat3& F, const Mat3& Fdot) {
  const Mat3 M = F.transpose() * Fdot;
  Vec6 Ed;
  Ed << M(0, 0), M(1, 1), M(2, 2), M(1, 2) + M(2, 1), M(0, 2) + M(2, 0), M(0, 1) + M(1, 0);
  return Ed;
}

namespace detail {
inline Mat3 to_tensor(const Vec6& s) {
  Mat3 m;
  m << s[0], s[5], s[4],  //
      s[5], s[1], s[3],   //
      s[4], s[3], s[2];
  return m;
}

// Nodal forces -V0 P grad0(N): nodes 1..3 take the columns of -V0 P Dm_inv^T, node 0 the
// negative of their sum (the shape-function gradients sum to zero).
inline void tet_nodal_forces(const Mat3& P, const Mat3& Dm_inv, double volume0, std::array<Vec3, 4>& f) {
  const Mat3 H = -volume0 * P * Dm_inv.transpose();
  f[1] = H.col(0);
  f[2] = H.col(1);
  f[3] = H.col(2);
  f[0] = -(f[1] + f[2] + f[3]);
}
}  // namespace detail

// Cauchy stress sigma = F S F^T / det F, Voigt (xx, yy, zz, yz, xz, xy).
inline Vec6 cauchy_from_pk2(const Mat3& F, const Vec6& S) {
  const Mat3 sigma = F * detail::to_tensor(S) * F.transpose() / F.determinant();
  Vec6 s;
  s << sigma(0, 0), sigma(1, 1), sigma(2, 2), 0.5 * (sigma(1, 2) + sigma(2, 1)), 0.5 * (sigma(0, 2) + sigma(2, 0)),
      0.5 * (sigma(0, 1) + sigma(1, 0));
  return s;
}

// Result of one tetrahedron evaluation.
struct TetResponse {
  std::array<Vec3, 4> force;   // internal force on each node (already with sign: add to f), N
  Vec6 cauchy = Vec6::Zero();  // Pa, elastic + initial stress (no damping part); left as it was when not asked for
  Vec6 green;                  // Green strain, Voigt with engineering shears
  double strain_energy = 0.0;  // J, V0 (S0 : E + E : D : E / 2)
  double detF = 1.0;           // <= 0: inverted
};

// Internal forces of one tetrahedron: P = F S with S = S0 + D E + beta D Edot (stiffness-
// proportional Rayleigh damping as a viscous stress, docs/theory.md §6); the damping part is
// returned separately so the energy balance can book it as dissipation.
struct TetInput {
  std::array<Vec3, 4> x;  // current positions
  std::array<Vec3, 4> v{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};  // velocities (read only when beta > 0)
  Mat3 Dm_inv;
  double volume0 = 0.0;    // reference volume, m^3
  Vec6 S0 = Vec6::Zero();  // initial stress, kept from an earlier stage (PK2 in reference frame)
  double beta = 0.0;       // Rayleigh stiffness coefficient, s
  bool cauchy = true;      // false: out.cauchy is left as it was
};
[[gnu::always_inline]] inline void tet_internal_force(const TetInput& in, const ElasticConstants& c, TetResponse& out,
                                                      std::array<Vec3, 4>& damping_force) {
  const Mat3 F = deformation_gradient(in.x[0], in.x[1], in.x[2], in.x[3], in.Dm_inv);
  out.detF = F.determinant();
  const Vec6 E = green_strain(F);
  const Vec6 DE = svk_stress(E, c);
  const Vec6 S = in.S0 + DE;
  detail::tet_nodal_forces(F * detail::to_tensor(S), in.Dm_inv, in.volume0, out.force);
  out.green = E;
  if (in.cauchy) out.cauchy = cauchy_from_pk2(F, S);
  out.strain_energy = in.volume0 * (in.S0.dot(E) + 0.5 * DE.dot(E));

  if (in.beta > 0.0) {
    const Mat3 Fdot = deformation_gradient(in.v[0], in.v[1], in.v[2], in.v[3], in.Dm_inv);
    const Vec6 Sd = in.beta * svk_stress(strain_rate(F, Fdot), c);
    detail::tet_nodal_forces(F * detail::to_tensor(Sd), in.Dm_inv, in.volume0, damping_force);
  } else {
    damping_force = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  }
}

// Characteristic length for the CFL limit: the smallest altitude, 3 V / largest face area
// (docs/theory.md §2). Zero for a degenerate tetrahedron.
double characteristic_length(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3);

// Critical time step of a tetrahedron: critical_time_step (cst.hpp) of its smallest altitude.
inline double tet_critical_time_step(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3, double cp,
                                     double beta) {
  return critical_time_step(characteristic_length(x0, x1, x2, x3), cp, beta);
}

// Lumped mass of each of the four nodes, rho V0 / 4 (docs/theory.md §2).
inline double tet_lumped_mass(double rho, double volume0) { return 0.25 * rho * volume0; }

}  // namespace dsdem::fem
