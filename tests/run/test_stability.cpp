// The equilibrium measure of `dsdem stability` (run/stability.hpp, DESIGN.md §12).
#include <gtest/gtest.h>

#include "run/stability.hpp"

using namespace dsdem;

TEST(StabilityRatio, UnbalancedForceLeavesTheDampingForceOut) {
  Model m;
  m.nodes.resize(3);
  for (std::size_t i = 0; i < 3; ++i) m.nodes.m[i] = 2.0;
  m.nodes.m[2] = 0.0;  // massless nodes do not count
  const double g = 10.0, alpha = 4.0;
  // Node 0 at rest, balanced; node 1 creeping at v under damping alone: a = -alpha v, so
  // the force without the damping force, m (a + alpha v), is zero: balanced.
  m.nodes.v[1] = Vec2(0.5, 0.0);
  m.nodes.a[1] = Vec2(-alpha * 0.5, 0.0);
  EXPECT_NEAR(run::unbalanced_force_ratio(m, alpha, g), 0.0, 1e-15);
  // Node 1 held back by the damping force only (terminal velocity, a = 0): unbalanced by
  // m alpha v = 4 N against a mean weight of 20 N.
  m.nodes.a[1] = Vec2::Zero();
  EXPECT_DOUBLE_EQ(run::unbalanced_force_ratio(m, alpha, g), 0.2);
  m.nodes.a[2] = Vec2(1e9, 0.0);  // massless: ignored
  EXPECT_DOUBLE_EQ(run::unbalanced_force_ratio(m, alpha, g), 0.2);
}
