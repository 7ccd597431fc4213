#pragma once
// Weakly compressible SPH in the vertical plane (docs/theory.md §11): the pair kernels, pure
// functions of two particles' data. The formulation is that of DualSPHysics (Dominguez et
// al. 2022): Wendland C2 smoothing kernel, Tait equation of state, Monaghan's artificial
// viscosity and the density diffusion of Fourtakas et al. (2019). Per unit width (2D):
// masses in kg/m, densities in kg/m^3. r_ij = x_i - x_j, v_ij = v_i - v_j.
#include <cmath>

#include "model/types.hpp"

namespace dsdem::sph {

// Wendland C2 in 2D (Wendland 1995; Dehnen & Aly 2012): W(q) = aD (1 - q/2)^4 (2q + 1),
// q = r / h < 2, aD = 7 / (4 pi h^2). Unit integral over the plane.
inline double wendland_normalisation(double h) { return 7.0 / (4.0 * kPi * h * h); }

// W(r) for r^2 = r2 (0 at and beyond the support 2h).
inline double wendland(double r2, double h) {
  const double q = std::sqrt(r2) / h;
  if (q >= 2.0) return 0.0;
  const double u = 1.0 - 0.5 * q;
  const double u2 = u * u;
  return wendland_normalisation(h) * u2 * u2 * (2.0 * q + 1.0);
}

// The gradient factor F with grad_i W_ij = F r_ij: F = W'(r) / r = -5 aD (1 - q/2)^3 / h^2
// (0 beyond the support). Branch-free. The hot loops pass 1 / h and the constant.
inline double wendland_gradient_factor(double r2, double inv_h, double minus_five_aD_over_h2) {
  const double q = std::sqrt(r2) * inv_h;
  const double t = 1.0 - 0.5 * q;
  // max(t, 0) without a branch (a neighbour list with a skin holds pairs beyond the support;
  // not std::fmax: a library call without -ffast-math). Exact: t + |t| = 2t or 0.
  const double u = 0.5 * (t + std::fabs(t));
  return minus_five_aD_over_h2 * u * u * u;
}
inline double wendland_gradient_factor(double r2, double h) {
  return wendland_gradient_factor(r2, 1.0 / h, -5.0 * wendland_normalisation(h) / (h * h));
}

// Tait's equation of state (docs/theory.md §11): p = B ((rho / rho0)^7 - 1), B = rho0 c0^2 / 7,
// so that dp/drho = c0^2 at rho0.
inline double tait_b(double rho0, double c0) { return rho0 * c0 * c0 / 7.0; }
inline double tait_pressure(double rho, double rho0, double b) {
  const double r = rho / rho0;
  const double r2 = r * r;
  return b * (r2 * r2 * r2 * r - 1.0);
}
// The density at pressure p (the inverse of tait_pressure).
inline double tait_density(double p, double rho0, double b) { return rho0 * std::pow(1.0 + p / b, 1.0 / 7.0); }
// Speed of sound c(rho) = sqrt(dp/drho) = c0 (rho / rho0)^3.
inline double tait_sound_speed(double rho, double rho0, double c0) {
  const double r = rho / rho0;
  return c0 * r * r * r;
}

// Monaghan's (1992) artificial viscosity Pi_ij: -alpha c mu_ij / rho_bar for approaching
// particles (v_ij . r_ij < 0), mu_ij = h v_ij . r_ij / (r^2 + 0.01 h^2), else 0. It enters
// the momentum equation as -m_j Pi_ij grad_i W_ij. Symmetric in i and j.
inline double artificial_viscosity(double vr, double r2, double rho_i, double rho_j, double h, double alpha_c) {
  // One division: -alpha c h v.r / ((r^2 + 0.01 h^2) (rho_i + rho_j) / 2). min(v.r, 0)
  // without a branch (approaching and receding pairs are mixed): v.r - |v.r| = 2 v.r or 0.
  return -2.0 * alpha_c * h * (0.5 * (vr - std::fabs(vr))) / ((r2 + 0.01 * h * h) * (rho_i + rho_j));
}

// The artificial viscosity of a free-slip wall (docs/theory.md §11, "Walls"): Monaghan's term
// for the pair's motion along the wall's normal n alone, vn = v_ib . n, rn = r_ib . n, acting
// along n: dv_i/dt gains -m_b f F n, the wall the reaction. It resists the approach through
// the face and never the sliding along it, and it only dissipates (the power is -m_i m_b f F vn
// with f vn <= 0). Along r_ib with the full v_ib the wall would hold the water still at its face
// (the no-slip wall, WallViscosity::NoSlip).
inline double wall_normal_viscosity(double vn, double rn, double r2, double rho_i, double rho_b, double h,
                                    double alpha_c) {
  return artificial_viscosity(vn * rn, r2, rho_i, rho_b, h, alpha_c) * rn;
}

// Pressure part of the momentum equation (DualSPHysics' form): -m_j (p_i + p_j) / (rho_i
// rho_j) grad_i W_ij is dv_i/dt; the factor returned multiplies -m_j grad_i W_ij.
// Symmetric in i and j, so the pair's forces are equal and opposite.
inline double pressure_term(double p_i, double p_j, double rho_i, double rho_j) {
  return (p_i + p_j) / (rho_i * rho_j);
}

// The hydrostatic part of the density difference rho_j - rho_i (Fourtakas et al. 2019,
// eq. 13): the pressure difference rho g . (x_j - x_i) over c^2(rho) = c0^2 (rho/rho0)^6, at
// the pair's mean density. Antisymmetric in i and j.
inline double hydrostatic_density_difference(double gx_dx_gy_dy, double rho_i, double rho_j, double rho0,
                                             double c0) {
  const double rho = 0.5 * (rho_i + rho_j);
  const double r = rho / rho0;
  const double r2 = r * r;
  return rho * gx_dx_gy_dy / (c0 * c0 * r2 * r2 * r2);
}

// Density diffusion (Molteni & Colagrossi 2009; Fourtakas et al. 2019): the term of
// drho_i/dt from neighbour j, delta h c0 psi_ij . grad_i W_ij V_j with psi_ij = 2 (rho_ji -
// rho_ji^H) (x_j - x_i) / r^2 and V_j = m_j / rho_j; with grad_i W_ij = F r_ij this is
// -2 delta h c0 F (rho_ji - rho_ji^H) V_j. Times V_i it is antisymmetric in i and j, so
// the diffusion moves density between particles without creating volume-weighted mass.
inline double density_diffusion(double delta_h_c0, double f, double rho_diff, double volume_j) {
  return -2.0 * delta_h_c0 * f * rho_diff * volume_j;
}

// The renormalised density gradient's correction to the diffusion (delta-SPH: Antuono et al.
// 2010, Marrone et al. 2011): psi_ij gains -(grad rho_i^L + grad rho_j^L), which cancels the
// Molteni term for any linear density field (hydrostatics, and the surface layer's
// equilibrium, which is not Tait's hydrostatic one). As a term of drho_i/dt:
// delta h c0 F (g_i + g_j) . (x_j - x_i) V_j, with g = grad rho^L. Times V_i antisymmetric.
inline double density_gradient_correction(double delta_h_c0, double f, double gsum_dot_rji, double volume_j) {
  return delta_h_c0 * f * gsum_dot_rji * volume_j;
}

// The time-step limit (docs/theory.md §11): dt <= cfl h / (c0 + v_max), and the force
// condition 0.25 sqrt(h / a_max) (Monaghan 1989).
inline double stable_time_step(double h, double c0, double v_max, double a_max, double cfl) {
  const double dt_c = cfl * h / (c0 + v_max);
  if (a_max <= 0.0) return dt_c;
  return std::fmin(dt_c, 0.25 * std::sqrt(h / a_max));
}

}  // namespace dsdem::sph
