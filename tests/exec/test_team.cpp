// The thread team's timed choice between one thread and OpenMP (exec::Team).
#include <gtest/gtest.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "exec/team.hpp"

using dsdem::exec::Team;

namespace {
// Runs steps `from`..`to` (steps done after each), each taking `serial` seconds on one
// thread and `parallel` on the threads.
long run(Team& team, long from, long to, double serial, double parallel) {
  for (long s = from; s <= to; ++s) team.record_step(team.parallel() ? parallel : serial, s);
  return to + 1;
}
}  // namespace

// A machine that becomes busy while the run is on the threads (other processes now
// deschedule a thread at every barrier): the team probes again within a few dozen steps
// instead of at the next regular window, and goes to one thread.
TEST(Team, ABusyMachineSendsTheRunToOneThreadWithinAFewDozenSteps) {
#ifdef _OPENMP
  omp_set_num_threads(2);
  Team team(true, true);
  ASSERT_TRUE(team.automatic());
  long s = run(team, 1, 2 * Team::kProbeSteps + Team::kProbeSteps, 1.0e-3, 0.6e-3);  // first window: threads faster
  ASSERT_TRUE(team.parallel());
  s = run(team, s, s + 200, 1.0e-3, 0.6e-3);  // steady: no new window
  EXPECT_TRUE(team.parallel());
  EXPECT_EQ(team.serial_steps_chosen(), Team::kProbeSteps);  // the first window's serial half
  // Busy: the threads' steps now take 8 times as long, one thread's twice.
  const long busy_from = s;
  s = run(team, s, s + Team::kWatchSteps + 2 * Team::kProbeSteps + 2, 2.0e-3, 5.0e-3);
  EXPECT_FALSE(team.parallel()) << "still on the threads " << s - busy_from << " steps after the machine got busy";
  omp_set_num_threads(1);
#else
  GTEST_SKIP() << "built without OpenMP";
#endif
}

// A few slow steps (a broad-phase rebuild) do not start a window.
TEST(Team, AFewSlowStepsDoNotStartAProbe) {
#ifdef _OPENMP
  omp_set_num_threads(2);
  Team team(true, true);
  long s = run(team, 1, 3 * Team::kProbeSteps, 1.0e-3, 0.6e-3);
  ASSERT_TRUE(team.parallel());
  const long serial_before = team.serial_steps_chosen();
  for (int k = 0; k < 10; ++k) {
    s = run(team, s, s + 5, 1.0e-3, 0.6e-3);
    s = run(team, s, s, 1.0e-3, 5.0e-3);  // one slow step in six
  }
  EXPECT_TRUE(team.parallel());
  EXPECT_EQ(team.serial_steps_chosen(), serial_before);
  omp_set_num_threads(1);
#else
  GTEST_SKIP() << "built without OpenMP";
#endif
}
