// SPH water in a tank (docs/theory.md §11): hydrostatic pressure and settling, and the same
// bits for 1 and 2 threads.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "sph/fluid.hpp"
#include "sph/setup.hpp"

using namespace dsdem;
using namespace dsdem::sph;

namespace {

struct Tank {
  FluidParameters par;
  double width, depth;
};

// A tank of water width x depth at rest, at hydrostatic density, walls up to 1.5 depth.
Fluid make_tank(const Tank& t, bool parallel = false) {
  FluidParticles water;
  BoundaryParticles walls;
  fill_rectangle(water, 0.0, 0.0, t.width, t.depth, t.par, t.depth);
  add_tank_walls(walls, 0.0, 0.0, t.width, 1.5 * t.depth, wall_layers(t.par), t.par, t.depth);
  return Fluid(t.par, std::move(water), std::move(walls), parallel);
}

Tank small_tank(double dp) {
  Tank t;
  t.width = 0.2;
  t.depth = 0.2;
  t.par.dp = dp;
  // Twice docs/theory.md §11's least c0: the density then varies by 0.25 % over the depth, and
  // the (p_i + p_j) pressure term's error with it (p / (rho c0^2), 2 % at 10 sqrt(g H)).
  t.par.c0 = 2.0 * sound_speed_for(t.depth, 0.0, 9.81);
  t.par.alpha = 0.1;
  return t;
}

}  // namespace

TEST(SphTank, HydrostaticPressureAndSettling) {
  // Laid out on a square lattice at Tait's hydrostatic density, the water first settles
  // with its velocities damped (set_settling_damping) for 0.5 s, then moves freely for 1 s.
  const Tank t = small_tank(0.02);
  Fluid fluid = make_tank(t);
  const double g = 9.81, scale = std::sqrt(g * t.depth);
  fluid.set_settling_damping(20.0);
  while (fluid.time() < 0.5 - 1e-9) fluid.advance(0.01);
  fluid.set_settling_damping(0.0);
  while (fluid.time() < 1.5 - 1e-9) fluid.advance(0.01);
  const auto& f = fluid.fluid();
  double surface = -INFINITY;
  for (double y : f.y) surface = std::max(surface, y);
  surface += 0.5 * t.par.dp;
  // The pressure profile: the mean pressure and depth of the particles in each row.
  const int rows = static_cast<int>(std::ceil(t.depth / t.par.dp)) + 2;
  std::vector<double> p_sum(rows, 0.0), d_sum(rows, 0.0);
  std::vector<int> count(rows, 0);
  double vmax = 0.0, worst_particle = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    vmax = std::max(vmax, std::hypot(f.vx[i], f.vy[i]));
    const double depth = surface - f.y[i];
    const int row = static_cast<int>(depth / t.par.dp);
    if (row < 3 || row >= rows) continue;
    p_sum[row] += f.p[i];
    d_sum[row] += depth;
    ++count[row];
    worst_particle = std::max(worst_particle, std::abs(f.p[i] / (t.par.rho0 * g * depth) - 1.0));
  }
  double worst = 0.0;
  int checked = 0;
  for (int r = 3; r < rows; ++r) {
    if (count[r] == 0) continue;
    const double ph = t.par.rho0 * g * d_sum[r] / count[r];
    worst = std::max(worst, std::abs(p_sum[r] / count[r] - ph) / ph);
    ++checked;
  }
  std::printf("tank %zu particles, %ld steps: surface %.4f m, pressure profile error %.4f (single particle %.4f), "
              "v_max %.3g sqrt(gH)\n", f.size(), fluid.steps(), surface, worst, worst_particle, vmax / scale);
  EXPECT_GE(checked, 6);
  EXPECT_LT(worst, 0.02);
  EXPECT_LT(vmax, 1e-3 * scale);

  // The walls carry the water's weight: the boundary particles' forces sum to the fluid's
  // momentum balance (pair by pair; to 1e-6, as the viscous term reads the velocities of
  // the call, v(n+1), where the step's force pass read v(n+1/2)), and to its weight at rest.
  std::vector<double> bx(fluid.boundary().size()), by(fluid.boundary().size());
  fluid.boundary_forces(bx, by);
  double fx_sum = 0.0, fy_sum = 0.0, max_ax = 0.0, ma_x = 0.0, ma_y = 0.0;
  for (std::size_t b = 0; b < bx.size(); ++b) {
    fx_sum += bx[b];
    fy_sum += by[b];
  }
  for (std::size_t i = 0; i < f.size(); ++i) {
    ma_x += f.mass * f.ax[i];
    ma_y += f.mass * (f.ay[i] + g);
    max_ax = std::max(max_ax, std::abs(f.ax[i]));
  }
  const double weight = f.mass * g * static_cast<double>(f.size());
  std::printf("walls: %.6g N/m down (weight %.6g), %.3g sideways\n", -fy_sum, weight, fx_sum);
  EXPECT_NEAR(fx_sum, -ma_x, 1e-6 * weight);
  EXPECT_NEAR(fy_sum, -ma_y, 1e-6 * weight);
  EXPECT_NEAR(-fy_sum, weight, 0.01 * weight);
  EXPECT_LT(std::abs(fx_sum), 1e-3 * weight);
}

TEST(SphTank, OneAndTwoThreadsGiveTheSameBits) {
  // A water column released in a tank (a small dam break) so that the flow is violent.
  Tank t = small_tank(0.01);
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    FluidParticles water;
    BoundaryParticles walls;
    fill_rectangle(water, 0.0, 0.0, 0.1, t.depth, t.par, t.depth);
    add_tank_walls(walls, 0.0, 0.0, t.width, 1.5 * t.depth, wall_layers(t.par), t.par, t.depth);
    Fluid fluid(t.par, std::move(water), std::move(walls), threads > 1);
    for (int k = 0; k < 4; ++k) fluid.advance(2e-3);  // 76 steps, four re-sorts
    omp_set_num_threads(1);
    return fluid;
  };
  const Fluid one = run(1), two = run(2);
  ASSERT_EQ(one.steps(), two.steps());
  const auto &a = one.fluid(), &b = two.fluid();
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.vx, b.vx);
  EXPECT_EQ(a.vy, b.vy);
  EXPECT_EQ(a.rho, b.rho);
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(one.boundary().rho, two.boundary().rho);
  // The column is collapsing.
  EXPECT_GT(one.max_speed(), 0.05);
}

TEST(SphTank, NeighbourListSkinDoesNotChangeTheBits) {
  // The Verlet lists' skin sets which candidates they hold and when they are rebuilt (a
  // thin skin: every few steps, at times set by the flow); the sums run over the pairs
  // within the support in a fixed order whatever the lists hold, so a fluid rebuilt from
  // its particle arrays continues with the same bits.
  Tank t = small_tank(0.01);
  auto run = [&](double skin, int threads) {
    omp_set_num_threads(threads);
    t.par.verlet_skin = skin;
    FluidParticles water;
    BoundaryParticles walls;
    fill_rectangle(water, 0.0, 0.0, 0.1, t.depth, t.par, t.depth);
    add_tank_walls(walls, 0.0, 0.0, t.width, 1.5 * t.depth, wall_layers(t.par), t.par, t.depth);
    Fluid fluid(t.par, std::move(water), std::move(walls), threads > 1);
    for (int k = 0; k < 4; ++k) fluid.advance(2e-3);
    omp_set_num_threads(1);
    return fluid;
  };
  const Fluid usual = run(0.3, 1);
  EXPECT_GT(usual.max_speed(), 0.05);
  for (const auto& [skin, threads] : {std::pair{0.02, 1}, std::pair{1.0, 1}, std::pair{0.02, 2}}) {
    const Fluid other = run(skin, threads);
    ASSERT_EQ(usual.steps(), other.steps());
    EXPECT_EQ(usual.fluid().x, other.fluid().x) << "skin " << skin << ", " << threads << " thread(s)";
    EXPECT_EQ(usual.fluid().vx, other.fluid().vx);
    EXPECT_EQ(usual.fluid().rho, other.fluid().rho);
    EXPECT_EQ(usual.boundary().rho, other.boundary().rho);
  }
}

TEST(SphTank, WallsBeyondTheWatersReachAreSkippedAndChangeNoBit) {
  // A column collapsing in the tank, with and without a second wall far above and to the
  // right of everything (the grid's origin stays where it was). The far wall is skipped by
  // the step (no fluid within the support of it or of its ghost node); every wall that has
  // fluid within that reach is used; and the water's bits are the same as without it.
  for (const BoundaryCondition bc : {BoundaryCondition::ModifiedDynamic, BoundaryCondition::Dynamic}) {
    Tank t = small_tank(0.01);
    t.par.boundary = bc;
    auto make = [&](bool far_wall) {
      FluidParticles water;
      BoundaryParticles walls;
      fill_rectangle(water, 0.0, 0.0, 0.1, t.depth, t.par, t.depth);
      add_tank_walls(walls, 0.0, 0.0, t.width, 1.5 * t.depth, wall_layers(t.par), t.par, t.depth);
      if (far_wall)
        for (int k = 0; k < 40; ++k) walls.add_fixed(0.5 + 0.01 * k, 0.6, t.par.rho0, Vec2(0.0, 1.0), 0.005);
      return Fluid(t.par, std::move(water), std::move(walls), false);
    };
    Fluid plain = make(false), with = make(true);
    const std::size_t nb = plain.boundary().size();
    const double h = t.par.h(), s2 = 4.0 * h * h;
    for (int k = 0; k < 4; ++k) {
      plain.advance(2e-3);
      with.advance(2e-3);
      const auto& f = with.fluid();
      const auto& b = with.boundary();
      std::size_t used = 0;
      for (std::size_t w = 0; w < b.size(); ++w) {
        const double two_d = 2.0 * b.wall_distance[w];
        const double gx = b.x[w] + two_d * b.nx[w], gy = b.y[w] + two_d * b.ny[w];
        bool reached = false;
        for (std::size_t i = 0; i < f.size() && !reached; ++i) {
          const double d1 = (f.x[i] - b.x[w]) * (f.x[i] - b.x[w]) + (f.y[i] - b.y[w]) * (f.y[i] - b.y[w]);
          const double d2 = (f.x[i] - gx) * (f.x[i] - gx) + (f.y[i] - gy) * (f.y[i] - gy);
          reached = d1 < s2 || d2 < s2;
        }
        if (reached) {
          ASSERT_TRUE(with.wall_active(w)) << "wall particle " << w << " has water within reach";
          ++used;
        }
        if (w >= nb) EXPECT_FALSE(with.wall_active(w)) << "far wall particle " << w;
      }
      EXPECT_GT(used, 50u);
    }
    EXPECT_GT(with.max_speed(), 0.05);
    ASSERT_EQ(plain.steps(), with.steps());
    EXPECT_EQ(plain.fluid().x, with.fluid().x);
    EXPECT_EQ(plain.fluid().vx, with.fluid().vx);
    EXPECT_EQ(plain.fluid().rho, with.fluid().rho);
    const auto& rho = with.boundary().rho;
    EXPECT_EQ(plain.boundary().rho, std::vector<double>(rho.begin(), rho.begin() + static_cast<long>(nb)));
    for (std::size_t w = nb; w < rho.size(); ++w) EXPECT_EQ(rho[w], t.par.rho0);
  }
}

TEST(SphTank, AdvanceSubCyclesALargerSolidStep) {
  // advance(dt_solid) takes n equal steps no longer than the stable one and lands on
  // dt_solid: the water inside one step of a coupled solid.
  Fluid fluid = make_tank(small_tank(0.02));
  const double dt_fluid = fluid.stable_dt(), dt_solid = 4.5 * dt_fluid;
  const int n = fluid.advance(dt_solid);
  EXPECT_EQ(n, 5);
  EXPECT_EQ(fluid.steps(), 5);
  EXPECT_NEAR(fluid.time(), dt_solid, 1e-15);
  EXPECT_EQ(fluid.advance(0.5 * fluid.stable_dt()), 1);
}
