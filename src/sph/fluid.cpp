#include "sph/fluid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sph/kernels.hpp"

namespace dsdem::sph {

namespace {
// Below this determinant the ghost node's first-order system is left for Shepard's average
// (DualSPHysics' default threshold).
constexpr double kModifiedBoundaryDeterminant = 1e-3;
// Below this determinant of the renormalisation matrix (1 for a full kernel) a particle is
// too isolated for a density gradient; it gets none.
constexpr double kRenormalisationDeterminant = 0.1;
}  // namespace

double sound_speed_for(double depth, double v_max, double g) {
  return 10.0 * std::max(std::sqrt(g * depth), v_max);
}

Fluid::Fluid(const FluidParameters& parameters, FluidParticles fluid, BoundaryParticles boundary, bool parallel)
    : par_(parameters), f_(std::move(fluid)), b_(std::move(boundary)), team_(parallel, false) {
  if (!(par_.dp > 0.0) || !(par_.h_over_dp > 0.0) || !(par_.c0 > 0.0) || !(par_.rho0 > 0.0))
    throw std::invalid_argument("sph::Fluid: dp, h_over_dp, c0 and rho0 must be positive");
  if (!(par_.verlet_skin > 0.0)) throw std::invalid_argument("sph::Fluid: verlet_skin must be positive");
  h_ = par_.h();
  b_tait_ = tait_b(par_.rho0, par_.c0);
  grad_c_ = -5.0 * wendland_normalisation(h_) / (h_ * h_);
  support2_ = 4.0 * h_ * h_;
  skin_ = par_.verlet_skin * h_;
  if (f_.mass == 0.0) f_.mass = par_.mass();
  if (b_.mass == 0.0) b_.mass = par_.mass();
  scratch_.resize(f_.size());
  scratch_id_.resize(f_.size());
  for (std::size_t i = 0; i < f_.size(); ++i) {
    f_.p[i] = tait_pressure(f_.rho[i], par_.rho0, b_tait_);
    f_.vol[i] = f_.mass / f_.rho[i];
  }
  for (std::size_t i = 0; i < b_.size(); ++i) b_.p[i] = tait_pressure(b_.rho[i], par_.rho0, b_tait_);
  // Room for 1.6 times a square lattice's neighbours within the support and skin (the
  // water compresses by a few per cent at most).
  const double reach = (2.0 * h_ + skin_) / par_.dp;
  neighbour_capacity_ = static_cast<std::size_t>(std::ceil(1.6 * kPi * reach * reach)) + 8;
  const std::size_t n = f_.size();
  vl_j_.resize(n * neighbour_capacity_);
  vl_n_.resize(n);
  vl_split_.resize(n);
  vl_x_.resize(n);
  vl_y_.resize(n);
  nb_j_.resize(n * neighbour_capacity_);
  nb_f_.resize(n * neighbour_capacity_);
  nb_n_.resize(n);
  sums_.resize(n);
  resort_fluid();
  rebuild_neighbour_lists();
  density_rates();  // the neighbour lists for the first accelerations
  if (par_.boundary == BoundaryCondition::ModifiedDynamic) extrapolate_boundary_densities();
  accelerations();
  a_max_ = 0.0;
  for (std::size_t i = 0; i < f_.size(); ++i) a_max_ = std::max(a_max_, std::hypot(f_.ax[i], f_.ay[i]));
}

double Fluid::stable_dt() const { return stable_time_step(h_, par_.c0, v_max_, a_max_, par_.cfl); }

int Fluid::substeps(double dt_outer) const {
  return std::max(1, static_cast<int>(std::ceil(dt_outer / stable_dt() * (1.0 - 1e-12))));
}

int Fluid::advance(double dt_outer) {
  const int n = substeps(dt_outer);
  const double dt = dt_outer / n;
  for (int k = 0; k < n; ++k) step(dt);
  return n;
}

void Fluid::step(double dt) {
  const std::size_t n = f_.size();
  const double half = 0.5 * dt;
  exec::parallel_for(team_, n, [&](std::size_t i) {
    f_.vx[i] += half * f_.ax[i];
    f_.vy[i] += half * f_.ay[i];
    f_.x[i] += dt * f_.vx[i];
    f_.y[i] += dt * f_.vy[i];
  });
  ++steps_;
  if (par_.resort_interval > 0 && steps_ % par_.resort_interval == 0) {
    resort_fluid();
    rebuild_neighbour_lists();
  } else {
    update_cells();
    if (neighbour_lists_stale()) rebuild_neighbour_lists();
  }
  density_rates();
  update_densities(dt);
  update_boundary_densities(dt);
  accelerations();
  if (record_) gather_boundary_forces(rec_fx_, rec_fy_);
  const double keep = damping_rate_ > 0.0 ? std::exp(-damping_rate_ * dt) : 1.0;
  exec::parallel_for(team_, n, [&](std::size_t i) {
    f_.vx[i] = keep * (f_.vx[i] + half * f_.ax[i]);
    f_.vy[i] = keep * (f_.vy[i] + half * f_.ay[i]);
  });
  // Maxima are exact in any order; one serial pass.
  double v2 = 0.0, a2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    v2 = std::max(v2, f_.vx[i] * f_.vx[i] + f_.vy[i] * f_.vy[i]);
    a2 = std::max(a2, f_.ax[i] * f_.ax[i] + f_.ay[i] * f_.ay[i]);
  }
  v_max_ = std::sqrt(v2);
  a_max_ = std::sqrt(a2);
  time_ += dt;
}

void Fluid::update_cells() {
  double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY;
  auto extend = [&](const std::vector<double>& x, const std::vector<double>& y) {
    for (std::size_t i = 0; i < x.size(); ++i) {
      xmin = std::min(xmin, x[i]);
      xmax = std::max(xmax, x[i]);
      ymin = std::min(ymin, y[i]);
      ymax = std::max(ymax, y[i]);
    }
  };
  extend(f_.x, f_.y);
  extend(b_.x, b_.y);
  if (!(xmin <= xmax)) xmin = ymin = xmax = ymax = 0.0;
  // Cells of h: 25 cells of h^2 searched instead of 9 of 4 h^2.
  const Grid grid = grid_over(xmin, ymin, xmax, ymax, h_);
  fluid_cells_.build(grid, f_.x, f_.y, 2);
  boundary_cells_.build(grid, b_.x, b_.y, 2);
  // The cells whose 5 x 5 block holds a boundary particle: the fluid elsewhere skips the
  // walls' loops (most of it).
  near_wall_.assign(grid.cells(), 0);
  for (std::size_t b = 0; b < b_.size(); ++b) {
    const int c = boundary_cells_.cell(b), cx = c % grid.nx, cy = c / grid.nx;
    for (int y = std::max(0, cy - 2); y <= std::min(grid.ny - 1, cy + 2); ++y)
      for (int x = std::max(0, cx - 2); x <= std::min(grid.nx - 1, cx + 2); ++x)
        near_wall_[static_cast<std::size_t>(y * grid.nx + x)] = 1;
  }
}

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

// The fluid arrays permuted into cell order, so that a particle's neighbours are close
// in memory; the order within a cell is the index order (deterministic).
void Fluid::resort_fluid() {
  update_cells();
  const std::size_t n = f_.size();
  const auto order = fluid_cells_.order();
  for (auto* a : {&f_.x, &f_.y, &f_.vx, &f_.vy, &f_.rho, &f_.p, &f_.ax, &f_.ay, &f_.drho, &f_.gx, &f_.gy, &f_.vol}) {
    for (std::size_t k = 0; k < n; ++k) scratch_[k] = (*a)[static_cast<std::size_t>(order[k])];
    a->swap(scratch_);
  }
  for (std::size_t k = 0; k < n; ++k) scratch_id_[k] = f_.id[static_cast<std::size_t>(order[k])];
  f_.id.swap(scratch_id_);
  update_cells();
}

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

// The fluid's rates. A fluid pair i < j gives drho_i/dt c + q V_j and drho_j/dt c - q V_i:
// the continuity term c is symmetric, the diffusion antisymmetric once the other
// particle's volume is taken out.
template <bool fourtakas>
void Fluid::fluid_density_rates() {
  const double h = h_, inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_, rho0 = par_.rho0, c0 = par_.c0;
  const double dhc = par_.delta * h * par_.c0;
  const double gx = par_.gravity.x(), gy = par_.gravity.y();
  const double mf = f_.mass, mb = b_.mass;
  const auto border = boundary_cells_.order();
  const double *fx = f_.x.data(), *fy = f_.y.data(), *fvx = f_.vx.data(), *fvy = f_.vy.data(), *frho = f_.rho.data();
  const double *fgx = f_.gx.data(), *fgy = f_.gy.data(), *fvol = f_.vol.data();
  const double *bx = b_.x.data(), *by = b_.y.data(), *bvx = b_.vx.data(), *bvy = b_.vy.data();
  const std::size_t cap = neighbour_capacity_, n = f_.size(), blocks = chunks();
  double* drho = f_.drho.data();
  // One particle's values, loaded once (the scatter's stores may alias the arrays).
  struct P {
    double x, y, vx, vy, rho, gx, gy;
  };
  auto load = [&](std::size_t i) { return P{fx[i], fy[i], fvx[i], fvy[i], frho[i], fgx[i], fgy[i]}; };
  // Pair a = i < b = j (0 terms beyond the support): F, c and q.
  auto pair = [=](const P& a, const P& b, double& f, double& c, double& q) {
    const double dx = a.x - b.x, dy = a.y - b.y;
    f = wendland_gradient_factor(dx * dx + dy * dy, inv_h, gc);
    c = mf * f * ((a.vx - b.vx) * dx + (a.vy - b.vy) * dy);
    if constexpr (fourtakas) {
      const double rho_h = hydrostatic_density_difference(-(gx * dx + gy * dy), a.rho, b.rho, rho0, c0);
      q = density_diffusion(dhc, f, b.rho - a.rho - rho_h, 1.0);
    } else {
      q = density_diffusion(dhc, f, b.rho - a.rho, 1.0) +
          density_gradient_correction(dhc, f, -((a.gx + b.gx) * dx + (a.gy + b.gy) * dy), 1.0);
    }
  };
  exec::parallel_for(team_, blocks, [&](std::size_t t) {
    const std::size_t lo = n * t / blocks, hi = n * (t + 1) / blocks;
    // The pairs with a partner below this block, from this side (the block below adds
    // them to its own particles): they come first in ascending partner order.
    for (std::size_t k = lo; k < hi; ++k) {
      const std::int32_t* list = vl_j_.data() + k * cap;
      const auto split = static_cast<std::size_t>(vl_split_[k]);
      const P pk = load(k);
      double sum = 0.0;
      for (std::size_t s = 0; s < split; ++s) {
        const auto j = static_cast<std::size_t>(list[s]);
        if (j >= lo) break;
        const double dx = fx[j] - pk.x, dy = fy[j] - pk.y;
        if (dx * dx + dy * dy >= s2) continue;
        double f, c, q;
        pair(load(j), pk, f, c, q);
        sum += c - q * fvol[j];
      }
      drho[k] = sum;
    }
    // Each pair within the block once, added to both; the partners above it to i alone.
    // The partners within the support (first picked out without a branch) are kept with
    // their F for the force pass.
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
      const double vi = fvol[i];
      const P pi = load(i);
      double sum = drho[i];
      for (std::size_t m = 0; m < count; ++m) {
        const auto j = static_cast<std::size_t>(list_j[m]);
        double f, c, q;
        pair(pi, load(j), f, c, q);
        list_f[m] = f;
        sum += c + q * fvol[j];
        if (j < hi) drho[j] += c - q * vi;
      }
      drho[i] = sum;
    }
    // The walls' continuity terms, a gather.
    for (std::size_t i = lo; i < hi; ++i) {
      const int cell = fluid_cells_.cell(i);
      if (!near_wall_[static_cast<std::size_t>(cell)]) continue;
      const double xi = fx[i], yi = fy[i], vxi = fvx[i], vyi = fvy[i];
      double cont = 0.0;
      boundary_cells_.for_each_range(cell, [&](std::int32_t k0, std::int32_t k1) {
        for (std::int32_t k = k0; k < k1; ++k) {
          const auto j = static_cast<std::size_t>(border[static_cast<std::size_t>(k)]);
          const double dx = xi - bx[j], dy = yi - by[j];
          const double r2 = dx * dx + dy * dy;
          if (r2 >= s2) continue;
          const double f = wendland_gradient_factor(r2, inv_h, gc);
          cont += mb * f * ((vxi - bvx[j]) * dx + (vyi - bvy[j]) * dy);
        }
      });
      drho[i] += cont;
    }
  });
}

void Fluid::update_densities(double dt) {
  const double rho0 = par_.rho0, b = b_tait_;
  exec::parallel_for(team_, f_.size(), [&](std::size_t i) {
    f_.rho[i] += dt * f_.drho[i];
    f_.p[i] = tait_pressure(f_.rho[i], rho0, b);
    f_.vol[i] = f_.mass / f_.rho[i];
  });
}

void Fluid::update_boundary_densities(double dt) {
  const double rho0 = par_.rho0, b = b_tait_;
  if (par_.boundary == BoundaryCondition::ModifiedDynamic) {
    extrapolate_boundary_densities();
    return;
  }
  // A boundary particle never pulls the fluid (DualSPHysics' floor at rho0).
  exec::parallel_for(team_, b_.size(), [&](std::size_t i) {
    b_.rho[i] = std::max(rho0, b_.rho[i] + dt * b_.drho[i]);
    b_.p[i] = tait_pressure(b_.rho[i], rho0, b);
  });
}

// The modified dynamic boundary (English et al. 2022, eqs. 7-10): at the ghost node x_g =
// x_b + 2 d n, the density and its gradient from the fluid by the first-order consistent
// interpolation [sum V W, sum V (x_j - x_g) W; sum V gW, sum V gW (x_j - x_g)^T] (rho_g,
// grad rho_g) = (sum m W, sum m gW), then rho_b = rho_g + (x_b - x_g) . grad rho_g. Where the
// system is singular (few fluid neighbours) Shepard's average; with none, rho0. Never below
// rho0: a wall does not pull the fluid.
void Fluid::extrapolate_boundary_densities() {
  const double inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_, rho0 = par_.rho0, b = b_tait_;
  const double aD = wendland_normalisation(h_);
  const double mf = f_.mass;
  const auto forder = fluid_cells_.order();
  const double *fx = f_.x.data(), *fy = f_.y.data(), *fvol = f_.vol.data();
  const Grid& grid = fluid_cells_.grid();
  exec::parallel_for(team_, b_.size(), [&](std::size_t i) {
    const double two_d = 2.0 * b_.wall_distance[i];
    const double gx = b_.x[i] + two_d * b_.nx[i], gy = b_.y[i] + two_d * b_.ny[i];
    // Row 0: W weights; rows 1-2: gradient weights. Columns: 1, x_j - x_g, y_j - y_g.
    double a00 = 0.0, a01 = 0.0, a02 = 0.0, a10 = 0.0, a11 = 0.0, a12 = 0.0, a20 = 0.0, a21 = 0.0, a22 = 0.0;
    double r0 = 0.0, r1 = 0.0, r2s = 0.0;
    fluid_cells_.for_each_range(grid.cell_of(gx, gy), [&](std::int32_t k0, std::int32_t k1) {
      for (std::int32_t k = k0; k < k1; ++k) {
        const auto j = static_cast<std::size_t>(forder[static_cast<std::size_t>(k)]);
        const double dx = fx[j] - gx, dy = fy[j] - gy;  // x_j - x_g
        const double r2 = dx * dx + dy * dy;
        if (r2 >= s2) continue;
        const double q = std::sqrt(r2) * inv_h, u = 1.0 - 0.5 * q, u2 = u * u;
        const double w = aD * u2 * u2 * (2.0 * q + 1.0);
        const double f = wendland_gradient_factor(r2, inv_h, gc);
        const double wx = -f * dx, wy = -f * dy;  // grad_g W_gj = F (x_g - x_j)
        const double v = fvol[j];  // m / rho
        a00 += v * w;
        a01 += v * dx * w;
        a02 += v * dy * w;
        a10 += v * wx;
        a11 += v * dx * wx;
        a12 += v * dy * wx;
        a20 += v * wy;
        a21 += v * dx * wy;
        a22 += v * dy * wy;
        r0 += mf * w;
        r1 += mf * wx;
        r2s += mf * wy;
      }
    });
    double rho = rho0;
    const double det = a00 * (a11 * a22 - a12 * a21) - a01 * (a10 * a22 - a12 * a20) + a02 * (a10 * a21 - a11 * a20);
    if (std::abs(det) >= kModifiedBoundaryDeterminant) {
      // Cramer's rule for (rho_g, d rho/dx, d rho/dy).
      const double rho_g = (r0 * (a11 * a22 - a12 * a21) - a01 * (r1 * a22 - a12 * r2s) + a02 * (r1 * a21 - a11 * r2s)) / det;
      const double drx = (a00 * (r1 * a22 - a12 * r2s) - r0 * (a10 * a22 - a12 * a20) + a02 * (a10 * r2s - r1 * a20)) / det;
      const double dry = (a00 * (a11 * r2s - r1 * a21) - a01 * (a10 * r2s - r1 * a20) + r0 * (a10 * a21 - a11 * a20)) / det;
      rho = rho_g - two_d * (b_.nx[i] * drx + b_.ny[i] * dry);
    } else if (a00 > 0.0) {
      rho = r0 / a00;
    }
    b_.rho[i] = std::max(rho0, rho);
    b_.p[i] = tait_pressure(b_.rho[i], rho0, b);
  });
}

// The momentum equation (DESIGN.md §13): pressure, artificial viscosity and gravity. A
// fluid pair's pressure and viscous terms are equal and opposite; the renormalised density
// gradient's sums (delta-SPH: M = -sum V_j F r r^T, sum V_j (rho_j - rho_i) F r over the
// fluid neighbours) take the same pair products with the other particle's volume.
void Fluid::accelerations() {
  if (par_.diffusion == DensityDiffusion::DeltaSph)
    fluid_accelerations<true>();
  else
    fluid_accelerations<false>();
}

template <bool grad>
void Fluid::fluid_accelerations() {
  const double h = h_, inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_;
  const double alpha_c = par_.alpha * par_.c0;
  const double gx = par_.gravity.x(), gy = par_.gravity.y();
  const double mf = f_.mass, mb = b_.mass;
  const auto border = boundary_cells_.order();
  const double *fx = f_.x.data(), *fy = f_.y.data(), *fvx = f_.vx.data(), *fvy = f_.vy.data();
  const double *frho = f_.rho.data(), *fp = f_.p.data(), *fvol = f_.vol.data();
  const double *bx = b_.x.data(), *by = b_.y.data(), *bvx = b_.vx.data(), *bvy = b_.vy.data();
  const double *brho = b_.rho.data(), *bp = b_.p.data();
  const std::size_t cap = neighbour_capacity_, n = f_.size(), blocks = chunks();
  ForceSums* sums = sums_.data();
  // Pair i < j with gradient factor f: i's acceleration (j's is minus it) and the products
  // F r r^T and (rho_j - rho_i) F r, the same for both.
  struct PairTerms {
    double ax = 0.0, ay = 0.0, xx = 0.0, xy = 0.0, yy = 0.0, sx = 0.0, sy = 0.0;
  };
  // One particle's values, loaded once (the scatter's stores may alias the arrays).
  struct P {
    double x, y, vx, vy, rho, p;
  };
  auto load = [&](std::size_t i) { return P{fx[i], fy[i], fvx[i], fvy[i], frho[i], fp[i]}; };
  auto pair = [=](const P& a, const P& b, double f) {
    const double dx = a.x - b.x, dy = a.y - b.y;
    const double visc =
        artificial_viscosity((a.vx - b.vx) * dx + (a.vy - b.vy) * dy, dx * dx + dy * dy, a.rho, b.rho, h, alpha_c);
    const double coef = -mf * (pressure_term(a.p, b.p, a.rho, b.rho) + visc) * f;
    PairTerms t;
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
  };
  auto add_lower = [](ForceSums& s, const PairTerms& t, double v_other) {
    s.ax += t.ax;
    s.ay += t.ay;
    s.mxx -= v_other * t.xx;
    s.mxy -= v_other * t.xy;
    s.myy -= v_other * t.yy;
    s.sx += v_other * t.sx;
    s.sy += v_other * t.sy;
  };
  auto add_upper = [](ForceSums& s, const PairTerms& t, double v_other) {
    s.ax -= t.ax;
    s.ay -= t.ay;
    s.mxx -= v_other * t.xx;
    s.mxy -= v_other * t.xy;
    s.myy -= v_other * t.yy;
    s.sx += v_other * t.sx;
    s.sy += v_other * t.sy;
  };
  exec::parallel_for(team_, blocks, [&](std::size_t t) {
    const std::size_t lo = n * t / blocks, hi = n * (t + 1) / blocks;
    // The pairs with a partner below this block, from this side, as in density_rates()
    // (F recomputed: the same bits; 0 beyond the support).
    for (std::size_t k = lo; k < hi; ++k) {
      const std::int32_t* list = vl_j_.data() + k * cap;
      const auto split = static_cast<std::size_t>(vl_split_[k]);
      const P pk = load(k);
      ForceSums s{};
      for (std::size_t m = 0; m < split; ++m) {
        const auto j = static_cast<std::size_t>(list[m]);
        if (j >= lo) break;
        const P pj = load(j);
        const double dx = pj.x - pk.x, dy = pj.y - pk.y;
        if (dx * dx + dy * dy >= s2) continue;
        add_upper(s, pair(pj, pk, wendland_gradient_factor(dx * dx + dy * dy, inv_h, gc)), fvol[j]);
      }
      sums[k] = s;
    }
    // The pairs found by density_rates() at these positions, each once.
    for (std::size_t i = lo; i < hi; ++i) {
      const std::int32_t* list_j = nb_j_.data() + i * cap;
      const double* list_f = nb_f_.data() + i * cap;
      const auto count = static_cast<std::size_t>(nb_n_[i]);
      const double vi = fvol[i];
      const P pi = load(i);
      ForceSums s = sums[i];
      for (std::size_t m = 0; m < count; ++m) {
        const auto j = static_cast<std::size_t>(list_j[m]);
        const PairTerms pt = pair(pi, load(j), list_f[m]);
        add_lower(s, pt, fvol[j]);
        if (j < hi) add_upper(sums[j], pt, vi);
      }
      sums[i] = s;
    }
    // The renormalised gradient, the walls' pressure and viscosity (a gather), gravity.
    for (std::size_t i = lo; i < hi; ++i) {
      const ForceSums& s = sums[i];
      if constexpr (grad) {
        const double det = s.mxx * s.myy - s.mxy * s.mxy;
        const bool ok = det > kRenormalisationDeterminant;
        f_.gx[i] = ok ? (s.myy * s.sx - s.mxy * s.sy) / det : 0.0;
        f_.gy[i] = ok ? (s.mxx * s.sy - s.mxy * s.sx) / det : 0.0;
      }
      const double xi = fx[i], yi = fy[i], vxi = fvx[i], vyi = fvy[i], rhoi = frho[i], pi = fp[i];
      double ax = s.ax, ay = s.ay;
      const int cell = fluid_cells_.cell(i);
      if (near_wall_[static_cast<std::size_t>(cell)]) {
        boundary_cells_.for_each_range(cell, [&](std::int32_t k0, std::int32_t k1) {
          for (std::int32_t k = k0; k < k1; ++k) {
            const auto j = static_cast<std::size_t>(border[static_cast<std::size_t>(k)]);
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
  });
}

void Fluid::boundary_forces(std::span<double> out_x, std::span<double> out_y) const {
  if (out_x.size() != b_.size() || out_y.size() != b_.size())
    throw std::invalid_argument("sph::Fluid::boundary_forces: one entry per boundary particle");
  gather_boundary_forces(out_x, out_y);
}

void Fluid::set_record_boundary_forces(bool on) {
  record_ = on;
  if (!on) {
    std::vector<double>().swap(rec_fx_);
    std::vector<double>().swap(rec_fy_);
    return;
  }
  rec_fx_.assign(b_.size(), 0.0);
  rec_fy_.assign(b_.size(), 0.0);
  gather_boundary_forces(rec_fx_, rec_fy_);
}

Fluid::Energy Fluid::energy() const {
  Energy e;
  const double m = f_.mass, gx = par_.gravity.x(), gy = par_.gravity.y(), rho0 = par_.rho0;
  const double r7 = std::pow(rho0, 7.0), e0 = 7.0 / (6.0 * rho0);
  for (std::size_t i = 0; i < f_.size(); ++i) {
    e.kinetic += 0.5 * m * (f_.vx[i] * f_.vx[i] + f_.vy[i] * f_.vy[i]);
    e.potential -= m * (gx * f_.x[i] + gy * f_.y[i]);
    const double rho = f_.rho[i], rho2 = rho * rho;
    e.compression += m * b_tait_ * (rho2 * rho2 * rho2 / (6.0 * r7) + 1.0 / rho - e0);
  }
  return e;
}

void Fluid::gather_boundary_forces(std::span<double> out_x, std::span<double> out_y) const {
  const double h = h_, inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_;
  const double alpha_c = par_.alpha * par_.c0;
  const double mf = f_.mass, mb = b_.mass;
  const auto forder = fluid_cells_.order();
  const double *fx = f_.x.data(), *fy = f_.y.data(), *fvx = f_.vx.data(), *fvy = f_.vy.data();
  const double *frho = f_.rho.data(), *fp = f_.p.data();
  exec::parallel_for(team_, b_.size(), [&](std::size_t b) {
    const double xb = b_.x[b], yb = b_.y[b], vxb = b_.vx[b], vyb = b_.vy[b], rhob = b_.rho[b], pb = b_.p[b];
    double sx = 0.0, sy = 0.0;
    fluid_cells_.for_each_range(boundary_cells_.cell(b), [&](std::int32_t k0, std::int32_t k1) {
      for (std::int32_t k = k0; k < k1; ++k) {
        const auto i = static_cast<std::size_t>(forder[static_cast<std::size_t>(k)]);
        const double dx = fx[i] - xb, dy = fy[i] - yb;  // r_ib
        const double r2 = dx * dx + dy * dy;
        if (r2 >= s2) continue;
        const double f = wendland_gradient_factor(r2, inv_h, gc);
        const double visc =
            artificial_viscosity((fvx[i] - vxb) * dx + (fvy[i] - vyb) * dy, r2, frho[i], rhob, h, alpha_c);
        // Fluid particle i gains m_i (-m_b (P + Pi) F r_ib); the wall particle the opposite.
        const double coef = mf * mb * (pressure_term(fp[i], pb, frho[i], rhob) + visc) * f;
        sx += coef * dx;
        sy += coef * dy;
      }
    });
    out_x[b] = sx;
    out_y[b] = sy;
  });
}

}  // namespace dsdem::sph
