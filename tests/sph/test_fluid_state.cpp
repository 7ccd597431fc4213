// The water's state between steps (sph::Fluid::State, a checkpoint's content): a fluid
// built afresh and given the state of another continues with the same bits, whatever the
// phase of the re-sorts and the thread count; a state of another set-up is refused.
#include <gtest/gtest.h>

#include <omp.h>

#include <cstring>
#include <stdexcept>
#include <vector>

#include "sph/fluid.hpp"
#include "sph/setup.hpp"

using namespace dsdem;
using namespace dsdem::sph;

namespace {

constexpr int kResort = 4;

FluidParameters parameters() {
  FluidParameters par;
  par.dp = 0.01;
  par.c0 = sound_speed_for(0.2, 0.0, 9.81);
  par.alpha = 0.1;
  par.resort_interval = kResort;  // a re-sort every few steps: many of them crossed
  return par;
}

// A water column 0.1 x 0.2 m at the left of a 0.4 m tank, released: a small dam break.
Fluid column(bool parallel, double width = 0.1, const FluidParameters& par = parameters()) {
  FluidParticles water;
  BoundaryParticles walls;
  fill_rectangle(water, 0.0, 0.0, width, 0.2, par, 0.2);
  add_tank_walls(walls, 0.0, 0.0, 0.4, 0.3, wall_layers(par), par, 0.2);
  Fluid f(par, std::move(water), std::move(walls), parallel);
  f.set_record_boundary_forces(true);
  f.set_settling_damping(1.0);
  return f;
}

template <class T>
bool same(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// Every array and scalar of the two fluids' states, bit for bit.
void expect_same_state(const Fluid& a, const Fluid& b) {
  const Fluid::State s = a.state(), t = b.state();
  for (auto m : {&FluidParticles::x, &FluidParticles::y, &FluidParticles::vx, &FluidParticles::vy, &FluidParticles::rho,
                 &FluidParticles::p, &FluidParticles::vol, &FluidParticles::ax, &FluidParticles::ay,
                 &FluidParticles::drho, &FluidParticles::gx, &FluidParticles::gy})
    EXPECT_TRUE(same(s.fluid.*m, t.fluid.*m));
  EXPECT_TRUE(same(s.fluid.id, t.fluid.id));
  for (auto m : {&BoundaryParticles::x, &BoundaryParticles::y, &BoundaryParticles::vx, &BoundaryParticles::vy,
                 &BoundaryParticles::rho, &BoundaryParticles::p, &BoundaryParticles::drho, &BoundaryParticles::nx,
                 &BoundaryParticles::ny})
    EXPECT_TRUE(same(s.boundary.*m, t.boundary.*m));
  EXPECT_TRUE(same(s.rec_fx, t.rec_fx));
  EXPECT_TRUE(same(s.rec_fy, t.rec_fy));
  EXPECT_EQ(std::memcmp(&s.time, &t.time, sizeof(double)), 0);
  EXPECT_EQ(s.steps, t.steps);
  EXPECT_EQ(std::memcmp(&s.v_max, &t.v_max, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&s.a_max, &t.a_max, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&s.boundary_work, &t.boundary_work, sizeof(double)), 0);
  EXPECT_EQ(a.boundary_work(), s.boundary_work);
}

}  // namespace

// Snapshots at every phase of the re-sort cycle (steps % 4 = 0, 1, 2, 3), each restored
// into a fresh fluid on 1 and on 2 threads and run over two re-sorts: the same bits as the
// run that went on without a stop.
TEST(SphFluidState, RestoredFluidContinuesBitIdenticallyAtEveryResortPhase) {
  omp_set_num_threads(2);
  const double dt = 0.5 * column(false).stable_dt();
  const int later = 2 * kResort + 1;
  for (int phase = 0; phase < kResort; ++phase) {
    Fluid a = column(false);
    for (int k = 0; k < 20 + phase; ++k) a.step(dt);  // the column is falling
    const Fluid::State s = a.state();
    ASSERT_EQ(s.steps % kResort, (20 + phase) % kResort);
    Fluid b1 = column(false), b2 = column(true);
    for (Fluid* b : {&b1, &b2}) {
      b->set_settling_damping(0.0);  // the state's damping rate wins
      b->restore(s);
      expect_same_state(a, *b);
    }
    for (int k = 0; k < later; ++k) {
      a.step(dt);
      b1.step(dt);
      b2.step(dt);
    }
    for (const Fluid* b : {&b1, &b2}) {
      expect_same_state(a, *b);
      std::vector<double> fx(a.boundary().size()), fy(fx.size()), gx(fx.size()), gy(fx.size());
      a.boundary_forces(fx, fy);
      b->boundary_forces(gx, gy);
      EXPECT_TRUE(same(fx, gx) && same(fy, gy));
    }
  }
  omp_set_num_threads(1);
}

// The neighbour lists (Verlet lists with a skin) are not in the state: a restored fluid
// builds its own at the restore, while the run that went on built its lists steps before
// and rebuilds them at other steps. A thin skin and no re-sorts: rebuilds every few steps,
// when the falling column has moved half the skin.
TEST(SphFluidState, RestoredFluidContinuesBitIdenticallyBetweenNeighbourListRebuilds) {
  FluidParameters par = parameters();
  par.resort_interval = 0;
  par.verlet_skin = 0.05;
  Fluid a = column(false, 0.1, par);
  const double dt = a.stable_dt();
  // A checkpoint two or more steps after the last rebuild, the column falling.
  while (a.steps() < 30 || a.neighbour_lists_built_at() > a.steps() - 2) {
    a.step(dt);
    ASSERT_LT(a.steps(), 400) << "no step between two neighbour list rebuilds";
  }
  const Fluid::State s = a.state();
  omp_set_num_threads(2);
  Fluid b1 = column(false, 0.1, par), b2 = column(true, 0.1, par);
  for (Fluid* b : {&b1, &b2}) {
    b->set_settling_damping(0.0);
    b->restore(s);
    EXPECT_EQ(b->neighbour_lists_built_at(), s.steps);
  }
  EXPECT_LT(a.neighbour_lists_built_at(), s.steps);
  int rebuilds = 0, steps_on_other_lists = 0;
  for (int k = 0; k < 60; ++k) {
    const long before = a.neighbour_lists_built_at();
    a.step(dt);
    b1.step(dt);
    b2.step(dt);
    rebuilds += a.neighbour_lists_built_at() != before ? 1 : 0;
    steps_on_other_lists += a.neighbour_lists_built_at() != b1.neighbour_lists_built_at() ? 1 : 0;
  }
  omp_set_num_threads(1);
  EXPECT_GE(rebuilds, 2);
  EXPECT_GT(steps_on_other_lists, 0);
  for (const Fluid* b : {&b1, &b2}) {
    expect_same_state(a, *b);
    std::vector<double> fx(a.boundary().size()), fy(fx.size()), gx(fx.size()), gy(fx.size());
    a.boundary_forces(fx, fy);
    b->boundary_forces(gx, gy);
    EXPECT_TRUE(same(fx, gx) && same(fy, gy));
  }
}

TEST(SphFluidState, StateOfAnotherSetUpIsRefused) {
  Fluid a = column(false);
  Fluid wider = column(false, 0.12);
  ASSERT_NE(a.fluid().size(), wider.fluid().size());
  try {
    wider.restore(a.state());
    FAIL() << "a state with another particle count was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("fluid"), std::string::npos) << e.what();
  }
  Fluid::State s = a.state();
  s.boundary.edge[0] = 3;  // the particle rides an edge it did not
  EXPECT_THROW(a.restore(s), std::invalid_argument);
}
