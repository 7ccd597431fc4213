#include "sph/fluid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "sph/kernels.hpp"

namespace dsdem::sph {

namespace {
// Below this determinant the ghost node's first-order system is left for Shepard's average
// (DualSPHysics' default threshold).
constexpr double kModifiedBoundaryDeterminant = 1e-3;
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
  if (!(par_.excluded_limit >= 0.0 && par_.excluded_limit < 1.0))
    throw std::invalid_argument("sph::Fluid: excluded_limit must be in [0, 1)");
  initial_size_ = f_.size();
  excluded_.reserve(excluded_capacity());
  scratch_.resize(f_.size());
  scratch_id_.resize(f_.size());
  double deepest = 0.0;
  for (std::size_t i = 0; i < b_.size(); ++i) deepest = std::max(deepest, b_.wall_distance[i]);
  wall_reach_ = 2.0 * h_ + 2.0 * deepest;  // the support, from the wall or its ghost node
  active_walls_.reserve(b_.size());
  for (std::size_t i = 0; i < f_.size(); ++i) {
    f_.p[i] = tait_pressure(f_.rho[i], par_.rho0, b_tait_);
    f_.vol[i] = f_.mass / f_.rho[i];
  }
  for (std::size_t i = 0; i < b_.size(); ++i) b_.p[i] = tait_pressure(b_.rho[i], par_.rho0, b_tait_);
  neighbour_capacity_ = neighbour_capacity(par_);
  const std::size_t n = f_.size();
  vl_j_.resize(n * neighbour_capacity_);
  vl_n_.resize(n);
  vl_x_.resize(n);
  vl_y_.resize(n);
  nb_j_ = std::make_unique_for_overwrite<std::int32_t[]>(n * neighbour_capacity_);
  nb_f_ = std::make_unique_for_overwrite<double[]>(n * neighbour_capacity_);
  nb_n_.resize(n);
  nb_at_.resize(n);
  sums_.resize(n);
  density_records_.resize(n);
  force_records_.resize(n);
  shift_x_.resize(n);
  shift_y_.resize(n);
  wall_power_.resize(n);
  resort_fluid();
  rebuild_neighbour_lists();
  density_rates();  // the neighbour lists for the first accelerations
  if (par_.boundary == BoundaryCondition::ModifiedDynamic) extrapolate_boundary_densities();
  accelerations();
  a_max_ = 0.0;
  for (std::size_t i = 0; i < f_.size(); ++i) a_max_ = std::max(a_max_, std::hypot(f_.ax[i], f_.ay[i]));
  sound_ = first_unsound_particle() == f_.size();
}

std::size_t Fluid::neighbour_capacity(const FluidParameters& parameters) {
  const double reach = (2.0 + parameters.verlet_skin) * parameters.h_over_dp;  // (2h + skin) / dp
  return static_cast<std::size_t>(std::ceil(1.6 * kPi * reach * reach)) + 8;
}

std::size_t Fluid::bytes_per_particle(const FluidParameters& parameters) {
  // FluidParticles (13 doubles, an id), the shifts, the Verlet and support lists (an index per
  // slot each, the support list's F too, their counts and offset, the positions at the build),
  // the force sums, the two pair records, the re-sort scratch and the cell lists' entries.
  const std::size_t state = 13 * sizeof(double) + sizeof(std::int32_t), shifts = 2 * sizeof(double);
  const std::size_t lists = neighbour_capacity(parameters) * (2 * sizeof(std::int32_t) + sizeof(double)) +
                            2 * sizeof(std::int32_t) + sizeof(std::size_t) + 2 * sizeof(double);
  const std::size_t records = sizeof(ForceSums) + sizeof(DensityRecord) + sizeof(ForceRecord);
  const std::size_t scratch = sizeof(double) + sizeof(std::int32_t), cells = 2 * sizeof(std::int32_t);
  return state + shifts + lists + records + scratch + cells;
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
  if (packing_ > 0.0) pack_particles();
  time_ += dt;
  update_maxima();
  if (!sound_ && par_.excluded_limit > 0.0) exclude_unsound_particles();
}

// Maxima are exact in any order; one serial pass.
void Fluid::update_maxima() {
  double v2 = 0.0, a2 = 0.0;
  bool sound = true;
  for (std::size_t i = 0; i < f_.size(); ++i) {
    v2 = std::max(v2, f_.vx[i] * f_.vx[i] + f_.vy[i] * f_.vy[i]);
    a2 = std::max(a2, f_.ax[i] * f_.ax[i] + f_.ay[i] * f_.ay[i]);
    sound = sound && particle_sound(i);
  }
  v_max_ = std::sqrt(v2);
  a_max_ = std::sqrt(a2);
  sound_ = sound;
}

std::size_t Fluid::excluded_capacity() const {
  return static_cast<std::size_t>(par_.excluded_limit * static_cast<double>(initial_size_));
}

std::array<std::vector<double>*, 12> Fluid::particle_arrays() {
  return {&f_.x, &f_.y, &f_.vx, &f_.vy, &f_.rho, &f_.p, &f_.ax, &f_.ay, &f_.drho, &f_.gx, &f_.gy, &f_.vol};
}

std::size_t Fluid::unsound_count() const {
  std::size_t bad = 0;
  for (std::size_t i = 0; i < f_.size(); ++i) bad += !particle_sound(i);
  return bad;
}

// Takes the particles out of the weakly compressible range out of the water, in index order
// (the arrays closed up behind them), while their count stays within the limit; past it
// none goes and the fluid stays unsound. So does a particle whose state is not finite: a
// broken number, not water out of range. The survivors' sums of this step had them in: the
// next step's do not (cells and lists rebuilt).
void Fluid::exclude_unsound_particles() {
  const std::size_t n = f_.size();
  if (excluded_.size() + unsound_count() > excluded_capacity()) return;
  for (std::size_t i = 0; i < n; ++i) {
    const double sum = f_.x[i] + f_.y[i] + f_.vx[i] + f_.vy[i] + f_.rho[i];
    if (!particle_sound(i) && !std::isfinite(sum)) return;
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!particle_sound(i)) {
      const Energy e = particle_energy(i, std::pow(par_.rho0, 7.0), 7.0 / (6.0 * par_.rho0));
      excluded_.push_back({f_.id[i], time_, f_.x[i], f_.y[i], std::hypot(f_.vx[i], f_.vy[i]), f_.rho[i], e.total()});
      continue;
    }
    if (kept != i)
      for (auto* a : particle_arrays())
        (*a)[kept] = (*a)[i];
    f_.id[kept] = f_.id[i];
    ++kept;
  }
  for (auto* a : particle_arrays())
    a->resize(kept);  // shrinking keeps the capacity: no allocation
  f_.id.resize(kept);
  resort_fluid();
  rebuild_neighbour_lists();
  update_maxima();
}

double Fluid::excluded_energy() const {
  double e = 0.0;
  for (const ExcludedParticle& x : excluded_) e += x.energy;
  return e;
}

// Written so that a NaN, which fails every comparison, is not sound.
bool Fluid::particle_sound(std::size_t i) const {
  const double v2 = f_.vx[i] * f_.vx[i] + f_.vy[i] * f_.vy[i], rho = f_.rho[i], rho0 = par_.rho0;
  return v2 <= par_.c0 * par_.c0 && rho >= (1.0 - kSoundRange) * rho0 && rho <= (1.0 + kSoundRange) * rho0;
}

std::size_t Fluid::first_unsound_particle() const {
  for (std::size_t i = 0; i < f_.size(); ++i)
    if (!particle_sound(i)) return i;
  return f_.size();
}

void Fluid::update_cells() {
  struct Box {
    double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY;
    void add(double x, double y) {
      xmin = std::min(xmin, x);
      xmax = std::max(xmax, x);
      ymin = std::min(ymin, y);
      ymax = std::max(ymax, y);
    }
    bool empty() const { return !(xmin <= xmax); }
  };
  Box water, all;
  for (std::size_t i = 0; i < f_.size(); ++i) water.add(f_.x[i], f_.y[i]);
  all = water;
  for (std::size_t i = 0; i < b_.size(); ++i) all.add(b_.x[i], b_.y[i]);
  if (all.empty()) all = Box{0.0, 0.0, 0.0, 0.0};
  // Cells of h: 25 cells of h^2 searched instead of 9 of 4 h^2.
  const Grid whole = grid_over(all.xmin, all.ymin, all.xmax, all.ymax, h_);
  // The walls that can meet the water now: within the support of a fluid particle, or
  // with their ghost node (mDBC) within it. The others are binned nowhere and skipped;
  // the cells are a window of the grid over every particle, so each sum meets its
  // partners in the same order as over that grid.
  active_walls_.clear();
  Box used = water;
  if (!water.empty()) {
    const double m = wall_reach_;
    for (std::size_t i = 0; i < b_.size(); ++i) {
      const double x = b_.x[i], y = b_.y[i];
      if (x < water.xmin - m || x > water.xmax + m || y < water.ymin - m || y > water.ymax + m) continue;
      active_walls_.push_back(static_cast<std::int32_t>(i));
      used.add(x, y);
    }
  } else {
    used = Box{all.xmin, all.ymin, all.xmin, all.ymin};
  }
  const Grid grid = window_of(whole, used.xmin, used.ymin, used.xmax, used.ymax);
  fluid_cells_.build(grid, f_.x, f_.y, 2);
  boundary_cells_.build(grid, b_.x, b_.y, active_walls_, 2);
  // The cells whose 5 x 5 block holds a boundary particle: the fluid elsewhere skips the
  // walls' loops (most of it).
  near_wall_.assign(grid.cells(), 0);
  for (const std::int32_t b : active_walls_) {
    const int c = boundary_cells_.cell(static_cast<std::size_t>(b)), cx = c % grid.nx, cy = c / grid.nx;
    for (int y = std::max(0, cy - 2); y <= std::min(grid.ny - 1, cy + 2); ++y)
      for (int x = std::max(0, cx - 2); x <= std::min(grid.nx - 1, cx + 2); ++x)
        near_wall_[static_cast<std::size_t>(y * grid.nx + x)] = 1;
  }
}

// The fluid arrays permuted into cell order, so that a particle's neighbours are close
// in memory; the order within a cell is the index order (deterministic).
void Fluid::resort_fluid() {
  update_cells();
  const std::size_t n = f_.size();
  scratch_.resize(n);  // within its capacity: fewer particles once some were excluded
  scratch_id_.resize(n);
  const auto order = fluid_cells_.order();
  for (auto* a : particle_arrays()) {
    for (std::size_t k = 0; k < n; ++k) scratch_[k] = (*a)[static_cast<std::size_t>(order[k])];
    a->swap(scratch_);
  }
  for (std::size_t k = 0; k < n; ++k) scratch_id_[k] = f_.id[static_cast<std::size_t>(order[k])];
  f_.id.swap(scratch_id_);
  update_cells();
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
    // The walls' pressure work over the step (boundary_work()): -m_f sum_i wall_power_i, the
    // fluid's shares gathered with its continuity from the walls at the step's start;
    // summed in index order, the same bits for any thread count.
    double power = 0.0;
    for (std::size_t i = 0; i < f_.size(); ++i) power += wall_power_[i];  // the arrays outlast excluded particles
    boundary_work_ -= dt * f_.mass * power;
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
    if (!wall_active(i)) {  // no fluid near its ghost node: as with no neighbours below
      b_.rho[i] = rho0;
      b_.p[i] = tait_pressure(rho0, rho0, b);
      return;
    }
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

Fluid::Energy Fluid::particle_energy(std::size_t i, double r7, double e0) const {
  const double m = f_.mass, gx = par_.gravity.x(), gy = par_.gravity.y();
  const double rho = f_.rho[i], rho2 = rho * rho;
  return {0.5 * m * (f_.vx[i] * f_.vx[i] + f_.vy[i] * f_.vy[i]), -m * (gx * f_.x[i] + gy * f_.y[i]),
          m * b_tait_ * (rho2 * rho2 * rho2 / (6.0 * r7) + 1.0 / rho - e0)};
}

Fluid::Energy Fluid::energy() const {
  Energy e;
  const double r7 = std::pow(par_.rho0, 7.0), e0 = 7.0 / (6.0 * par_.rho0);
  for (std::size_t i = 0; i < f_.size(); ++i) {
    const Energy p = particle_energy(i, r7, e0);
    e.kinetic += p.kinetic;
    e.potential += p.potential;
    e.compression += p.compression;
  }
  return e;
}

void Fluid::gather_boundary_forces(std::span<double> out_x, std::span<double> out_y) const {
  const double h = h_, inv_h = 1.0 / h_, gc = grad_c_, s2 = support2_;
  const double alpha_c = par_.alpha * par_.c0;
  const double mf = f_.mass, mb = b_.mass;
  const bool free_slip = par_.wall_viscosity == WallViscosity::FreeSlip;
  const auto forder = fluid_cells_.order();
  const double *fx = f_.x.data(), *fy = f_.y.data(), *fvx = f_.vx.data(), *fvy = f_.vy.data();
  const double *frho = f_.rho.data(), *fp = f_.p.data();
  exec::parallel_for(team_, b_.size(), [&](std::size_t b) {
    double sx = 0.0, sy = 0.0;
    if (!wall_active(b)) {  // no fluid within its support
      out_x[b] = sx;
      out_y[b] = sy;
      return;
    }
    const double xb = b_.x[b], yb = b_.y[b], vxb = b_.vx[b], vyb = b_.vy[b], rhob = b_.rho[b], pb = b_.p[b];
    const double nxb = b_.nx[b], nyb = b_.ny[b];
    // Two copies of the loop, the choice made once per wall particle (as the fluid's gather).
    auto gather = [&](auto free) {
      fluid_cells_.for_each_range(boundary_cells_.cell(b), [&](std::int32_t k0, std::int32_t k1) {
        for (std::int32_t k = k0; k < k1; ++k) {
          const auto i = static_cast<std::size_t>(forder[static_cast<std::size_t>(k)]);
          const double dx = fx[i] - xb, dy = fy[i] - yb;  // r_ib
          const double r2 = dx * dx + dy * dy;
          if (r2 >= s2) continue;
          const double f = wendland_gradient_factor(r2, inv_h, gc);
          if constexpr (decltype(free)::value) {  // m_i (-m_b (P F r_ib + Pi_n F n)): the same pair by pair
            const double visc = wall_normal_viscosity((fvx[i] - vxb) * nxb + (fvy[i] - vyb) * nyb,
                                                      dx * nxb + dy * nyb, r2, frho[i], rhob, h, alpha_c);
            const double coef = mf * mb * pressure_term(fp[i], pb, frho[i], rhob) * f, vcoef = mf * mb * visc * f;
            sx += coef * dx + vcoef * nxb;
            sy += coef * dy + vcoef * nyb;
          } else {
            const double visc =
                artificial_viscosity((fvx[i] - vxb) * dx + (fvy[i] - vyb) * dy, r2, frho[i], rhob, h, alpha_c);
            // Fluid particle i gains m_i (-m_b (P + Pi) F r_ib); the wall particle the opposite.
            const double coef = mf * mb * (pressure_term(fp[i], pb, frho[i], rhob) + visc) * f;
            sx += coef * dx;
            sy += coef * dy;
          }
        }
      });
    };
    if (free_slip)
      gather(std::true_type{});
    else
      gather(std::false_type{});
    out_x[b] = sx;
    out_y[b] = sy;
  });
}

}  // namespace dsdem::sph
