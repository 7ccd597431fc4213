// sph::Fluid's pair passes (DESIGN.md §13): the neighbour lists, the density rates and the
// accelerations. Each fluid pair is evaluated once (pair_terms.hpp). Every particle's sums
// run over its partners in ascending index: the partners below its thread's block first
// (evaluated from this side, *_from_below), then a fixed-order scatter within the block
// (*_within): the same bits for any thread count, and whatever the lists hold beyond the
// support, so for any time the lists were built at.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sph/fluid.hpp"
#include "sph/pair_lanes.hpp"
#include "sph/pair_terms.hpp"

namespace dsdem::sph {

namespace {
// Below this determinant of the renormalisation matrix (1 for a full kernel) a particle is
// too isolated for a density gradient; it gets none.
constexpr double kRenormalisationDeterminant = 0.1;

// Lane l of four pairs' force terms added to the lower particle's sums (sign +1) or the
// higher's (-1): add_pair() with the products by the other's volume formed in the lanes.
template <int sign>
inline void add_lane(ForceSums& s, const ForceLanes& t, std::size_t l, const double (&w)[5][4]) {
  if constexpr (sign > 0) {
    s.ax += t.ax[l];
    s.ay += t.ay[l];
  } else {
    s.ax -= t.ax[l];
    s.ay -= t.ay[l];
  }
  s.mxx -= w[0][l];
  s.mxy -= w[1][l];
  s.myy -= w[2][l];
  s.sx += w[3][l];
  s.sy += w[4][l];
}
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
    if (count <= cap) {
      // Ascending already right after a re-sort (the cells in index order, rows bottom
      // first, as for_each_range walks them).
      if (!std::is_sorted(list, list + count)) std::sort(list, list + count);
      const std::int32_t* above = std::upper_bound(list, list + count, static_cast<std::int32_t>(i));
      vl_split_[i] = static_cast<std::int32_t>(above - list);
    }
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

ForcePairConstants Fluid::force_constants() const { return {h_, par_.alpha * par_.c0, f_.mass}; }

// Continuity with density diffusion (DESIGN.md §13) for the fluid, continuity alone for
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
    const double xi = b_.x[i], yi = b_.y[i], vxi = b_.vx[i], vyi = b_.vy[i];
    double cont = 0.0;
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

// The fluid's rates. A fluid pair i < j gives drho_i/dt c + q V_j and drho_j/dt c - q V_i.
template <bool fourtakas>
void Fluid::fluid_density_rates() {
  const std::size_t n = f_.size(), blocks = chunks();
  exec::parallel_for(team_, blocks, [&](std::size_t t) {
    const std::size_t lo = n * t / blocks, hi = n * (t + 1) / blocks;
    density_from_below<fourtakas>(lo, hi);
    density_within<fourtakas>(lo, hi);
    density_from_walls(lo, hi);
  });
}

// The pairs with a partner below the block [lo, hi), from this side (the block below adds
// them to its own particles): they come first in ascending partner order.
template <bool fourtakas>
void Fluid::density_from_below(std::size_t lo, std::size_t hi) {
  if (lo == 0) {  // the first block: no partner below it
    std::fill(f_.drho.begin(), f_.drho.begin() + static_cast<std::ptrdiff_t>(hi), 0.0);
    return;
  }
  const DensityPairConstants k = density_constants();
  const double s2 = support2_;
  const std::size_t cap = neighbour_capacity_;
  for (std::size_t i = lo; i < hi; ++i) {
    const std::int32_t* list = vl_j_.data() + i * cap;
    const auto split = static_cast<std::size_t>(vl_split_[i]);
    const DensityPoint pi = density_point(i);
    double sum = 0.0;
    for (std::size_t s = 0; s < split; ++s) {
      const auto j = static_cast<std::size_t>(list[s]);
      if (j >= lo) break;
      const double dx = f_.x[j] - pi.x, dy = f_.y[j] - pi.y;
      if (dx * dx + dy * dy >= s2) continue;
      const DensityPairTerms t = density_pair<fourtakas>(k, density_point(j), pi);
      sum += t.c - t.q * f_.vol[j];
    }
    f_.drho[i] = sum;
  }
}

// Each pair within the block once, added to both; the partners above it to i alone. The
// partners within the support (first picked out without a branch) are kept with their F
// for the force pass (the same positions). Four pairs' terms at a time (pair_lanes.hpp),
// added in order.
template <bool fourtakas>
void Fluid::density_within(std::size_t lo, std::size_t hi) {
  const DensityPairConstants k = density_constants();
  const bool avx2 = pair_lanes_avx2();
  const double s2 = support2_;
  const std::size_t cap = neighbour_capacity_;
  const DensityArrays arrays{f_.x.data(),   f_.y.data(),  f_.vx.data(), f_.vy.data(),
                             f_.rho.data(), f_.gx.data(), f_.gy.data(), f_.vol.data()};
  const double *fx = f_.x.data(), *fy = f_.y.data();
  double* drho = f_.drho.data();
  DensityLanes lanes;
  for (std::size_t i = lo; i < hi; ++i) {
    const std::int32_t* list = vl_j_.data() + i * cap;
    std::int32_t* list_j = nb_j_.data() + i * cap;
    double* list_f = nb_f_.data() + i * cap;
    const auto end = static_cast<std::size_t>(vl_n_[i]);
    const double xi = fx[i], yi = fy[i];
    std::size_t count = 0;
    for (auto s = static_cast<std::size_t>(vl_split_[i]); s < end; ++s) {
      const std::int32_t j = list[s];
      const double dx = xi - fx[j], dy = yi - fy[j];
      list_j[count] = j;
      count += dx * dx + dy * dy < s2 ? 1 : 0;
    }
    nb_n_[i] = static_cast<std::int32_t>(count);
    const double vi = f_.vol[i];
    const DensityPoint pi = density_point(i);
    double sum = drho[i];
    for (std::size_t m = 0; m < count; m += 4) {
      const std::size_t w = std::min<std::size_t>(4, count - m);
      // The last group padded with its first partner (terms computed, not added).
      std::int32_t js[4];
      for (std::size_t l = 0; l < 4; ++l) js[l] = list_j[m + (l < w ? l : 0)];
      if (avx2)
        density_lanes_avx2<fourtakas>(k, pi, vi, arrays, js, lanes);
      else
        density_lanes_scalar<fourtakas>(k, pi, vi, arrays, js, lanes);
      for (std::size_t l = 0; l < w; ++l) {
        const auto j = static_cast<std::size_t>(js[l]);
        list_f[m + l] = lanes.f[l];
        sum += lanes.ti[l];
        if (j < hi) drho[j] += lanes.tj[l];
      }
    }
    drho[i] = sum;
  }
}

// The walls' continuity terms, a gather; the fluid away from the walls (no boundary
// particle in its cell's search block) skips them.
void Fluid::density_from_walls(std::size_t lo, std::size_t hi) {
  const double inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_, mb = b_.mass;
  const auto border = boundary_cells_.order();
  const double *bx = b_.x.data(), *by = b_.y.data(), *bvx = b_.vx.data(), *bvy = b_.vy.data();
  for (std::size_t i = lo; i < hi; ++i) {
    const int cell = fluid_cells_.cell(i);
    if (!near_wall_[static_cast<std::size_t>(cell)]) continue;
    const double xi = f_.x[i], yi = f_.y[i], vxi = f_.vx[i], vyi = f_.vy[i];
    double cont = 0.0;
    boundary_cells_.for_each_range(cell, [&](std::int32_t k0, std::int32_t k1) {
      for (std::int32_t kk = k0; kk < k1; ++kk) {
        const auto j = static_cast<std::size_t>(border[static_cast<std::size_t>(kk)]);
        const double dx = xi - bx[j], dy = yi - by[j];
        const double r2 = dx * dx + dy * dy;
        if (r2 >= s2) continue;
        const double f = wendland_gradient_factor(r2, inv_h, gc);
        cont += mb * f * ((vxi - bvx[j]) * dx + (vyi - bvy[j]) * dy);
      }
    });
    f_.drho[i] += cont;
  }
}

// The momentum equation (DESIGN.md §13): pressure, artificial viscosity and gravity. A
// fluid pair's pressure and viscous terms are equal and opposite; the renormalised density
// gradient's sums take the same pair products with the other particle's volume.
void Fluid::accelerations() {
  if (par_.diffusion == DensityDiffusion::DeltaSph)
    fluid_accelerations<true>();
  else
    fluid_accelerations<false>();
}

template <bool grad>
void Fluid::fluid_accelerations() {
  const std::size_t n = f_.size(), blocks = chunks();
  exec::parallel_for(team_, blocks, [&](std::size_t t) {
    const std::size_t lo = n * t / blocks, hi = n * (t + 1) / blocks;
    forces_from_below<grad>(lo, hi);
    forces_within<grad>(lo, hi);
    finish_accelerations<grad>(lo, hi);
  });
}


// The pairs with a partner below the block, from this side, as in density_from_below() (F
// recomputed: the same bits; 0 beyond the support).
template <bool grad>
void Fluid::forces_from_below(std::size_t lo, std::size_t hi) {
  if (lo == 0) {  // the first block: no partner below it
    std::fill(sums_.begin(), sums_.begin() + static_cast<std::ptrdiff_t>(hi), ForceSums{});
    return;
  }
  const ForcePairConstants k = force_constants();
  const double inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_;
  const std::size_t cap = neighbour_capacity_;
  for (std::size_t i = lo; i < hi; ++i) {
    const std::int32_t* list = vl_j_.data() + i * cap;
    const auto split = static_cast<std::size_t>(vl_split_[i]);
    const ForcePoint pi = force_point(i);
    ForceSums s{};
    for (std::size_t m = 0; m < split; ++m) {
      const auto j = static_cast<std::size_t>(list[m]);
      if (j >= lo) break;
      const ForcePoint pj = force_point(j);
      const double dx = pj.x - pi.x, dy = pj.y - pi.y;
      if (dx * dx + dy * dy >= s2) continue;
      add_pair<-1>(s, force_pair<grad>(k, pj, pi, wendland_gradient_factor(dx * dx + dy * dy, inv_h, gc)), f_.vol[j]);
    }
    sums_[i] = s;
  }
}

// The pairs found by the density pass at these positions, each once, four at a time
// (pair_lanes.hpp) and added in order: i's sums and j's as add_pair<1> and add_pair<-1>.
template <bool grad>
void Fluid::forces_within(std::size_t lo, std::size_t hi) {
  const ForcePairConstants k = force_constants();
  const bool avx2 = pair_lanes_avx2();
  const std::size_t cap = neighbour_capacity_;
  const ForceArrays arrays{f_.x.data(), f_.y.data(), f_.vx.data(), f_.vy.data(), f_.rho.data(), f_.p.data(), f_.vol.data()};
  ForceSums* sums = sums_.data();
  ForceLanes lanes;
  for (std::size_t i = lo; i < hi; ++i) {
    const std::int32_t* list_j = nb_j_.data() + i * cap;
    const double* list_f = nb_f_.data() + i * cap;
    const auto count = static_cast<std::size_t>(nb_n_[i]);
    const double vi = f_.vol[i];
    const ForcePoint pi = force_point(i);
    ForceSums s = sums[i];
    for (std::size_t m = 0; m < count; m += 4) {
      const std::size_t w = std::min<std::size_t>(4, count - m);
      std::int32_t js[4];
      double fs[4];
      for (std::size_t l = 0; l < 4; ++l) {
        js[l] = list_j[m + (l < w ? l : 0)];
        fs[l] = list_f[m + (l < w ? l : 0)];
      }
      if (avx2)
        force_lanes_avx2<grad>(k, pi, vi, arrays, js, fs, lanes);
      else
        force_lanes_scalar<grad>(k, pi, vi, arrays, js, fs, lanes);
      for (std::size_t l = 0; l < w; ++l) {
        const auto j = static_cast<std::size_t>(js[l]);
        add_lane<1>(s, lanes, l, lanes.wi);
        if (j < hi) add_lane<-1>(sums[j], lanes, l, lanes.wj);
      }
    }
    sums[i] = s;
  }
}

// The renormalised gradient, the walls' pressure and viscosity (a gather; the fluid away
// from the walls skips it), gravity.
template <bool grad>
void Fluid::finish_accelerations(std::size_t lo, std::size_t hi) {
  const double h = h_, inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_;
  const double alpha_c = par_.alpha * par_.c0, mb = b_.mass, gx = par_.gravity.x(), gy = par_.gravity.y();
  const auto border = boundary_cells_.order();
  const double *bx = b_.x.data(), *by = b_.y.data(), *bvx = b_.vx.data(), *bvy = b_.vy.data();
  const double *brho = b_.rho.data(), *bp = b_.p.data();
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
    if (near_wall_[static_cast<std::size_t>(cell)]) {
      boundary_cells_.for_each_range(cell, [&](std::int32_t k0, std::int32_t k1) {
        for (std::int32_t kk = k0; kk < k1; ++kk) {
          const auto j = static_cast<std::size_t>(border[static_cast<std::size_t>(kk)]);
          const double dx = xi - bx[j], dy = yi - by[j];
          const double r2 = dx * dx + dy * dy;
          if (r2 >= s2) continue;
          const double f = wendland_gradient_factor(r2, inv_h, gc);
          const double visc =
              artificial_viscosity((vxi - bvx[j]) * dx + (vyi - bvy[j]) * dy, r2, rhoi, brho[j], h, alpha_c);
          const double coef = -mb * (pressure_term(pi, bp[j], rhoi, brho[j]) + visc) * f;
          ax += coef * dx;
          ay += coef * dy;
        }
      });
    }
    f_.ax[i] = ax + gx;
    f_.ay[i] = ay + gy;
  }
}

}  // namespace dsdem::sph
