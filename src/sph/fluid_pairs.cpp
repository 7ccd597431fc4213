// sph::Fluid's pair passes (docs/theory.md §11): the neighbour lists, the density rates and the
// accelerations. Each particle gathers its sums over the fluid partners within the support,
// picked out of its Verlet list in ascending index (pair_lanes.hpp sums them four pairs at a
// time in a fixed order): the same bits for any thread count, and whatever the lists hold
// beyond the support, so for any time the lists were built at.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "sph/fluid.hpp"
#include "sph/pair_lanes.hpp"

namespace dsdem::sph {

namespace {
// Below this determinant of the renormalisation matrix (1 for a full kernel) a particle is
// too isolated for a density gradient; it gets none.
constexpr double kRenormalisationDeterminant = 0.1;

}  // namespace

// The Verlet lists from the current positions and cell lists (after update_cells()): the
// cells of h within the support and skin.
void Fluid::rebuild_neighbour_lists() {
  const std::size_t n = f_.size(), cap = neighbour_capacity_;
  const double cut = 2.0 * h_ + skin_, cut2 = cut * cut;
  const int reach = static_cast<int>(std::ceil(cut / h_));
  const auto order = fluid_cells_.order();
  const double *x = f_.x.data(), *y = f_.y.data();
  exec::parallel_for(team_, n, [&](std::size_t i) {
    std::int32_t* list = vl_j_.data() + i * cap;
    const double xi = x[i], yi = y[i];
    std::size_t count = 0;
    fluid_cells_.for_each_range(fluid_cells_.cell(i), reach, [&](std::int32_t k0, std::int32_t k1) {
      for (std::int32_t k = k0; k < k1; ++k) {
        const auto j = static_cast<std::size_t>(order[static_cast<std::size_t>(k)]);
        const double dx = xi - x[j], dy = yi - y[j];
        if (j == i || dx * dx + dy * dy >= cut2) continue;
        if (count < cap) list[count] = static_cast<std::int32_t>(j);
        ++count;
      }
    });
    vl_n_[i] = static_cast<std::int32_t>(count);
    // Ascending already right after a re-sort (the cells in index order, rows bottom first,
    // as for_each_range walks them).
    if (count <= cap && !std::is_sorted(list, list + count)) std::sort(list, list + count);
    vl_x_[i] = xi;
    vl_y_[i] = yi;
  });
  vl_built_at_ = steps_;
  for (std::size_t i = 0; i < n; ++i)
    if (static_cast<std::size_t>(vl_n_[i]) > cap)
      throw std::runtime_error("sph::Fluid: a particle has more than " + std::to_string(cap) +
                               " neighbours (the water is compressed far beyond its weakly compressible range)");
}

// A pair closer than the support now was within the support plus the skin at the rebuild
// while no particle moved more than half the skin.
bool Fluid::neighbour_lists_stale() const {
  const double limit2 = 0.25 * skin_ * skin_;
  for (std::size_t i = 0; i < f_.size(); ++i) {
    const double dx = f_.x[i] - vl_x_[i], dy = f_.y[i] - vl_y_[i];
    if (dx * dx + dy * dy >= limit2) return true;
  }
  return false;
}

// The blocks of the pair loops: one per thread, contiguous index ranges.
std::size_t Fluid::chunks() const {
  return std::max<std::size_t>(1, std::min<std::size_t>(static_cast<std::size_t>(team_.threads()), f_.size()));
}

DensityPairConstants Fluid::density_constants() const {
  return {1.0 / h_, grad_c_, f_.mass, par_.delta * h_ * par_.c0, par_.gravity.x(), par_.gravity.y(), par_.rho0, par_.c0};
}

ForcePairConstants Fluid::force_constants() const { return {h_, par_.alpha * par_.c0, f_.mass, 1.0 / h_, grad_c_}; }

// Continuity with density diffusion (docs/theory.md §11) for the fluid, continuity alone for
// the boundary particles (the dynamic boundary condition; fluid neighbours only).
void Fluid::density_rates() {
  if (par_.diffusion == DensityDiffusion::Fourtakas)
    fluid_density_rates<true>();
  else
    fluid_density_rates<false>();
  if (par_.boundary != BoundaryCondition::Dynamic) return;
  const double inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_, mf = f_.mass;
  const auto forder = fluid_cells_.order();
  const double *fx = f_.x.data(), *fy = f_.y.data(), *fvx = f_.vx.data(), *fvy = f_.vy.data();
  exec::parallel_for(team_, b_.size(), [&](std::size_t i) {
    double cont = 0.0;
    if (!wall_active(i)) {  // no fluid within its support
      b_.drho[i] = cont;
      return;
    }
    const double xi = b_.x[i], yi = b_.y[i], vxi = b_.vx[i], vyi = b_.vy[i];
    fluid_cells_.for_each_range(boundary_cells_.cell(i), [&](std::int32_t k0, std::int32_t k1) {
      for (std::int32_t k = k0; k < k1; ++k) {
        const auto j = static_cast<std::size_t>(forder[static_cast<std::size_t>(k)]);
        const double dx = xi - fx[j], dy = yi - fy[j];
        const double r2 = dx * dx + dy * dy;
        if (r2 >= s2) continue;
        const double f = wendland_gradient_factor(r2, inv_h, gc);
        cont += mf * f * ((vxi - fvx[j]) * dx + (vyi - fvy[j]) * dy);
      }
    });
    b_.drho[i] = cont;
  });
}

void Fluid::pack_density_records() {
  exec::parallel_for(team_, f_.size(), [&](std::size_t i) {
    density_records_[i] = {f_.x[i], f_.y[i], f_.vx[i], f_.vy[i], f_.rho[i], f_.gx[i], f_.gy[i], f_.vol[i]};
  });
}

void Fluid::pack_force_records() {
  exec::parallel_for(team_, f_.size(), [&](std::size_t i) {
    force_records_[i] = {f_.x[i], f_.y[i], f_.vx[i], f_.vy[i], f_.rho[i], f_.p[i], f_.vol[i], 0.0};
  });
}

// The fluid's rates: each particle's own gather, in blocks of indices.
template <bool fourtakas>
void Fluid::fluid_density_rates() {
  const std::size_t n = f_.size(), blocks = chunks();
  pack_density_records();
  exec::parallel_for(team_, blocks, [&](std::size_t t) {
    const std::size_t lo = n * t / blocks, hi = n * (t + 1) / blocks;
    density_within<fourtakas>(lo, hi);
    density_from_walls(lo, hi);
  });
}

// Each particle's partners within the support (picked out without a branch), kept for the
// force pass (the same positions), and its continuity and diffusion sum.
template <bool fourtakas>
void Fluid::density_within(std::size_t lo, std::size_t hi) {
  const DensityPairConstants k = density_constants();
  const bool avx2 = pair_lanes_avx2();
  const double s2 = support2_;
  const std::size_t cap = neighbour_capacity_;
  const DensityRecord* records = density_records_.data();
  std::size_t at = lo * cap;  // the block's partners, one after another
  for (std::size_t i = lo; i < hi; ++i) {
    const std::int32_t* list = vl_j_.data() + i * cap;
    std::int32_t* list_j = nb_j_.get() + at;
    const auto end = static_cast<std::size_t>(vl_n_[i]);
    const double xi = records[i].x, yi = records[i].y;
    std::size_t count = 0;
    for (std::size_t s = 0; s < end; ++s) {
      const std::int32_t j = list[s];
      const double dx = xi - records[j].x, dy = yi - records[j].y;
      list_j[count] = j;
      count += dx * dx + dy * dy < s2 ? 1 : 0;
    }
    nb_n_[i] = static_cast<std::int32_t>(count);
    nb_at_[i] = at;
    double* fs = nb_f_.get() + at;
    at += count;
    const DensityPoint pi = density_point(i);
    f_.drho[i] = avx2 ? density_sum_avx2<fourtakas>(k, pi, records, list_j, count, fs)
                      : density_sum_scalar<fourtakas>(k, pi, records, list_j, count, fs);
  }
}

// The walls' continuity terms, a gather; the fluid away from the walls (no boundary
// particle in its cell's search block) skips them. With the modified dynamic boundary each
// term weighted by its wall's p / rho^2 too: the particle's share of the power of the walls'
// pressure, which no wall state stores (boundary_work()).
void Fluid::density_from_walls(std::size_t lo, std::size_t hi) {
  const double inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_, mb = b_.mass;
  const auto border = boundary_cells_.order();
  const double *bx = b_.x.data(), *by = b_.y.data(), *bvx = b_.vx.data(), *bvy = b_.vy.data();
  const double *bp = b_.p.data(), *brho = b_.rho.data();
  const bool book = par_.boundary == BoundaryCondition::ModifiedDynamic;
  for (std::size_t i = lo; i < hi; ++i) {
    wall_power_[i] = 0.0;
    const int cell = fluid_cells_.cell(i);
    if (!near_wall_[static_cast<std::size_t>(cell)]) continue;
    const double xi = f_.x[i], yi = f_.y[i], vxi = f_.vx[i], vyi = f_.vy[i];
    double cont = 0.0, power = 0.0;
    boundary_cells_.for_each_range(cell, [&](std::int32_t k0, std::int32_t k1) {
      for (std::int32_t kk = k0; kk < k1; ++kk) {
        const auto j = static_cast<std::size_t>(border[static_cast<std::size_t>(kk)]);
        const double dx = xi - bx[j], dy = yi - by[j];
        const double r2 = dx * dx + dy * dy;
        if (r2 >= s2) continue;
        const double f = wendland_gradient_factor(r2, inv_h, gc);
        const double term = mb * f * ((vxi - bvx[j]) * dx + (vyi - bvy[j]) * dy);
        cont += term;
        if (book) power += bp[j] / (brho[j] * brho[j]) * term;
      }
    });
    f_.drho[i] += cont;
    wall_power_[i] = power;
  }
}

// The momentum equation (docs/theory.md §11): pressure, artificial viscosity and gravity, and the
// renormalised density gradient's sums.
void Fluid::accelerations() {
  if (par_.diffusion == DensityDiffusion::DeltaSph)
    fluid_accelerations<true>();
  else
    fluid_accelerations<false>();
}

template <bool grad>
void Fluid::fluid_accelerations() {
  const std::size_t n = f_.size(), blocks = chunks();
  pack_force_records();
  exec::parallel_for(team_, blocks, [&](std::size_t t) {
    const std::size_t lo = n * t / blocks, hi = n * (t + 1) / blocks;
    forces_within<grad>(lo, hi);
    finish_accelerations<grad>(lo, hi);
  });
}


// Each particle's sums over the partners found by the density pass at these positions.
template <bool grad>
void Fluid::forces_within(std::size_t lo, std::size_t hi) {
  const ForcePairConstants k = force_constants();
  const bool avx2 = pair_lanes_avx2();
  const ForceRecord* records = force_records_.data();
  for (std::size_t i = lo; i < hi; ++i) {
    const std::int32_t* list_j = nb_j_.get() + nb_at_[i];
    const double* fs = nb_f_.get() + nb_at_[i];
    const auto count = static_cast<std::size_t>(nb_n_[i]);
    const ForcePoint pi = force_point(i);
    sums_[i] = avx2 ? force_sum_avx2<grad>(k, pi, records, list_j, fs, count)
                    : force_sum_scalar<grad>(k, pi, records, list_j, fs, count);
  }
}

// The renormalised gradient, the walls' pressure and viscosity (a gather; the fluid away
// from the walls skips it; a free-slip wall's viscosity along its normal, docs/theory.md §11),
// gravity.
template <bool grad>
void Fluid::finish_accelerations(std::size_t lo, std::size_t hi) {
  const double h = h_, inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_;
  const double alpha_c = par_.alpha * par_.c0, mb = b_.mass, gx = par_.gravity.x(), gy = par_.gravity.y();
  const auto border = boundary_cells_.order();
  const double *bx = b_.x.data(), *by = b_.y.data(), *bvx = b_.vx.data(), *bvy = b_.vy.data();
  const double *brho = b_.rho.data(), *bp = b_.p.data(), *bnx = b_.nx.data(), *bny = b_.ny.data();
  const bool free_slip = par_.wall_viscosity == WallViscosity::FreeSlip;
  for (std::size_t i = lo; i < hi; ++i) {
    const ForceSums& s = sums_[i];
    if constexpr (grad) {
      const double det = s.mxx * s.myy - s.mxy * s.mxy;
      const bool ok = det > kRenormalisationDeterminant;
      f_.gx[i] = ok ? (s.myy * s.sx - s.mxy * s.sy) / det : 0.0;
      f_.gy[i] = ok ? (s.mxx * s.sy - s.mxy * s.sx) / det : 0.0;
    }
    const double xi = f_.x[i], yi = f_.y[i], vxi = f_.vx[i], vyi = f_.vy[i], rhoi = f_.rho[i], pi = f_.p[i];
    double ax = s.ax, ay = s.ay;
    const int cell = fluid_cells_.cell(i);
    // The walls' loop in two copies, the choice made once per particle: the no-slip one is the
    // fluid pairs' term as it always was.
    auto walls = [&](auto free) {
      boundary_cells_.for_each_range(cell, [&](std::int32_t k0, std::int32_t k1) {
        for (std::int32_t kk = k0; kk < k1; ++kk) {
          const auto j = static_cast<std::size_t>(border[static_cast<std::size_t>(kk)]);
          const double dx = xi - bx[j], dy = yi - by[j];
          const double r2 = dx * dx + dy * dy;
          if (r2 >= s2) continue;
          const double f = wendland_gradient_factor(r2, inv_h, gc);
          if constexpr (decltype(free)::value) {
            const double nx = bnx[j], ny = bny[j];
            const double visc = wall_normal_viscosity((vxi - bvx[j]) * nx + (vyi - bvy[j]) * ny, dx * nx + dy * ny,
                                                      r2, rhoi, brho[j], h, alpha_c);
            const double coef = -mb * pressure_term(pi, bp[j], rhoi, brho[j]) * f, vcoef = -mb * visc * f;
            ax += coef * dx + vcoef * nx;
            ay += coef * dy + vcoef * ny;
          } else {
            const double visc =
                artificial_viscosity((vxi - bvx[j]) * dx + (vyi - bvy[j]) * dy, r2, rhoi, brho[j], h, alpha_c);
            const double coef = -mb * (pressure_term(pi, bp[j], rhoi, brho[j]) + visc) * f;
            ax += coef * dx;
            ay += coef * dy;
          }
        }
      });
    };
    if (near_wall_[static_cast<std::size_t>(cell)]) {
      if (free_slip)
        walls(std::true_type{});
      else
        walls(std::false_type{});
    }
    f_.ax[i] = ax + gx;
    f_.ay[i] = ay + gy;
  }
}

}  // namespace dsdem::sph
