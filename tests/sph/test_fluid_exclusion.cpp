// Water particles taken out of the weakly compressible range (FluidParameters::excluded_limit):
// the one that left it goes, with its energy booked; the rest of the water runs on, on 1 and 2
// threads alike and through a checkpoint; past the limit the fluid is unsound instead.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "sph/fluid.hpp"
#include "sph/setup.hpp"

using namespace dsdem;
using namespace dsdem::sph;

namespace {

FluidParameters parameters(double limit) {
  FluidParameters par;
  par.dp = 0.01;
  par.c0 = sound_speed_for(0.2, 0.0, 9.81);
  par.alpha = 0.1;
  par.resort_interval = 4;
  par.excluded_limit = limit;
  return par;
}

// A water column 0.1 x 0.2 m at the left of a 0.4 m tank (200 particles), released.
Fluid column(double limit, bool parallel = false) {
  const FluidParameters par = parameters(limit);
  FluidParticles water;
  BoundaryParticles walls;
  fill_rectangle(water, 0.0, 0.0, 0.1, 0.2, par, 0.2);
  add_tank_walls(walls, 0.0, 0.0, 0.4, 0.3, wall_layers(par), par, 0.2);
  Fluid f(par, std::move(water), std::move(walls), parallel);
  f.set_record_boundary_forces(true);
  return f;
}

constexpr std::int32_t kFlung = 57;  // the particle thrown out (its id)

// After a few steps the particle with id kFlung is thrown upward at twice the sound speed.
void fling(Fluid& f) {
  for (int k = 0; k < 10; ++k) f.step(f.stable_dt());
  Fluid::State s = f.state();
  const auto at = std::find(s.fluid.id.begin(), s.fluid.id.end(), kFlung) - s.fluid.id.begin();
  s.fluid.vy[static_cast<std::size_t>(at)] = 2.0 * f.parameters().c0;
  f.restore(s);
  ASSERT_FALSE(f.sound());
}

double total(const Fluid& f) { return f.energy().total() + f.excluded_energy(); }

bool same(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

}  // namespace

TEST(SphFluidExclusion, AParticleOutOfRangeIsTakenOutWithItsEnergyAndTheWaterRunsOn) {
  Fluid f = column(0.02);  // up to 4 of 200
  const std::size_t n = f.fluid().size();
  fling(f);
  const double before = f.energy().total();
  const double dt = 0.5 * f.stable_dt();  // short enough for the flung particle too
  f.step(dt);
  ASSERT_TRUE(f.sound());
  ASSERT_EQ(f.fluid().size(), n - 1);
  ASSERT_EQ(f.excluded().size(), 1u);
  const Fluid::ExcludedParticle& x = f.excluded()[0];
  EXPECT_EQ(x.id, kFlung);
  EXPECT_EQ(f.initial_size(), n);
  EXPECT_GT(x.speed, f.parameters().c0);
  EXPECT_DOUBLE_EQ(x.time, f.time());
  EXPECT_EQ(std::count(f.fluid().id.begin(), f.fluid().id.end(), kFlung), 0);
  // The books keep the energy it took, as energy() counted it: kinetic, -m g.x and Tait's
  // compression at its density.
  const double m = f.fluid().mass, c0 = f.parameters().c0, rho0 = f.parameters().rho0, b = rho0 * c0 * c0 / 7.0;
  const double r = x.density;
  const double compression = m * b * (std::pow(r, 6) / (6.0 * std::pow(rho0, 7)) + 1.0 / r - 7.0 / (6.0 * rho0));
  EXPECT_NEAR(x.energy, 0.5 * m * x.speed * x.speed + m * 9.81 * x.y + compression, 1e-12 * x.energy);
  EXPECT_EQ(f.excluded_energy(), x.energy);
  // It carried most of the water's energy away (the column's potential about its base is small);
  // the water's books with it change over the step by the dissipation of its passage only.
  EXPECT_GT(x.energy, 0.5 * before);
  EXPECT_LT(std::abs(total(f) - before), 0.01 * before);
  for (int k = 0; k < 200; ++k) f.step(f.stable_dt());
  EXPECT_TRUE(f.sound());
  EXPECT_EQ(f.fluid().size(), n - 1);
  for (std::size_t i = 0; i < f.fluid().size(); ++i) ASSERT_TRUE(std::isfinite(f.fluid().y[i]));
  EXPECT_LT(f.max_speed(), 0.2 * f.parameters().c0);  // the rest of the column falls as water does
}

// One and two threads take the same particle out and go on with the same bits; a state taken
// after it restores into a fluid built as the original (all its particles) and continues
// bit-identically.
TEST(SphFluidExclusion, SameBitsOnOneAndTwoThreadsAndThroughAState) {
  Fluid one = column(0.02, false), two = column(0.02, true);
  fling(one);
  fling(two);
  for (int k = 0; k < 40; ++k) {
    const double dt = 0.5 * one.stable_dt();
    one.step(dt);
    two.step(dt);
  }
  ASSERT_EQ(one.excluded().size(), 1u);
  ASSERT_EQ(two.excluded().size(), 1u);
  EXPECT_TRUE(same(one.fluid().x, two.fluid().x));
  EXPECT_TRUE(same(one.fluid().vy, two.fluid().vy));
  EXPECT_TRUE(same(one.fluid().rho, two.fluid().rho));

  Fluid restored = column(0.02, true);
  restored.restore(one.state());
  EXPECT_EQ(restored.excluded().size(), 1u);
  EXPECT_EQ(restored.excluded()[0].id, kFlung);
  EXPECT_EQ(restored.excluded_energy(), one.excluded_energy());
  for (int k = 0; k < 40; ++k) {
    const double dt = one.stable_dt();
    one.step(dt);
    restored.step(dt);
  }
  EXPECT_TRUE(same(one.fluid().x, restored.fluid().x));
  EXPECT_TRUE(same(one.fluid().vx, restored.fluid().vx));
  EXPECT_TRUE(same(one.fluid().rho, restored.fluid().rho));
  EXPECT_TRUE(same(one.state().rec_fy, restored.state().rec_fy));
  // The walls' work sums the particles there are, not the arrays' room for the excluded one.
  const double w1 = one.boundary_work(), w2 = restored.boundary_work();
  EXPECT_NE(w1, 0.0);
  EXPECT_EQ(std::memcmp(&w1, &w2, sizeof(double)), 0) << w1 << " " << w2;

  // A state whose particles and excluded ones do not make up the fluid is refused.
  Fluid::State s = one.state();
  s.excluded.clear();
  EXPECT_THROW(restored.restore(s), std::invalid_argument);
}

// With no room left under the limit (0: none; 0.004 of 200: none either) the particle stays and
// the fluid is unsound, as without exclusion.
TEST(SphFluidExclusion, PastTheLimitTheFluidIsUnsound) {
  for (const double limit : {0.0, 0.004}) {
    Fluid f = column(limit);
    const std::size_t n = f.fluid().size();
    fling(f);
    f.step(0.5 * f.stable_dt());
    EXPECT_FALSE(f.sound()) << limit;
    EXPECT_EQ(f.fluid().size(), n) << limit;
    EXPECT_TRUE(f.excluded().empty()) << limit;
    EXPECT_EQ(f.fluid().id[f.first_unsound_particle()], kFlung) << limit;
  }
  // A particle whose numbers are not finite is a broken step, not water out of range: never
  // taken out, whatever the room.
  Fluid f = column(0.02);
  Fluid::State s = f.state();
  s.fluid.vx[3] = std::numeric_limits<double>::quiet_NaN();
  f.restore(s);
  f.step(0.5 * f.stable_dt());
  EXPECT_FALSE(f.sound());
  EXPECT_TRUE(f.excluded().empty());
  EXPECT_THROW(column(1.0), std::invalid_argument);
  EXPECT_THROW(column(-0.1), std::invalid_argument);
}
