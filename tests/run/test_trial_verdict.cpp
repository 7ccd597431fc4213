// How a strength-reduction trial is judged (run/trial_verdict.hpp, docs/theory.md §9): the
// motion trend over a doubling of the trial, and Rayleigh's quotients that size the
// observation window and the adaptive damping.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "run/trial_verdict.hpp"

using namespace dsdem;

namespace {

// Samples every 50 steps to step n of a displacement d(step) and a ratio r(step).
std::vector<run::TrialSample> history(long n, const std::function<double(double)>& d,
                                      const std::function<double(double)>& r) {
  std::vector<run::TrialSample> h;
  for (long s = 50; s <= n; s += 50) h.push_back({s, r(static_cast<double>(s)), d(static_cast<double>(s))});
  return h;
}

}  // namespace

TEST(TrialVerdict, AMassThatAcceleratesOrCreepsSteadilyKeepsMoving) {
  const long n = 8000;
  const auto flat = [](double) { return 1e-3; };
  // Accelerating (d ~ t^2): the velocity doubles over the doubling.
  auto t = run::motion_trend(history(n, [](double s) { return 1e-9 * s * s; }, flat), 50, 1e-4);
  EXPECT_TRUE(t.keeps_moving);
  EXPECT_NEAR(t.velocity_late / t.velocity_early, 2.0, 1e-9);
  // Creeping at a terminal velocity under heavy damping: the velocity stops falling.
  t = run::motion_trend(history(n, [](double s) { return 1e-6 * s; }, flat), 50, 1e-4);
  EXPECT_TRUE(t.keeps_moving);
  EXPECT_NEAR(t.moved_late, 1e-6 * n / 2, 1e-12);
}

TEST(TrialVerdict, AMassComingToRestDoesNot) {
  const long n = 8000;
  // Motion decaying with a time constant of n/4 steps, its unbalanced force with it.
  const double tau = n / 4.0;
  auto t = run::motion_trend(history(n, [&](double s) { return 1e-2 * (1 - std::exp(-s / tau)); },
                                     [&](double s) { return 1e-2 * std::exp(-s / tau); }),
                             50, 1e-6);
  EXPECT_FALSE(t.keeps_moving);
  EXPECT_LT(t.velocity_late, 0.5 * t.velocity_early);
  // Steady motion whose unbalanced force has fallen below half: still settling.
  t = run::motion_trend(history(n, [](double s) { return 1e-6 * s; }, [&](double s) { return std::exp(-s / tau); }),
                        50, 1e-6);
  EXPECT_FALSE(t.keeps_moving);
  // Motion too small to count (below the floor): not a failure.
  t = run::motion_trend(history(n, [](double s) { return 1e-12 * s; }, [](double) { return 1e-3; }), 50, 1e-6);
  EXPECT_FALSE(t.keeps_moving);
  // Swinging back over (n/4, n/2] then forward again: not a failure, however far.
  t = run::motion_trend(history(n, [&](double s) { return 0.3 + 0.2 * std::cos(2.0 * std::numbers::pi * s / n); },
                                [](double) { return 1e-3; }),
                        50, 1e-6);
  EXPECT_LT(t.velocity_early, 0.0);
  EXPECT_NEAR(t.moved_late, 0.4, 1e-9);
  EXPECT_FALSE(t.keeps_moving);
  // Not a judgement step (samples not a multiple of 4): no verdict.
  auto h = history(n, [](double s) { return 1e-6 * s; }, [](double) { return 1e-3; });
  h.pop_back();
  EXPECT_FALSE(run::motion_trend(h, 50, 1e-6).keeps_moving);
}

// A mass on a spring: Rayleigh's quotient of any of its motions is k / m, and its static
// deflection under gravity m g / k gives its period 2 pi sqrt(m / k).
TEST(TrialVerdict, RayleighQuotientsOfASpringMass) {
  Nodes n;
  n.resize(2);
  n.m[0] = 4.0;
  n.m[1] = 0.0;  // massless: left out
  const double k = 900.0, g = 9.81;
  const std::vector<Vec2> du{Vec2(0.0, -0.02), Vec2(5.0, 5.0)};
  const std::vector<Vec2> df{Vec2(0.0, 0.02 * k), Vec2(1e9, 0.0)};  // the spring pushes back by k du
  EXPECT_DOUBLE_EQ(run::rayleigh_omega2(n, du, df), k / 4.0);
  // Softening along the motion (the force grows with it): a negative quotient.
  const std::vector<Vec2> soft{Vec2(0.0, -0.02 * k), Vec2::Zero()};
  EXPECT_LT(run::rayleigh_omega2(n, du, soft), 0.0);
  const std::vector<Vec2> deflection{Vec2(0.0, -4.0 * g / k), Vec2::Zero()};
  EXPECT_NEAR(run::rayleigh_period(n, deflection, Vec2(0, -g)), 2 * std::numbers::pi * std::sqrt(4.0 / k), 1e-12);
  EXPECT_EQ(run::rayleigh_period(n, std::vector<Vec2>(2, Vec2::Zero()), Vec2(0, -g)), 0.0);
  EXPECT_DOUBLE_EQ(run::shear_column_period(30.0, 1200.0), 0.1);
}
