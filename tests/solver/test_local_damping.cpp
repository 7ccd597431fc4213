// Cundall's local non-viscous damping (solver/local_damping.hpp, docs/theory.md §9): the
// kernel, a column brought to rest by it alone with its work booked as applied, and a
// mass under a steady unbalanced force that it slows but never stops.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/boundary_spec.hpp"
#include "common/materials.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/local_damping.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

Material rock() { return test::elastic_material("rock", 1e9, 0.25, 2500); }

using test::boundary_spec;

}  // namespace

TEST(LocalDamping, OpposesEachVelocityComponentWithAFractionOfTheForce) {
  const Vec2 fd = solver::local_damping_force(Vec2(3.0, -4.0), Vec2(1e-9, 2.0), 0.8);
  EXPECT_DOUBLE_EQ(fd.x(), -0.8 * 3.0);  // moving +x: pushed back by 0.8 |fx|
  EXPECT_DOUBLE_EQ(fd.y(), -0.8 * 4.0);  // moving +y: pushed back by 0.8 |fy|, whatever fy's sign
  const Vec2 rest = solver::local_damping_force(Vec2(3.0, -4.0), Vec2(0.0, -1.0), 0.8);
  EXPECT_EQ(rest.x(), 0.0);  // a component at rest takes none
  EXPECT_DOUBLE_EQ(rest.y(), 0.8 * 4.0);
  // The same kernel in 3D.
  const Eigen::Vector3d f3 = solver::local_damping_force(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(-1, 0, 1), 0.5);
  EXPECT_DOUBLE_EQ(f3.x(), 0.5);
  EXPECT_EQ(f3.y(), 0.0);
  EXPECT_DOUBLE_EQ(f3.z(), -1.5);
}

// A column on a fixed base between rollers, gravity switched on at rest, local damping
// alone (no Rayleigh damping): it comes to rest with the base carrying the weight, and
// the ledger books the damping's work exactly as the integrator applies it.
TEST(LocalDamping, BringsAGravityColumnToRestAndBooksItsWork) {
  const double H = 10.0, rho = 2500, g = 9.81;
  Model model = mesh::build_model(mesh::rectangle_mesh(2, 20, 1.0, H, mesh::Diagonal::Alternate), rock());
  solver::Solver s(model);
  s.set_constraints(solver::build_constraints(
      model,
      {boundary_spec("left", io::BoundaryType::Roller, 0), boundary_spec("right", io::BoundaryType::Roller, 0),
       boundary_spec("bottom", io::BoundaryType::Fixed)},
      0.0));
  solver::StepSettings st;
  st.gravity = Vec2(0, -g);
  st.dt = 0.5 * solver::stable_time_step(model, 0.0).dt;
  st.local_damping = 0.8;
  s.set_settings(st);
  s.initialise();
  const double T1 = 4.0 * H / model.materials[0].cp();  // the column's first period
  double peak = 0.0;
  while (s.time() < 30.0 * T1) {
    s.step();
    peak = std::max(peak, s.kinetic_energy());
  }
  const auto& e = s.energy();
  std::printf("[ measured ] local damping: kinetic %.3e of its peak after 30 periods, damping dissipated %.4e J/m, "
              "balance error %.2e\n", e.kinetic / peak, e.damping_dissipated, e.balance_error());
  EXPECT_LT(e.kinetic, 1e-8 * peak);
  EXPECT_GT(e.damping_dissipated, 0.1 * e.strain);
  EXPECT_LT(e.balance_error(), 1e-6);
  const Vec2 reaction = s.reaction_on(model.groups[model.find_group("bottom")].nodes);
  EXPECT_NEAR(reaction.y(), rho * g * H * 1.0, 1e-5 * rho * g * H);
  // The damping force it took is the one the step applied: m a = f - f_damping at rest is 0.
  ASSERT_EQ(s.damping_forces().size(), model.nodes.size());
}

// A free block under gravity alone: every node's unbalanced force is m g, so it falls at
// (1 - 0.8) g: local damping slows a mass under a steady force, it never holds it.
TEST(LocalDamping, SlowsButNeverStopsAMassUnderASteadyForce) {
  Model model = mesh::build_model(mesh::rectangle_mesh(2, 2, 1.0, 1.0, mesh::Diagonal::Alternate), rock());
  solver::Solver s(model);
  solver::StepSettings st;
  st.gravity = Vec2(0, -9.81);
  st.dt = 1e-4;
  st.local_damping = 0.8;
  s.set_settings(st);
  s.initialise();
  for (int i = 0; i < 1000; ++i) s.step();
  // At rest at the start the first half kick takes the whole g (no velocity, no damping).
  const double expected = -0.2 * 9.81 * s.time() - 0.8 * 9.81 * 0.5 * st.dt;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) EXPECT_NEAR(model.nodes.v[i].y(), expected, 1e-12);
  EXPECT_LT(s.energy().balance_error(), 1e-9);
}
