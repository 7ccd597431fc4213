// Checkpoints: a run restarted from a checkpoint continues bit-identically.
#include <H5Cpp.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/same_bits.hpp"
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
  sc.joints.defaults.params.values["ft"] = 2e4;
  sc.joints.defaults.params.values["c"] = 5e4;
  sc.joints.defaults.params.values["phi"] = 30;
  sc.joints.defaults.params.values["GI"] = 1;
  sc.joints.defaults.params.values["GII"] = 5;
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
  EXPECT_TRUE(test::same_motion(a, sa.time(), b, sb.time()));
  EXPECT_EQ(sa.energy().friction_dissipated, sb.energy().friction_dissipated);
  EXPECT_EQ(sa.energy().fracture_dissipated, sb.energy().fracture_dissipated);
  // The dashpot work of the step before the checkpoint is completed after the restart.
  EXPECT_GT(sa.energy().contact_damping_dissipated, 0.0);
  EXPECT_EQ(sa.energy().contact_damping_dissipated, sb.energy().contact_damping_dissipated);
  // Velocity Verlet's kinetic offset continues from the checkpoint's sum m|a|^2.
  EXPECT_NE(sa.energy().verlet_kinetic_offset, 0.0);
  EXPECT_EQ(sa.energy().verlet_kinetic_offset, sb.energy().verlet_kinetic_offset);
  EXPECT_EQ(sa.energy().balance_error(), sb.energy().balance_error());
  // The joint state (checkpoint version 2): histories, end modes, break records.
  const Joints &ja = a.joints, &jb = b.joints;
  for (std::size_t j = 0; j < ja.size(); ++j) {
    ASSERT_EQ(std::memcmp(ja.state[j].data(), jb.state[j].data(), sizeof(ja.state[j])), 0) << "joint " << j;
    ASSERT_EQ(ja.end_mode[j], jb.end_mode[j]) << "joint " << j;
    ASSERT_EQ(ja.broken[j], jb.broken[j]) << "joint " << j;
  }
  ASSERT_EQ(ja.breaks.size(), jb.breaks.size());
  ASSERT_GT(ja.breaks.size(), 0u);
  for (std::size_t k = 0; k < ja.breaks.size(); ++k) {
    EXPECT_EQ(ja.breaks[k].joint, jb.breaks[k].joint);
    EXPECT_EQ(ja.breaks[k].time, jb.breaks[k].time);
    EXPECT_EQ(ja.breaks[k].position, jb.breaks[k].position);
  }
  std::filesystem::remove(path);
}

// Version 1 stored the joint state in another layout (since changed): such a file
// is refused with its path and both versions, not misread.
TEST(Checkpoint, FileOfAnOlderVersionIsRejectedNamingBothVersions) {
  const auto path = std::filesystem::temp_directory_path() / ("dsdem_ckpt_v1_" + std::to_string(::getpid()) + ".h5");
  {
    H5::H5File f(path.string(), H5F_ACC_TRUNC);
    const hsize_t one = 1;
    const std::int64_t version = 1;
    f.createDataSet("dsdem_checkpoint_version", H5::PredType::NATIVE_INT64, H5::DataSpace(1, &one))
        .write(&version, H5::PredType::NATIVE_INT64);
  }
  try {
    io::CheckpointReader r(path);
    FAIL() << "a version-1 checkpoint was accepted";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find("version 1"), std::string::npos) << what;
    EXPECT_NE(what.find("version 2"), std::string::npos) << what;
  }
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
