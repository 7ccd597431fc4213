// Packing while the water settles (sph::Fluid::set_packing, docs/theory.md §11): particles move
// down their concentration gradient into the gaps of the lattice, never at the free
// surface, and the same on 1 and 2 threads.
#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <utility>
#include <vector>

#include "sph/fluid.hpp"
#include "sph/setup.hpp"

using namespace dsdem;
using namespace dsdem::sph;

namespace {

constexpr double kDp = 0.01, kSide = 0.2;  // a 20 x 20 lattice

// The tank's water without gravity (at rho0 and rest: no force on any particle, so a step
// moves only what the packing shifts), the lattice's column `moved` shifted right by 0.3 dp:
// a gap of 1.3 dp on its left, 0.7 dp on its right.
Fluid weightless_tank(int moved, bool parallel = false) {
  FluidParameters par;
  par.dp = kDp;
  par.gravity = Vec2(0.0, 0.0);
  par.c0 = 10.0;
  FluidParticles water;
  BoundaryParticles walls;
  const int n = static_cast<int>(std::lround(kSide / kDp));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      water.add((i + 0.5 + (i == moved ? 0.3 : 0.0)) * kDp, (j + 0.5) * kDp, par.rho0);
  water.mass = par.mass();
  add_tank_walls(walls, 0.0, 0.0, kSide, 1.5 * kSide, wall_layers(par), par, kSide);
  return Fluid(par, std::move(water), std::move(walls), parallel);
}

// Each particle's position by its creation index (the fluid re-sorts its arrays).
std::vector<Vec2> by_id(const Fluid& f) {
  const FluidParticles& w = f.fluid();
  std::vector<Vec2> p(w.size());
  for (std::size_t k = 0; k < w.size(); ++k) p[static_cast<std::size_t>(w.id[k])] = Vec2(w.x[k], w.y[k]);
  return p;
}

}  // namespace

// One packing step with the lattice's column 10 shifted right by 0.3 dp: below the surface's
// support, that column moves back left and its neighbours' columns right (into the gap, away
// from the crowding), each by at most dp / 10; particles beyond the support of those columns
// do not move (a full lattice has no concentration gradient: under 1e-9 dp), and neither
// does the free surface's top row.
TEST(SphPacking, ParticlesMoveIntoAGapAndTheRestStay) {
  Fluid f = weightless_tank(10);
  const std::vector<Vec2> before = by_id(f);
  f.set_packing(0.05);
  f.step(1e-4);
  const std::vector<Vec2> after = by_id(f);
  const double h = f.parameters().h(), below = kSide - 2.0 * h - kDp;
  int column = 0, beside = 0, far = 0, top = 0;
  for (std::size_t k = 0; k < before.size(); ++k) {
    const Vec2 moved = after[k] - before[k];
    const double x = before[k].x(), y = before[k].y();
    const int i = static_cast<int>(std::floor(x / kDp));
    EXPECT_LE(moved.norm(), 0.1 * kDp * (1.0 + 1e-12)) << k;
    if (y > 2.0 * h + kDp && y < below && (i == 9 || i == 10 || i == 11)) {
      const double toward = i == 10 ? -moved.x() : moved.x();
      EXPECT_GT(toward, 1e-3 * kDp) << "column " << i << ", y " << y;
      ++(i == 10 ? column : beside);
    } else if (y > 2.0 * h + kDp && y < below && x > 2.0 * h + kDp && x < kSide - 2.0 * h - kDp &&
               std::abs(x - 10.8 * kDp) > 2.0 * h + 2.0 * kDp) {
      ++far;
      EXPECT_LT(moved.norm(), 1e-9 * kDp) << k;
    }
    if (y > kSide - kDp) {
      ++top;
      EXPECT_EQ(moved.norm(), 0.0) << k;
    }
  }
  EXPECT_GT(column, 8);
  EXPECT_EQ(beside, 2 * column);
  EXPECT_GT(far, 20);
  EXPECT_EQ(top, 20);
  // Off again, nothing moves.
  f.set_packing(0.0);
  const std::vector<Vec2> still = by_id(f);
  f.step(1e-4);
  EXPECT_EQ(by_id(f), still);
}

// Forty packing steps beside a gap: the same bits on 1 and 2 threads.
TEST(SphPacking, OneAndTwoThreadsGiveTheSameBits) {
  auto run = [](int threads) {
    omp_set_num_threads(threads);
    Fluid f = weightless_tank(7, threads > 1);
    f.set_packing(0.05);
    for (int k = 0; k < 40; ++k) f.step(2e-4);
    omp_set_num_threads(1);
    return f;
  };
  const Fluid one = run(1), two = run(2);
  EXPECT_EQ(one.fluid().x, two.fluid().x);
  EXPECT_EQ(one.fluid().y, two.fluid().y);
  EXPECT_EQ(one.fluid().rho, two.fluid().rho);
  EXPECT_NE(by_id(one), by_id(weightless_tank(7)));
}
