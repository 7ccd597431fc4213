// Checkpoints: a run restarted from a checkpoint continues bit-identically (issue 8).
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

// A breakable block dropped on a contact ground: joints break, contacts come and go.
Model falling_block() {
  RawMesh raw = mesh::rectangle_mesh(8, 1, 0.8, 0.1, mesh::Diagonal::Alternate, -0.4, -0.1, "ground");
  for (auto& g : raw.groups)
    if (g.dim == 1) g.name = "ground_" + g.name;
  mesh::append_mesh(raw, mesh::rectangle_mesh(4, 4, 0.2, 0.2, mesh::Diagonal::Alternate, -0.1, 0.02, "block"));
  io::Scenario sc;
  sc.file = "(test)";
  Material m;
  m.name = "rock";
  m.E = 1e9;
  m.nu = 0.25;
  m.rho = 2500;
  sc.materials["rock"] = m;
  sc.regions = {io::RegionSpec{"ground", "rock", Zone::ContactBedrock, {}, {}},
                io::RegionSpec{"block", "rock", Zone::Discrete, {}, {}}};
  sc.joints.present = true;
  sc.joints.defaults.ft = 2e4;
  sc.joints.defaults.c = 5e4;
  sc.joints.defaults.phi_deg = 30;
  sc.joints.defaults.GI = 1;
  sc.joints.defaults.GII = 5;
  sc.contact.friction = 0.4;
  sc.contact.restitution = 0.5;
  sc.stages.push_back(io::StageSpec{});
  Model model = mesh::build_model(sc, raw);
  for (Index n : model.groups[model.find_group("block")].nodes) model.nodes.v[n] = Vec2(0.3, -3.0);
  return model;
}

void setup(solver::Solver& s, const Model& model, double dt) {
  io::BoundarySpec fixed;
  fixed.group = "ground";
  fixed.type = io::BoundaryType::Fixed;
  s.set_constraints(solver::build_constraints(model, {fixed}, 0.0));
  s.set_settings({Vec2(0, -9.81), 0.0, 0.0, dt, true});
}

}  // namespace

TEST(Checkpoint, RestartContinuesBitIdentically) {
  Model a = falling_block();
  solver::Solver sa(a);
  const double dt = 0.3 * solver::stable_time_step(a, 0.0).dt;
  setup(sa, a, dt);
  sa.initialise();
  const int half = 1500;
  for (int i = 0; i < half; ++i) sa.step();
  const auto path = std::filesystem::temp_directory_path() / ("dsdem_ckpt_" + std::to_string(::getpid()) + ".h5");
  {
    io::CheckpointWriter w(path);
    sa.save(w);
    w.commit();
  }
  for (int i = 0; i < half; ++i) sa.step();
  ASSERT_GT(sa.broken_joints(), 0) << "the test needs joints that break";

  Model b = falling_block();
  solver::Solver sb(b);
  setup(sb, b, dt);
  sb.initialise();
  sb.restore(io::CheckpointReader(path));
  EXPECT_EQ(sb.step_count(), half);
  for (int i = 0; i < half; ++i) sb.step();
  EXPECT_EQ(sb.broken_joints(), sa.broken_joints());
  const double ta = sa.time(), tb = sb.time();
  EXPECT_EQ(std::memcmp(&ta, &tb, sizeof(double)), 0);
  for (std::size_t n = 0; n < a.nodes.size(); ++n) {
    ASSERT_EQ(std::memcmp(a.nodes.u[n].data(), b.nodes.u[n].data(), 2 * sizeof(double)), 0) << "node " << n;
    ASSERT_EQ(std::memcmp(a.nodes.v[n].data(), b.nodes.v[n].data(), 2 * sizeof(double)), 0) << "node " << n;
  }
  EXPECT_EQ(sa.energy().friction_dissipated, sb.energy().friction_dissipated);
  std::filesystem::remove(path);
}

TEST(Checkpoint, WrongFileIsRejectedWithItsPath) {
  const auto path = std::filesystem::temp_directory_path() / ("dsdem_not_ckpt_" + std::to_string(::getpid()) + ".h5");
  std::ofstream(path) << "not hdf5";
  try {
    io::CheckpointReader r(path);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}
