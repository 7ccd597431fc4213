// The time step as joints break (docs/theory.md §6): dt = safety x the stable step of
// the model as it is, taken again whenever joints break (Solver::set_time_step_rule).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "common/notched_bar.hpp"
#include "common/same_bits.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

constexpr double kSafety = 0.3;

// The bar of the direct-tension test (20 x 2 cells, 0.2 x 0.02 m) whose mid-section
// joints are 8 times stiffer than the others (penalty 80 against 10), so they control the
// stable step, and 1 % weaker, so they are the ones that break when the bar is pulled.
Model bar_with_stiff_weak_section() { return test::notched_bar(0.2, 0.02, 20, 2, 21e9, 2.5e6, 10, 80); }

// The limit of the triangles and contact springs: what the joints' limits are weighed against.
double fixed_limit(const Model& model) {
  return std::min(solver::triangle_step_limit(model, 0.0).dt, solver::contact_step_limit(model).dt);
}

// What the rule must give for the model as it is now: safety x min(fixed, intact joints),
// found by a plain scan (not the solver's ascending walk).
double expected_dt(const Model& model, double fixed) {
  double least = fixed;
  for (const auto& l : solver::joint_step_limits(model)) least = std::min(least, l.dt);
  return kSafety * least;
}

// The bar pulled (tests/common/notched_bar.hpp), light mass damping, the given dt.
void pull(solver::Solver& s, Model& model, double dt) {
  io::BoundarySpec right;
  s.set_constraints(solver::build_constraints(model, test::pull_bar(right), 0.0));
  s.set_settings({Vec2::Zero(), 2000.0, 0.0, dt, true});
}

bool is_mid_joint(const Model& model, Index j) {
  return std::abs(model.nodes.X[model.joints.nodes[j][0]].x() - 0.1) < 1e-9 &&
         std::abs(model.nodes.X[model.joints.nodes[j][1]].x() - 0.1) < 1e-9;
}

}  // namespace

// The parts of the stable step: their least is stable_time_step, and the joints' limits
// come in ascending order, each the lesser of its two ends' 2 sqrt(m/k).
TEST(StableStepParts, LeastOfThePartsIsTheStableStepAndJointsAscend) {
  Model model = bar_with_stiff_weak_section();
  const auto joints = solver::joint_step_limits(model);
  ASSERT_EQ(joints.size(), model.joints.size());
  for (std::size_t k = 1; k < joints.size(); ++k) {
    EXPECT_LE(joints[k - 1].dt, joints[k].dt) << k;
    if (joints[k - 1].dt == joints[k].dt) EXPECT_LT(joints[k - 1].joint, joints[k].joint) << k;
  }
  const auto stable = solver::stable_time_step(model, 0.0);
  EXPECT_EQ(stable.dt, std::min(fixed_limit(model), joints.front().dt));
  EXPECT_NE(stable.controlled_by.find("joint"), std::string::npos) << stable.controlled_by;
  EXPECT_TRUE(is_mid_joint(model, joints.front().joint)) << "the stiff section controls";
  // Broken joints leave the list, unless asked for all.
  model.joints.broken[joints.front().joint] = 1;
  EXPECT_EQ(solver::joint_step_limits(model).size(), joints.size() - 1);
  EXPECT_EQ(solver::joint_step_limits(model, false).size(), joints.size());
  EXPECT_EQ(solver::stable_time_step(model, 0.0).dt, std::min(fixed_limit(model), joints[1].dt));
}

// Before any joint breaks the rule gives the runner's first step bit for bit; as the
// stiff section breaks, dt grows to safety x the stable step of the rest, at every step
// equal to a fresh scan of the intact joints, never smaller than before; the energy
// still balances across the changes of step.
TEST(TimeStepRule, StepGrowsAsTheControllingJointsBreak) {
  Model model = bar_with_stiff_weak_section();
  const double first = kSafety * solver::stable_time_step(model, 0.0).dt;
  const double fixed = fixed_limit(model);
  solver::Solver s(model);
  pull(s, model, 1.0);  // a dt the rule must replace
  s.set_time_step_rule(kSafety, fixed);
  EXPECT_EQ(s.settings().dt, first);
  ASSERT_NE(s.time_step_joint(), nullptr);
  EXPECT_TRUE(is_mid_joint(model, s.time_step_joint()->joint));
  pull(s, model, 1.0);  // a new stage's settings: the rule again
  EXPECT_EQ(s.settings().dt, first);
  s.initialise();
  double dt_before = first;
  int changes = 0;
  long mid_broken = 0;
  while (s.time() < 8e-3 && mid_broken < 2) {
    s.step();
    mid_broken = 0;
    for (std::size_t j = 0; j < model.joints.size(); ++j)
      mid_broken += model.joints.broken[j] && is_mid_joint(model, static_cast<Index>(j));
    // The step just taken used the dt of the joints intact before it; the next one follows.
    if (s.settings().dt != dt_before) ++changes;
    ASSERT_GE(s.settings().dt, dt_before) << "step " << s.step_count();
    dt_before = s.settings().dt;
  }
  ASSERT_EQ(mid_broken, 2) << "the section must break";
  EXPECT_EQ(s.settings().dt, first) << "the last joint of the section broke in the step just taken: the next one takes the rule";
  s.step();  // the rule is taken at the start of a step
  EXPECT_EQ(s.settings().dt, expected_dt(model, fixed));
  EXPECT_GT(s.settings().dt, 1.5 * first) << "the section's joints were 8x stiffer";
  if (s.settings().dt != dt_before) ++changes;
  EXPECT_EQ(changes, 1) << "the other joints stay intact: one change, when the section goes";
  const auto* now = s.time_step_joint();
  if (now) EXPECT_FALSE(model.joints.broken[now->joint]);
  EXPECT_LT(s.energy().balance_error(), 1e-2);
}

// A restart takes the steps the run would have taken: the rule is taken again from the
// restored joints, and the run goes on bit for bit.
TEST(TimeStepRule, RestartGoesOnWithTheSameSteps) {
  Model a = bar_with_stiff_weak_section();
  const double fixed = fixed_limit(a);
  solver::Solver sa(a);
  pull(sa, a, 1.0);
  sa.set_time_step_rule(kSafety, fixed);
  const double first = sa.settings().dt;
  sa.initialise();
  while (sa.broken_joints() == 0 && sa.time() < 8e-3) sa.step();
  ASSERT_GT(sa.broken_joints(), 0);
  for (int i = 0; i < 20; ++i) sa.step();
  ASSERT_GT(sa.settings().dt, first);
  const auto path = std::filesystem::temp_directory_path() / ("dsdem_dt_rule_" + std::to_string(::getpid()) + ".h5");
  {
    io::CheckpointWriter w(path);
    sa.save(w);
    w.commit();
  }
  const double dt_saved = sa.settings().dt;
  for (int i = 0; i < 300; ++i) sa.step();

  Model b = bar_with_stiff_weak_section();
  solver::Solver sb(b);
  pull(sb, b, 1.0);
  sb.set_time_step_rule(kSafety, fixed);
  sb.initialise();
  EXPECT_EQ(sb.settings().dt, first);
  sb.restore(io::CheckpointReader(path));
  EXPECT_EQ(sb.settings().dt, dt_saved);
  for (int i = 0; i < 300; ++i) sb.step();
  EXPECT_EQ(sb.broken_joints(), sa.broken_joints());
  EXPECT_TRUE(test::same_motion(a, sa.time(), b, sb.time()));
  EXPECT_NE(sa.energy().verlet_kinetic_offset, 0.0);
  EXPECT_TRUE(test::same_bits(sa.energy().verlet_kinetic_offset, sb.energy().verlet_kinetic_offset));
  std::filesystem::remove(path);
}

// Velocity Verlet's kinetic offset (EnergyLedger::verlet_kinetic_offset), which the solver
// sums per stretch of one dt and settles when the ledger is read, is each step's
// dt^2/8 (S(n+1) - S(n)), S = sum m |a|^2, with that step's dt across the changes of step;
// reading the ledger every step changes none of its bits.
TEST(TimeStepRule, VerletOffsetBooksEachStepWithItsStep) {
  struct Result {
    double offset = 0.0, per_step = 0.0, balance = 0.0, first_dt = 0.0, last_dt = 0.0;
  };
  auto run = [](bool read_every_step) {
    Model model = bar_with_stiff_weak_section();
    solver::Solver s(model);
    pull(s, model, 1.0);
    s.set_time_step_rule(kSafety, fixed_limit(model));
    s.initialise();
    auto mass_accel2 = [&] {
      double sum = 0.0;
      for (std::size_t i = 0; i < model.nodes.size(); ++i) sum += model.nodes.m[i] * model.nodes.a[i].squaredNorm();
      return sum;
    };
    Result r;
    r.first_dt = s.settings().dt;
    double before = mass_accel2();
    auto step = [&] {
      s.step();
      const double after = mass_accel2();
      r.per_step += 0.125 * s.settings().dt * s.settings().dt * (after - before);
      before = after;
      if (read_every_step) r.balance = std::max(r.balance, s.energy().balance_error());
    };
    while (s.broken_joints() < 2 && s.time() < 8e-3) step();
    for (int i = 0; i < 100; ++i) step();  // on the grown step
    r.offset = s.energy().verlet_kinetic_offset;
    r.last_dt = s.settings().dt;
    return r;
  };
  const Result lazy = run(false), read = run(true);
  ASSERT_GT(lazy.last_dt, 1.5 * lazy.first_dt) << "the section must break within the run";
  EXPECT_GT(std::abs(lazy.per_step), 0.0);
  EXPECT_NEAR(lazy.offset, lazy.per_step, 1e-9 * std::abs(lazy.per_step));
  EXPECT_TRUE(test::same_bits(lazy.offset, read.offset));
  EXPECT_LT(read.balance, 1e-2);
}

TEST(TimeStepRule, RejectsASafetyOutsideItsRangeOrNoFixedLimit) {
  Model model = bar_with_stiff_weak_section();
  solver::Solver s(model);
  EXPECT_THROW(s.set_time_step_rule(0.0, 1e-6), std::invalid_argument);
  EXPECT_THROW(s.set_time_step_rule(1.5, 1e-6), std::invalid_argument);
  EXPECT_THROW(s.set_time_step_rule(0.3, 0.0), std::invalid_argument);
  EXPECT_FALSE(s.has_time_step_rule());
}

// One and two threads break the same joints at the same steps, so take the same steps
// and end bit for bit alike (the solver's OpenMP forced on for this small bar).
TEST(TimeStepRule, OneAndTwoThreadsTakeTheSameSteps) {
  struct Result {
    Model model;
    double time = 0.0, dt = 0.0;
  };
  auto run = [](int threads) {
#ifdef _OPENMP
    omp_set_num_threads(threads);
#endif
    Result r{bar_with_stiff_weak_section()};
    const double fixed = fixed_limit(r.model);
    solver::Solver s(r.model);
    s.set_parallel(true);
    pull(s, r.model, 1.0);
    s.set_time_step_rule(kSafety, fixed);
    s.initialise();
    while (s.broken_joints() < 2 && s.time() < 8e-3) s.step();
    for (int i = 0; i < 100; ++i) s.step();  // on the grown step
    r.time = s.time();
    r.dt = s.settings().dt;
#ifdef _OPENMP
    omp_set_num_threads(1);
#endif
    return r;
  };
  const Result one = run(1), two = run(2);
  EXPECT_GT(one.dt, kSafety * solver::stable_time_step(bar_with_stiff_weak_section(), 0.0).dt)
      << "the section must break within the run";
  EXPECT_TRUE(test::same_bits(one.dt, two.dt));
  EXPECT_TRUE(test::same_motion(one.model, one.time, two.model, two.time));
}
