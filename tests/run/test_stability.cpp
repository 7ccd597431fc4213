// The equilibrium measure of `dsdem stability` (run/stability.hpp, docs/theory.md §9).
#include <gtest/gtest.h>

#include "run/stability.hpp"

using namespace dsdem;

TEST(StabilityRatio, UnbalancedForceLeavesTheDampingForceOut) {
  Model m;
  m.nodes.resize(3);
  for (std::size_t i = 0; i < 3; ++i) m.nodes.m[i] = 2.0;
  m.nodes.m[2] = 0.0;  // massless nodes do not count
  const double g = 10.0;
  // Node 0 at rest, balanced; node 1 decelerating under its damping force alone: m a is
  // the damping force, so the force without it is zero: balanced.
  std::vector<Vec2> damping(3, Vec2::Zero());
  damping[1] = Vec2(-4.0, 0.0);
  m.nodes.a[1] = Vec2(-2.0, 0.0);
  EXPECT_NEAR(run::unbalanced_force_ratio(m, damping, g), 0.0, 1e-15);
  // Node 1 held back by the damping force only (terminal velocity, a = 0): unbalanced by
  // the 4 N the damping takes, against a mean weight of 20 N.
  m.nodes.a[1] = Vec2::Zero();
  EXPECT_DOUBLE_EQ(run::unbalanced_force_ratio(m, damping, g), 0.2);
  m.nodes.a[2] = Vec2(1e9, 0.0);  // massless: ignored
  EXPECT_DOUBLE_EQ(run::unbalanced_force_ratio(m, damping, g), 0.2);
  // An undamped step (no damping forces): the whole m a.
  EXPECT_DOUBLE_EQ(run::unbalanced_force_ratio(m, {}, g), 0.0);
}
