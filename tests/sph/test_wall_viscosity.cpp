// The artificial viscosity between water and its walls (docs/theory.md §11, "Walls"): a no-slip
// wall drags water sliding along it, a free-slip wall does not and resists its approach as the
// no-slip one does; and a sloshing tank's first mode, started pure, against linear theory.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "sph/fluid.hpp"
#include "sph/setup.hpp"
#include "sph/surface.hpp"

using namespace dsdem;
using namespace dsdem::sph;

namespace {

// A block of still-density water (rho0, no gravity: no pressure anywhere) 12 x 4 particles
// lying on a flat bed of three rows of wall particles, all moving at (u, v).
Fluid block_on_a_bed(WallViscosity walls, double u, double v) {
  FluidParameters par;
  par.dp = 0.02;
  par.c0 = 10.0;
  par.gravity = Vec2(0.0, 0.0);
  par.wall_viscosity = walls;
  FluidParticles water;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 12; ++i) water.add((i + 0.5) * par.dp, (j + 0.5) * par.dp, par.rho0);
  for (std::size_t i = 0; i < water.size(); ++i) {
    water.vx[i] = u;
    water.vy[i] = v;
  }
  water.mass = par.mass();
  BoundaryParticles bed;
  for (int k = 0; k < wall_layers(par); ++k)
    for (int i = -6; i < 18; ++i)
      bed.add_fixed((i + 0.5) * par.dp, -(k + 0.5) * par.dp, par.rho0, Vec2(0.0, 1.0), (k + 0.5) * par.dp);
  bed.mass = par.mass();
  return Fluid(par, std::move(water), std::move(bed));
}

struct Pull {
  double x = 0.0, y = 0.0;      // N/m: the walls' force on the water, m sum a (no gravity)
  double wx = 0.0, wy = 0.0;    // N/m: the water's force on the walls (boundary_forces)
};
Pull pull(const Fluid& f) {
  Pull p;
  for (std::size_t i = 0; i < f.fluid().size(); ++i) {
    p.x += f.fluid().mass * f.fluid().ax[i];
    p.y += f.fluid().mass * f.fluid().ay[i];
  }
  std::vector<double> fx(f.boundary().size()), fy(f.boundary().size());
  f.boundary_forces(fx, fy);
  for (std::size_t b = 0; b < fx.size(); ++b) {
    p.wx += fx[b];
    p.wy += fy[b];
  }
  return p;
}

}  // namespace

TEST(SphWallViscosity, AFreeSlipWallLetsWaterSlideAlongItAndResistsItsApproachAsANoSlipWall) {
  // Sliding at 0.5 m/s: the no-slip wall's viscosity drags the water back, the free-slip wall's
  // puts nothing on it.
  const Pull no_slip = pull(block_on_a_bed(WallViscosity::NoSlip, 0.5, 0.0));
  const Pull free_slip = pull(block_on_a_bed(WallViscosity::FreeSlip, 0.5, 0.0));
  std::printf("sliding: no-slip wall %.4g N/m, free-slip wall %.4g N/m along the bed\n", no_slip.x, free_slip.x);
  EXPECT_LT(no_slip.x, -1.0);
  EXPECT_NEAR(free_slip.x, 0.0, 1e-9 * -no_slip.x);  // round-off of the walls' pressure, rho within 1e-16 of rho0
  EXPECT_NEAR(free_slip.y, 0.0, 1e-9 * -no_slip.x);
  // Coming down onto the bed at 0.5 m/s: the same push back along the normal from both.
  const Pull no_slip_down = pull(block_on_a_bed(WallViscosity::NoSlip, 0.0, -0.5));
  const Pull free_slip_down = pull(block_on_a_bed(WallViscosity::FreeSlip, 0.0, -0.5));
  std::printf("approaching: no-slip wall %.6g N/m, free-slip wall %.6g N/m up from the bed\n", no_slip_down.y,
              free_slip_down.y);
  EXPECT_GT(free_slip_down.y, 1.0);
  EXPECT_NEAR(free_slip_down.y, no_slip_down.y, 1e-9 * no_slip_down.y);
  EXPECT_NEAR(free_slip_down.x, 0.0, 1e-9 * free_slip_down.y);
  // The walls take the reaction pair by pair: equal and opposite.
  EXPECT_NEAR(free_slip_down.wy, -free_slip_down.y, 1e-9 * free_slip_down.y);
  EXPECT_NEAR(free_slip_down.wx, -free_slip_down.x, 1e-9 * free_slip_down.y);
}

// A closed tank 1 m long, water 0.5 m deep at 20 particles per depth (the defaults otherwise:
// h = 1.5 dp, alpha = 0.02, delta-SPH 0.1, modified dynamic walls), settled 2 s, then started
// in its first linear sloshing mode (the potential flow of eta = A cos(pi x / L) sin(omega t),
// A = 12 mm, at eta = 0) and run free for six periods. a1(t), the surface of 20 gauges on
// cos(pi x / L), is fitted by the log of its half-period extremes: the decay per period and the
// period against T1 = 2 pi / sqrt(g k tanh(k h)) (docs/validation.md §5.8).
namespace {
struct Slosh {
  double decay = 0.0, period_error = 0.0;
};
Slosh slosh(WallViscosity walls) {
  const double L = 1.0, H = 0.5, g = 9.81, A = 0.012;
  FluidParameters par;
  par.dp = H / 20.0;
  par.c0 = sound_speed_for(H, 0.0, g);
  par.wall_viscosity = walls;
  FluidParticles water;
  fill_rectangle(water, 0.0, 0.0, L, H, par, H);
  BoundaryParticles tank;
  add_tank_walls(tank, 0.0, 0.0, L, 2.0 * H, wall_layers(par), par, H);
  Fluid fluid(par, std::move(water), std::move(tank));
  settle(fluid, 2.0, 2.0 * std::sqrt(g / H));
  const double k = kPi / L, omega = std::sqrt(g * k * std::tanh(k * H)), T1 = 2.0 * kPi / omega;
  FluidParticles start = fluid.state().fluid;
  const double c = A * g / omega * k / std::cosh(k * H);  // phi = -(A g / omega) cos(kx) cosh(ky) / cosh(kH)
  for (std::size_t i = 0; i < start.size(); ++i) {
    start.vx[i] = c * std::sin(k * start.x[i]) * std::cosh(k * start.y[i]);
    start.vy[i] = -c * std::cos(k * start.x[i]) * std::sinh(k * start.y[i]);
  }
  Fluid::State s = fluid.state();
  s.fluid = std::move(start);
  fluid.restore(s);
  std::vector<double> xs;
  for (int i = 0; i < 20; ++i) xs.push_back((i + 0.5) * L / 20.0);
  std::vector<double> t, a1;
  const double t0 = fluid.time(), every = 0.01;
  for (int n = 0; fluid.time() - t0 < 6.0 * T1; ++n) {
    const double at = t0 + n * every;
    while (fluid.time() < at - 1e-12) fluid.step(std::min(fluid.stable_dt(), at - fluid.time()));
    const std::vector<double> eta = free_surface_elevations(fluid.fluid(), xs, par.h(), par.dp / 20.0);
    double sum = 0.0;
    for (int i = 0; i < 20; ++i) sum += 0.1 * eta[static_cast<std::size_t>(i)] * std::cos(k * xs[static_cast<std::size_t>(i)]);
    t.push_back(fluid.time() - t0);
    a1.push_back(sum);
  }
  // Extremes of |a1| between its zero crossings, refined by a parabola; log-linear fit.
  std::vector<double> te, le, cross;
  for (std::size_t i = 1; i < t.size(); ++i)
    if ((a1[i - 1] < 0.0) != (a1[i] < 0.0)) cross.push_back(t[i - 1] + (t[i] - t[i - 1]) * a1[i - 1] / (a1[i - 1] - a1[i]));
  for (std::size_t c0 = 0; c0 + 1 < cross.size(); ++c0) {
    std::size_t best = 0;
    for (std::size_t i = 1; i + 1 < t.size(); ++i)
      if (t[i] > cross[c0] && t[i] < cross[c0 + 1] && (best == 0 || std::abs(a1[i]) > std::abs(a1[best]))) best = i;
    if (best == 0) continue;
    const double ya = a1[best - 1], yb = a1[best], yc = a1[best + 1], den = ya - 2.0 * yb + yc;
    const double s = den != 0.0 ? 0.5 * (ya - yc) / den : 0.0;
    te.push_back(t[best] + s * every);
    le.push_back(std::log(std::abs(yb - 0.25 * (ya - yc) * s)));
  }
  auto slope = [](const std::vector<double>& x, const std::vector<double>& y) {
    double mx = 0.0, my = 0.0, sxx = 0.0, sxy = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) mx += x[i] / x.size(), my += y[i] / x.size();
    for (std::size_t i = 0; i < x.size(); ++i) sxx += (x[i] - mx) * (x[i] - mx), sxy += (x[i] - mx) * (y[i] - my);
    return sxy / sxx;
  };
  std::vector<double> idx;
  for (std::size_t i = 0; i < cross.size(); ++i) idx.push_back(static_cast<double>(i));
  const double T = 2.0 * slope(idx, cross);
  EXPECT_GE(te.size(), 4u);
  return {1.0 - std::exp(slope(te, le) * T), T / T1 - 1.0};
}
}  // namespace

TEST(SphWallViscosity, ASloshingTanksFirstModeDecaysLessAlongFreeSlipWalls) {
  const Slosh no_slip = slosh(WallViscosity::NoSlip), free_slip = slosh(WallViscosity::FreeSlip);
  std::printf("first mode over 6 periods: no-slip walls %.2f %% per period, period %+.2f %%; free-slip walls "
              "%.2f %% per period, period %+.2f %%\n",
              100.0 * no_slip.decay, 100.0 * no_slip.period_error, 100.0 * free_slip.decay,
              100.0 * free_slip.period_error);
  // Measured 11.71 and 9.82 % per period, -2.20 and -1.83 % (docs/validation.md §5.8): the
  // bounds guard what is reached, far from the target of 0.5 % per period; the no-slip wall's
  // viscosity costs about 2 points of it.
  EXPECT_LT(free_slip.decay, 0.105);
  EXPECT_LT(free_slip.decay, no_slip.decay - 0.01);
  EXPECT_LT(std::abs(free_slip.period_error), 0.025);
}
