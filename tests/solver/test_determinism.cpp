// Results do not depend on the thread count: the same model with a discrete
// zone (joints that break) and contact, run for a few hundred steps on 1 and on 2
// OpenMP threads, gives bit-identical node positions and velocities.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <tuple>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "common/block_on_ground.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

struct RunResult {
  std::vector<Vec2> u, v;
  long broken = 0;
  long contacts = 0;
  double kinetic = 0.0;
  double contact_damping = 0.0, friction = 0.0;  // J/m
  long steps_on_partition_chunks = 0;  // node loops split where the contact partition put its threads
};

// parallel: 1 on, 0 off (set_parallel), -1 the solver's own (timed) choice. modes: the
// parallel() flag seen after each step, when given.
RunResult run(int threads, int steps, int nx = 24, int ny = 12, int parallel = 1, std::vector<bool>* modes = nullptr) {
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  Model model = test::impact_block(nx, ny);
  solver::Solver s(model);
  // The 24 x 12 model is below the size that switches OpenMP on by itself.
  if (parallel >= 0) s.set_parallel(parallel == 1);
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
    r.steps_on_partition_chunks += s.node_chunks().empty() ? 0 : 1;
    if (modes) modes->push_back(s.parallel());
  }
  r.u = model.nodes.u;
  r.v = model.nodes.v;
  r.broken = s.broken_joints();
  r.kinetic = s.energy().kinetic;
  r.contact_damping = s.energy().contact_damping_dissipated;
  r.friction = s.energy().friction_dissipated;
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
  // Two threads: the node loops follow the contact phase's partition (from its second
  // step on, but for the steps after a broad-phase rebuild).
  EXPECT_EQ(one.steps_on_partition_chunks, 0);
#ifdef _OPENMP
  EXPECT_GT(two.steps_on_partition_chunks, steps / 2);
#endif
  EXPECT_EQ(one.broken, two.broken);
  EXPECT_TRUE(bitwise_equal(one.u, two.u)) << "node displacements differ between 1 and 2 threads";
  EXPECT_TRUE(bitwise_equal(one.v, two.v)) << "node velocities differ between 1 and 2 threads";
  EXPECT_EQ(std::memcmp(&one.kinetic, &two.kinetic, sizeof(double)), 0);
  EXPECT_GT(one.contact_damping, 0.0);
  EXPECT_EQ(std::memcmp(&one.contact_damping, &two.contact_damping, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&one.friction, &two.friction, sizeof(double)), 0);
}

// Prescribed velocities and displacements are applied by each thread to the nodes of its
// own range, in the kick and in the velocity update: supports spread over the
// node numbering (the block's curves, numbered first, and the ground's, numbered last)
// must end with their prescribed values and the same bits on 1 and 2 threads.
TEST(Determinism, PrescribedMotionsOnEveryThreadsNodes) {
  auto run_prescribed = [](int threads) {
#ifdef _OPENMP
    omp_set_num_threads(threads);
#endif
    Model model = test::impact_block(24, 12);
    solver::Solver s(model);
    s.set_parallel(true);
    io::BoundarySpec fixed, left, top;
    fixed.group = "ground_bottom";
    fixed.type = io::BoundaryType::Fixed;
    left.group = "left";  // the block's left side: x velocity ramping from 0 to 2 m/s
    left.type = io::BoundaryType::Velocity;
    left.x = io::TimeHistory{{0.0, 1e-3}, {0.0, 2.0}};
    top.group = "top";  // the block's top: y displacement -0.1 mm per 0.1 ms
    top.type = io::BoundaryType::Displacement;
    top.y = io::TimeHistory{{0.0, 1e-3}, {0.0, -1e-3}};
    s.set_constraints(solver::build_constraints(model, {fixed, left, top}, 0.0));
    s.set_settings({Vec2(0.0, -9.81), 50.0, 1e-7, 0.3 * solver::stable_time_step(model, 1e-7).dt, true});
    s.initialise();
    for (int k = 0; k < 200; ++k) s.step();
    const double t = s.time();
    std::vector<Vec2> u = model.nodes.u, v = model.nodes.v;
    double worst_v = 0.0, worst_u = 0.0;
    for (Index i : model.groups[model.find_group("left")].nodes) worst_v = std::max(worst_v, std::abs(v[i].x() - left.x->at(t)));
    for (Index i : model.groups[model.find_group("top")].nodes) worst_u = std::max(worst_u, std::abs(u[i].y() - top.y->at(t)));
#ifdef _OPENMP
    omp_set_num_threads(1);
#endif
    return std::make_tuple(u, v, worst_v, worst_u, model.nodes.size());
  };
  const auto [u1, v1, dv1, du1, n] = run_prescribed(1);
  const auto [u2, v2, dv2, du2, n2] = run_prescribed(2);
  EXPECT_LT(dv1, 1e-12);
  EXPECT_LT(du1, 1e-15);
  EXPECT_LT(dv2, 1e-12);
  EXPECT_LT(du2, 1e-15);
  EXPECT_TRUE(bitwise_equal(u1, u2)) << "node displacements differ between 1 and 2 threads";
  EXPECT_TRUE(bitwise_equal(v1, v2)) << "node velocities differ between 1 and 2 threads";
}

TEST(Determinism, RepeatedRunsAreBitIdentical) {
  const RunResult a = run(2, 150);
  const RunResult b = run(2, 150);
  EXPECT_TRUE(bitwise_equal(a.u, b.u));
}

// Large models choose between OpenMP and one thread by timing both (Solver::kProbeSteps):
// a run that switches mode mid-way gives the same bits as a serial one.
TEST(Determinism, AutomaticSwitchBetweenSerialAndParallelKeepsTheBits) {
#ifdef _OPENMP
  const int steps = 3 * solver::Solver::kProbeSteps + 8;  // past the first probe window
  std::vector<bool> modes;
  const RunResult automatic = run(2, steps, 70, 30, -1, &modes);  // 4200 triangles: above kParallelThreshold
  const RunResult serial = run(1, steps, 70, 30, 0);
  EXPECT_NE(std::find(modes.begin(), modes.end(), true), modes.end()) << "never ran in parallel";
  EXPECT_NE(std::find(modes.begin(), modes.end(), false), modes.end()) << "never ran on one thread";
  EXPECT_TRUE(bitwise_equal(automatic.u, serial.u));
  EXPECT_TRUE(bitwise_equal(automatic.v, serial.v));
#else
  GTEST_SKIP() << "built without OpenMP";
#endif
}
