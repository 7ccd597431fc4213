// Instability detection in Solver::check_stability: non-finite state, inverted
// elements, energy growing beyond the work put in; and no false alarm on a healthy run.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

io::Scenario block_scenario(Zone zone) {
  io::Scenario sc;
  sc.file = "(test)";
  Material m;
  m.name = "rock";
  m.E = 10e9;
  m.nu = 0.25;
  m.rho = 2500;
  sc.materials["rock"] = m;
  sc.regions.push_back(io::RegionSpec{"block", "rock", zone, {}, {}});
  if (zone == Zone::Discrete) {
    sc.joints.present = true;
    sc.joints.defaults.params.values["ft"] = 1e9;  // strong: the joints stay elastic
    sc.joints.defaults.params.values["c"] = 4e9;
    sc.joints.defaults.params.values["phi"] = 30;
    sc.joints.defaults.params.values["GI"] = 1e6;
    sc.joints.defaults.params.values["GII"] = 1e7;
    sc.joints.defaults.params.values["penalty"] = 50;
  }
  sc.stages.push_back(io::StageSpec{});
  return sc;
}

Model block(Zone zone, int n = 6) {
  const RawMesh raw = mesh::rectangle_mesh(n, n, 1.0, 1.0, mesh::Diagonal::Alternate, 0, 0, "block");
  return mesh::build_model(block_scenario(zone), raw);
}

std::vector<solver::PrescribedDof> fixed_bottom(const Model& model) {
  io::BoundarySpec bottom;
  bottom.group = "bottom";
  bottom.type = io::BoundaryType::Fixed;
  return solver::build_constraints(model, {bottom}, 0.0);
}

// Runs until an InstabilityError (returned) or max_steps (kind "").
solver::InstabilityError run_until_unstable(solver::Solver& s, long max_steps) {
  try {
    for (long i = 0; i < max_steps; ++i) s.step();
  } catch (const solver::InstabilityError& e) {
    return e;
  }
  return solver::InstabilityError("none", "", kNoIndex, Vec2::Zero(), -1, 0.0);
}

}  // namespace

TEST(Instability, NonFiniteVelocityNamesTheNode) {
  Model model = block(Zone::Bedrock);
  solver::Solver s(model);
  s.set_constraints(fixed_bottom(model));
  s.set_settings({Vec2(0, -9.81), 0.0, 0.0, 0.3 * solver::stable_time_step(model, 0.0).dt, true});
  s.initialise();
  for (int i = 0; i < 10; ++i) s.step();
  const Index victim = static_cast<Index>(model.nodes.size() - 2);
  model.nodes.v[victim].x() = std::numeric_limits<double>::quiet_NaN();
  const auto e = run_until_unstable(s, 5);
  EXPECT_EQ(e.kind, "non_finite") << e.what();
  // Within the step the NaN reaches the victim's neighbours; the first of them is named.
  ASSERT_NE(e.id, kNoIndex);
  EXPECT_EQ(e.position, model.nodes.X[e.id]);
  EXPECT_LE((e.position - model.nodes.X[victim]).norm(), 0.25) << "named node " << e.id << " is next to " << victim;
  EXPECT_EQ(e.step, 11);  // the 11th step went bad
  EXPECT_GT(e.time, 0.0);
  EXPECT_NE(std::string(e.what()).find("node " + std::to_string(e.id)), std::string::npos) << e.what();
}

TEST(Instability, InvertedElementNamesTheElementAndItsCentre) {
  Model model = block(Zone::Bedrock);
  solver::Solver s(model);
  s.set_constraints(fixed_bottom(model));
  s.set_settings({Vec2(0, -9.81), 0.0, 0.0, 0.3 * solver::stable_time_step(model, 0.0).dt, true});
  s.initialise();
  // Push the top-right corner node through its triangle.
  const Index corner = static_cast<Index>(model.nodes.size() - 1);
  model.nodes.u[corner] = Vec2(-2.0, -2.0);
  const auto e = run_until_unstable(s, 3);
  EXPECT_EQ(e.kind, "inverted_element") << e.what();
  ASSERT_NE(e.id, kNoIndex);
  const auto& c = model.triangles.conn[e.id];
  EXPECT_TRUE(c[0] == corner || c[1] == corner || c[2] == corner) << "element " << e.id;
  EXPECT_EQ(e.step, 1);
  EXPECT_NE(std::string(e.what()).find("inverted element " + std::to_string(e.id)), std::string::npos) << e.what();
}

// A time step above the real limit (as a stiffness the stable-step estimate missed would
// give): the high modes grow exponentially. The ledger sees energy appear that no force
// put in, and stops the run before the state overflows or an element turns over.
TEST(Instability, EnergyGrowthBeyondTheWorkPutInIsDetected) {
  Model model = block(Zone::Bedrock);
  solver::Solver s(model);
  s.set_constraints(fixed_bottom(model));
  const double dt = 1.15 * solver::stable_time_step(model, 0.0).dt;
  s.set_settings({Vec2(0, -9.81), 0.0, 0.0, dt, true});
  s.initialise();
  const auto e = run_until_unstable(s, 20000);
  EXPECT_EQ(e.kind, "energy_growth") << e.what();
  ASSERT_NE(e.id, kNoIndex);
  EXPECT_GT(e.step, 5);
  EXPECT_NE(std::string(e.what()).find("energy growing beyond the work put in"), std::string::npos) << e.what();
  EXPECT_TRUE(std::isfinite(s.energy().kinetic));
}

// No false alarm: a velocity imposed suddenly at t = 0 (an impulse the ledger does not
// count as work) and gravity, at the normal safety factor, for many steps.
TEST(Instability, HealthyRunWithSuddenVelocityRaisesNothing) {
  Model model = block(Zone::Discrete, 4);
  solver::Solver s(model);
  io::BoundarySpec bottom;
  bottom.group = "bottom";
  bottom.type = io::BoundaryType::Fixed;
  io::BoundarySpec top;
  top.group = "top";
  top.type = io::BoundaryType::Velocity;
  top.y = io::TimeHistory{{0.0}, {-0.05}};
  s.set_constraints(solver::build_constraints(model, {bottom, top}, 0.0));
  s.set_settings({Vec2(0, -9.81), 50.0, 0.0, 0.3 * solver::stable_time_step(model, 0.0).dt, true});
  s.initialise();
  const auto e = run_until_unstable(s, 3000);
  EXPECT_EQ(e.kind, "") << e.what();
}
