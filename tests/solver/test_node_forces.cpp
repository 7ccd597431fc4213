// The node-force assembler and its booking rule (src/solver/node_forces.hpp): forces reach
// the sum the same for 1 and 2 threads, and drift_work books exactly the kinetic energy
// velocity Verlet gives a node (docs/theory.md §1, §7).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "exec/team.hpp"
#include "solver/integrator.hpp"
#include "solver/node_forces.hpp"

using namespace dsdem;
using solver::drift_work;
using solver::NodeForces;

TEST(NodeForces, PerNodeAndListedForcesAddInPlace) {
  for (bool parallel : {false, true}) {
    std::vector<Vec2> sum(5000, Vec2(1.0, -2.0));
    exec::Team team(parallel, /*automatic=*/false);
    NodeForces f(sum);
    f.add_per_node(team, [](std::size_t i) { return Vec2(0.5 * static_cast<double>(i), 1.0); });
    f.add_at(7, Vec2(3.0, 4.0));
    f.add_at(7, 1, -0.25);
    EXPECT_EQ(f.at(7), Vec2(1.0 + 3.5 + 3.0, -2.0 + 1.0 + 4.0 - 0.25));
    for (std::size_t i : {0ul, 4999ul}) EXPECT_EQ(sum[i], Vec2(1.0 + 0.5 * static_cast<double>(i), -1.0));
    EXPECT_EQ(&f.scatter(), &sum);
  }
}

TEST(NodeForces, DriftWorkIsTheTrapezoidOnTheDrift) {
  EXPECT_DOUBLE_EQ(drift_work(Vec2(1.0, 2.0), Vec2(3.0, -4.0), Vec2(0.5, 0.25)), 0.5 * (4.0 * 0.5 - 2.0 * 0.25));
  EXPECT_DOUBLE_EQ(drift_work(2.0, 4.0, -0.5), -1.5);
  // A constant force: its work is F . du.
  EXPECT_DOUBLE_EQ(drift_work(Vec2(2.0, 3.0), Vec2(2.0, 3.0), Vec2(1.0, 1.0)), 5.0);
}

// A node of mass m under a force that changes every step, integrated by velocity Verlet:
// the kinetic energy it gains is the sum of drift_work plus dt^2/8 m (|a(n)|^2 - |a(0)|^2),
// the Verlet offset the ledger books (docs/theory.md §7), to rounding.
TEST(NodeForces, DriftWorkBooksWhatVelocityVerletGives) {
  Nodes n;
  n.resize(1);
  n.m[0] = 3.0;
  n.v[0] = Vec2(0.4, -0.1);
  const double dt = 1e-2;
  auto force = [](double t, const Vec2& u) { return Vec2(2.0 * std::sin(7.0 * t) - 5.0 * u.x(), 1.5 - 4.0 * u.y()); };
  Vec2 f_prev = force(0.0, n.u[0]);
  n.a[0] = f_prev / n.m[0];
  const double ke0 = 0.5 * n.m[0] * n.v[0].squaredNorm();
  const double a2_0 = n.a[0].squaredNorm();
  double work = 0.0;
  for (int s = 1; s <= 2000; ++s) {
    const Vec2 u_before = n.u[0];
    solver::kick_and_drift(n, {dt, Vec2::Zero(), (s - 0.5) * dt, s * dt}, {}, 0, 1);
    const Vec2 f = force(s * dt, n.u[0]);
    std::vector<Vec2>& sum = n.a;  // the kick restarted it at m g = 0
    NodeForces(sum).add_at(0, f);
    work += drift_work(f_prev, f, n.u[0] - u_before);
    f_prev = f;
    solver::finish_kick(n, dt, s * dt, {}, 0, 1);
  }
  const double ke = 0.5 * n.m[0] * n.v[0].squaredNorm();
  const double offset = 0.125 * dt * dt * n.m[0] * (n.a[0].squaredNorm() - a2_0);
  EXPECT_NEAR(ke - ke0, work + offset, 1e-12 * (std::abs(work) + ke0));
}
