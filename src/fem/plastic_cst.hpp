#pragma once
// The total Lagrangian CST (cst.hpp) with the Mohr-Coulomb bulk law (mohr_coulomb.hpp,
// DESIGN.md §12): the same deformation gradient, nodal forces P = F S and Cauchy stress as
// the elastic kernel, with S from the return mapping. Stiffness-proportional Rayleigh
// damping stays the viscous stress beta D Edot on the elastic D (DESIGN.md §6).
#include "fem/cst.hpp"
#include "fem/mohr_coulomb.hpp"

namespace dsdem::fem {

struct PlasticTriangleResponse {
  double dissipation = 0.0;  // plastic work of this update per unit reference volume, J/m^3
  double S_zz = 0.0;         // out-of-plane PK2 stress, Pa
  MohrCoulombRegion region = MohrCoulombRegion::Elastic;
};

// in.S0 is the initial stress; S0_zz its out-of-plane part. The state at the step's start
// is `start`, the state at its end goes to `end` (a separate record: evaluating twice from
// the same start gives the same bits).
[[gnu::always_inline]] inline PlasticTriangleResponse triangle_internal_force_mohr_coulomb(
    const TriangleInput& in, const MohrCoulombModel& mc, double S0_zz, const MohrCoulombState& start,
    MohrCoulombState& end, TriangleResponse& out, std::array<Vec2, 3>& damping_force) {
  const Mat2 F = deformation_gradient(in.x[0], in.x[1], in.x[2], in.Dm_inv);
  out.detF = F.determinant();
  const Vec3 E = green_strain(F);
  const MohrCoulombResult r = mohr_coulomb_update(mc, E, in.S0, S0_zz, start, end);
  const double scale = in.area0 * in.thickness;
  detail::nodal_forces(F * detail::to_tensor(r.S), in.Dm_inv, scale, out.force);
  out.green = E;
  if (in.cauchy) out.cauchy = cauchy_from_pk2(F, r.S);
  out.strain_energy = scale * r.strain_energy;
  if (in.beta > 0.0) {
    const Mat2 Fdot = deformation_gradient(in.v[0], in.v[1], in.v[2], in.Dm_inv);
    const Vec3 Sd = in.beta * svk_stress(strain_rate(F, Fdot), mc.elastic);
    detail::nodal_forces(F * detail::to_tensor(Sd), in.Dm_inv, scale, damping_force);
  } else {
    damping_force = {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  }
  return {r.dissipation, r.S_zz, r.region};
}

}  // namespace dsdem::fem
