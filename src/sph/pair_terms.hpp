#pragma once
// A fluid pair's terms in the two passes of sph::Fluid (docs/theory.md §11), from the kernels of
// kernels.hpp: pure functions of the two particles' values (a = the particle whose sums take
// them, b = its partner). Seen from b the terms are the same mirrored exactly: continuity
// and the gradient products symmetric, diffusion and acceleration the same values negated.
#include "sph/kernels.hpp"

namespace dsdem::sph {

// One particle's values read by the density pass.
struct DensityPoint {
  double x, y, vx, vy, rho, gx, gy;
};
struct DensityPairConstants {
  double inv_h, grad_c, mass, delta_h_c0, gx, gy, rho0, c0;
};
// F (grad_a W_ab = F r_ab), the continuity term c = m F v_ab . r_ab (drho_a/dt and drho_b/dt
// both gain it) and the diffusion q without the other's volume (drho_a/dt gains q V_b,
// drho_b/dt loses q V_a). Fourtakas et al. (2019) eq. 13, or delta-SPH (Antuono et al. 2010)
// with the renormalised gradients gx, gy. Beyond the support every term is 0.
struct DensityPairTerms {
  double f, c, q;
};
template <bool fourtakas>
inline DensityPairTerms density_pair(const DensityPairConstants& k, const DensityPoint& a, const DensityPoint& b) {
  const double dx = a.x - b.x, dy = a.y - b.y;
  DensityPairTerms t;
  t.f = wendland_gradient_factor(dx * dx + dy * dy, k.inv_h, k.grad_c);
  t.c = k.mass * t.f * ((a.vx - b.vx) * dx + (a.vy - b.vy) * dy);
  if constexpr (fourtakas) {
    const double rho_h = hydrostatic_density_difference(-(k.gx * dx + k.gy * dy), a.rho, b.rho, k.rho0, k.c0);
    t.q = density_diffusion(k.delta_h_c0, t.f, b.rho - a.rho - rho_h, 1.0);
  } else {
    t.q = density_diffusion(k.delta_h_c0, t.f, b.rho - a.rho, 1.0) +
          density_gradient_correction(k.delta_h_c0, t.f, -((a.gx + b.gx) * dx + (a.gy + b.gy) * dy), 1.0);
  }
  return t;
}

// One particle's values read by the force pass.
struct ForcePoint {
  double x, y, vx, vy, rho, p;
};
struct ForcePairConstants {
  double h, alpha_c, mass, inv_h, grad_c;  // grad_c: wendland_gradient_factor's constant
};
// With the pair's F: a's acceleration from b (pressure and artificial viscosity; b's is
// minus it) and the renormalised gradient's products F r r^T and (rho_b - rho_a) F r, the
// same for both (each weighted by the other's volume: M = -sum V F r r^T, sum V (rho_j -
// rho_i) F r; Marrone et al. 2011).
struct ForcePairTerms {
  double ax = 0.0, ay = 0.0, xx = 0.0, xy = 0.0, yy = 0.0, sx = 0.0, sy = 0.0;
};
template <bool grad>
inline ForcePairTerms force_pair(const ForcePairConstants& k, const ForcePoint& a, const ForcePoint& b, double f) {
  const double dx = a.x - b.x, dy = a.y - b.y;
  const double visc =
      artificial_viscosity((a.vx - b.vx) * dx + (a.vy - b.vy) * dy, dx * dx + dy * dy, a.rho, b.rho, k.h, k.alpha_c);
  const double coef = -k.mass * (pressure_term(a.p, b.p, a.rho, b.rho) + visc) * f;
  ForcePairTerms t;
  t.ax = coef * dx;
  t.ay = coef * dy;
  if constexpr (grad) {
    const double fdx = f * dx, fdy = f * dy, dr = b.rho - a.rho;
    t.xx = fdx * dx;
    t.xy = fdx * dy;
    t.yy = fdy * dy;
    t.sx = dr * fdx;
    t.sy = dr * fdy;
  }
  return t;
}

// One particle's sums of the force pass: acceleration and the renormalised gradient's
// matrix and right-hand side (one cache line).
struct ForceSums {
  double ax, ay, mxx, mxy, myy, sx, sy, pad;
};
}  // namespace dsdem::sph
