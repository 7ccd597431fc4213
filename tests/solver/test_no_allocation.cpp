// No heap allocation inside the time loop after warm-up: Solver::step() on a
// model with joints (some breaking) and contacts allocates nothing once its buffers
// have grown. The global operator new of the test_solver binary is replaced here to
// count calls (tests/common/alloc_counter.hpp; the only replacement in test_solver).
#include <gtest/gtest.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#define DSDEM_DEFINE_ALLOC_COUNTER  // the counting operator new of test_solver
#include "common/alloc_counter.hpp"
#include "common/block_on_ground.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

void check_no_allocation(int threads, bool parallel) {
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  Model model = test::impact_block(24, 12);
  solver::Solver s(model);
  s.set_parallel(parallel);
  io::BoundarySpec fixed;
  fixed.group = "ground";
  fixed.type = io::BoundaryType::Fixed;
  s.set_constraints(solver::build_constraints(model, {fixed}, 0.0));
  s.set_settings({Vec2(0.0, -9.81), 50.0, 1e-7, 0.3 * solver::stable_time_step(model, 1e-7).dt, true});
  // The step taken again as joints break (the runner's default): its walk runs in the loop.
  s.set_time_step_rule(0.3, std::min(solver::triangle_step_limit(model, 1e-7).dt, solver::contact_step_limit(model).dt));
  s.initialise();
  // Warm-up: buffers grow, threads start, and the impact's contact count passes its peak
  // (the contact buffers grow geometrically while the count rises, which is allowed).
  long warm_contacts = 0;
  for (int k = 0; k < 600; ++k) {
    s.step();
    warm_contacts = std::max<long>(warm_contacts, s.active_contacts());
  }
  const long broken_before = s.broken_joints();
  const long before = test::g_allocations.load();
  long max_contacts = 0;
  for (int k = 0; k < 200; ++k) {
    s.step();
    max_contacts = std::max<long>(max_contacts, s.active_contacts());
  }
  const long allocations = test::g_allocations.load() - before;
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  EXPECT_EQ(allocations, 0) << threads << " thread(s); contacts: peak " << warm_contacts << " in warm-up, "
                            << max_contacts << " after";
  // The measured steps did the work that could allocate: contacts and breaking joints.
  EXPECT_GT(max_contacts, 0);
  EXPECT_GT(s.broken_joints(), broken_before);
}

}  // namespace

TEST(NoAllocation, CounterSeesAllocations) {
  const long before = test::g_allocations.load();
  auto* p = new std::vector<double>(10);
  delete p;
  EXPECT_GE(test::g_allocations.load() - before, 2);
}

TEST(NoAllocation, StepAllocatesNothingAfterWarmUpSerial) { check_no_allocation(1, false); }

TEST(NoAllocation, StepAllocatesNothingAfterWarmUpTwoThreads) { check_no_allocation(2, true); }
