// Packing of the water while it settles (sph::Fluid::set_packing, sph::settle): particle
// shifting (Lind et al. 2012) before the run, never during it.
#include <algorithm>
#include <cmath>

#include "sph/fluid.hpp"
#include "sph/kernels.hpp"

namespace dsdem::sph {

namespace {
// Below this divergence of the position (2 with a full support in 2D) a particle is at or
// near the free surface and is not shifted: its gradient points into the water.
constexpr double kFreeSurfaceDivergence = 1.9;
// settle()'s packing coefficient A (delta r = -A h^2 grad C a step); docs/validation.md §5.6
// says how it was chosen.
constexpr double kSettlePacking = 0.05;
}  // namespace

double settle(Fluid& fluid, double duration, double rate) {
  if (!(duration > 0.0)) return fluid.max_speed();
  fluid.set_settling_damping(rate);
  fluid.set_packing(kSettlePacking);
  const double packed = fluid.time() + 0.5 * duration, end = fluid.time() + duration;
  while (fluid.time() < end - 1e-12) {
    if (fluid.time() >= packed) fluid.set_packing(0.0);
    fluid.step(std::min(fluid.stable_dt(), end - fluid.time()));
  }
  fluid.set_packing(0.0);
  fluid.set_settling_damping(0.0);
  fluid.reset_boundary_work();
  return fluid.max_speed();
}

// grad C_i = sum_j V_j grad_i W_ij over the fluid and wall partners within the support,
// div r_i = -sum_j V_j F_ij r_ij^2; delta r_i = -A h^2 grad C_i (at most dp / 10 a step),
// rho_i += delta r_i . grad rho_i (delta-SPH's renormalised gradient of the last force pass;
// Fourtakas' diffusion computes none and the density stays).
void Fluid::pack_particles() {
  const double inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_, a_h2 = packing_ * h_ * h_, limit = 0.1 * par_.dp;
  const auto border = boundary_cells_.order();
  const double mb = b_.mass;
  exec::parallel_for(team_, f_.size(), [&](std::size_t i) {
    const double xi = f_.x[i], yi = f_.y[i];
    double gx = 0.0, gy = 0.0, div = 0.0;
    const std::int32_t* list = nb_j_.get() + nb_at_[i];
    for (std::int32_t s = 0; s < nb_n_[i]; ++s) {
      const auto j = static_cast<std::size_t>(list[s]);
      const double dx = xi - f_.x[j], dy = yi - f_.y[j], r2 = dx * dx + dy * dy;
      const double vf = f_.vol[j] * wendland_gradient_factor(r2, inv_h, gc);
      gx += vf * dx;
      gy += vf * dy;
      div -= vf * r2;
    }
    const int cell = fluid_cells_.cell(i);
    if (near_wall_[static_cast<std::size_t>(cell)])
      boundary_cells_.for_each_range(cell, [&](std::int32_t k0, std::int32_t k1) {
        for (std::int32_t k = k0; k < k1; ++k) {
          const auto b = static_cast<std::size_t>(border[static_cast<std::size_t>(k)]);
          const double dx = xi - b_.x[b], dy = yi - b_.y[b], r2 = dx * dx + dy * dy;
          if (r2 >= s2) continue;
          const double vf = mb / b_.rho[b] * wendland_gradient_factor(r2, inv_h, gc);
          gx += vf * dx;
          gy += vf * dy;
          div -= vf * r2;
        }
      });
    double sx = 0.0, sy = 0.0;
    if (div >= kFreeSurfaceDivergence) {
      sx = -a_h2 * gx;
      sy = -a_h2 * gy;
      const double len = std::hypot(sx, sy);
      if (len > limit) {
        sx *= limit / len;
        sy *= limit / len;
      }
    }
    shift_x_[i] = sx;
    shift_y_[i] = sy;
  });
  const double rho0 = par_.rho0, b = b_tait_;
  exec::parallel_for(team_, f_.size(), [&](std::size_t i) {
    f_.x[i] += shift_x_[i];
    f_.y[i] += shift_y_[i];
    f_.rho[i] += shift_x_[i] * f_.gx[i] + shift_y_[i] * f_.gy[i];
    f_.p[i] = tait_pressure(f_.rho[i], rho0, b);
    f_.vol[i] = f_.mass / f_.rho[i];
  });
}

}  // namespace dsdem::sph
