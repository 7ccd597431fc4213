// Results do not depend on the thread count (issue 7): the same model with a discrete
// zone (joints that break) and contact, run for a few hundred steps on 1 and on 2
// OpenMP threads, gives bit-identical node positions and velocities.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "common/block_on_ground.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

// The block of tests/common/block_on_ground.hpp: joints on every interior edge,
// contact on, hitting the ground at 20 m/s, so joints break within a few hundred steps.
Model impact_model(int nx, int ny) {
  test::BlockOnGround b;
  b.nx = nx;
  b.ny = ny;
  return test::block_on_ground(b);
}

struct RunResult {
  std::vector<Vec2> u, v;
  long broken = 0;
  long contacts = 0;
  double kinetic = 0.0;
};

RunResult run(int threads, int steps) {
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  Model model = impact_model(24, 12);
  solver::Solver s(model);
  s.set_parallel(true);  // this model is below the size that switches OpenMP on by itself
  io::BoundarySpec fixed;
  fixed.group = "ground";
  fixed.type = io::BoundaryType::Fixed;
  s.set_constraints(solver::build_constraints(model, {fixed}, 0.0));
  s.set_settings({Vec2(0.0, -9.81), 50.0, 1e-7, 0.3 * solver::stable_time_step(model, 1e-7).dt, true});
  s.initialise();
  RunResult r;
  for (int k = 0; k < steps; ++k) {
    s.step();
    r.contacts = std::max<long>(r.contacts, s.active_contacts());
  }
  r.u = model.nodes.u;
  r.v = model.nodes.v;
  r.broken = s.broken_joints();
  r.kinetic = s.energy().kinetic;
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  return r;
}

bool bitwise_equal(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec2)) == 0;
}

}  // namespace

TEST(Determinism, OneAndTwoThreadsGiveBitIdenticalResults) {
  const int steps = 400;
  const RunResult one = run(1, steps);
  const RunResult two = run(2, steps);
  // The run must exercise what could differ: joints breaking and contacts.
  EXPECT_GT(one.broken, 0);
  EXPECT_GT(one.contacts, 0);
  EXPECT_EQ(one.broken, two.broken);
  EXPECT_TRUE(bitwise_equal(one.u, two.u)) << "node displacements differ between 1 and 2 threads";
  EXPECT_TRUE(bitwise_equal(one.v, two.v)) << "node velocities differ between 1 and 2 threads";
  EXPECT_EQ(std::memcmp(&one.kinetic, &two.kinetic, sizeof(double)), 0);
}

TEST(Determinism, RepeatedRunsAreBitIdentical) {
  const RunResult a = run(2, 150);
  const RunResult b = run(2, 150);
  EXPECT_TRUE(bitwise_equal(a.u, b.u));
}
