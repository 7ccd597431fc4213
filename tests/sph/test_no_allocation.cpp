// No allocation in the SPH time loop (docs/developer-guide.md §7): after warm-up, steps of a collapsing
// water column (cell lists rebuilt, re-sorts, both passes, the boundary) allocate nothing
// while the grid does not grow. Defines the counting operator new of the test_sph binary.
#define DSDEM_DEFINE_ALLOC_COUNTER
#include "common/alloc_counter.hpp"

#include <gtest/gtest.h>

#include "sph/fluid.hpp"
#include "sph/setup.hpp"
#include "sph/solid_coupling.hpp"

using namespace dsdem;
using namespace dsdem::sph;

namespace {

// A water column 0.1 x 0.2 m in a tank 0.3 m long, released and stepped 20 times (warm-up).
// Walls up to 0.4 m: the grid spans them, so the splash stays inside it.
Fluid collapsing_column(double excluded_limit) {
  FluidParameters par;
  par.dp = 0.01;
  par.c0 = sound_speed_for(0.2, 2.0, 9.81);
  par.excluded_limit = excluded_limit;
  FluidParticles water;
  BoundaryParticles walls;
  fill_rectangle(water, 0.0, 0.0, 0.1, 0.2, par, 0.2);
  add_tank_walls(walls, 0.0, 0.0, 0.3, 0.4, wall_layers(par), par, 0.2);
  Fluid fluid(par, std::move(water), std::move(walls));
  for (int k = 0; k < 20; ++k) fluid.step(0.5 * fluid.stable_dt());
  return fluid;
}

}  // namespace

TEST(SphNoAllocation, StepsAllocateNothing) {
  Fluid fluid = collapsing_column(0.0);
  std::vector<double> fx(fluid.boundary().size()), fy(fluid.boundary().size());
  const test::AllocationScope scope;
  for (int k = 0; k < 100; ++k) fluid.step(0.5 * fluid.stable_dt());
  fluid.advance(4.0 * fluid.stable_dt());
  fluid.boundary_forces(fx, fy);
  fluid.set_packing(0.05);  // the settle's packing
  for (int k = 0; k < 10; ++k) fluid.step(0.5 * fluid.stable_dt());
  fluid.set_packing(0.0);
  EXPECT_EQ(scope.count(), 0);
  EXPECT_GT(fluid.max_speed(), 0.05);
}

// The coupling's step (place the riding particles at every sub-step, step the fluid, map the
// forces to the nodes) allocates nothing either.
TEST(SphNoAllocation, CoupledStepsAllocateNothing) {
  FluidParameters par;
  par.dp = 0.01;
  par.c0 = sound_speed_for(0.2, 2.0, 9.81);
  FluidParticles water;
  BoundaryParticles walls;
  fill_rectangle(water, 0.0, 0.0, 0.3, 0.1, par, 0.1);
  add_tank_walls(walls, 0.0, 0.0, 0.3, 0.4, wall_layers(par), par, 0.1);
  // A block 0.06 m square above the water, pushed down into it.
  const std::vector<Vec2> x0{Vec2(0.12, 0.12), Vec2(0.18, 0.12), Vec2(0.18, 0.18), Vec2(0.12, 0.18)};
  const std::vector<SolidEdge> edges{{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  lay_edge_particles(walls, edges, x0, wall_layers(par), par, 0.1);
  Fluid fluid(par, std::move(water), std::move(walls));
  SolidCoupling coupling(edges, fluid, x0);
  int step = 0;
  auto advance = [&] {
    ++step;
    const auto next = coupling.next_positions();
    for (std::size_t k = 0; k < next.size(); ++k) next[k] = x0[coupling.nodes()[k]] + Vec2(0.0, -0.5e-3 * step);
    coupling.advance(fluid, 1e-3);
  };
  for (int k = 0; k < 5; ++k) advance();
  const test::AllocationScope scope;
  for (int k = 0; k < 40; ++k) advance();
  EXPECT_EQ(scope.count(), 0);
  EXPECT_GT(coupling.particle_force_sum().norm(), 0.0);
}

// A particle taken out of the water (FluidParameters::excluded_limit) allocates nothing: its
// record goes into the room reserved for the limit, the arrays shrink within their capacity.
TEST(SphNoAllocation, TakingAParticleOutAllocatesNothing) {
  Fluid fluid = collapsing_column(0.02);
  Fluid::State s = fluid.state();
  s.fluid.vx[s.fluid.size() / 2] = 2.0 * fluid.parameters().c0;  // thrown sideways within the water's grid
  fluid.restore(s);
  const test::AllocationScope scope;
  for (int k = 0; k < 20; ++k) fluid.step(0.1 * fluid.stable_dt());
  EXPECT_EQ(scope.count(), 0);
  EXPECT_EQ(fluid.excluded().size(), 1u);
}
