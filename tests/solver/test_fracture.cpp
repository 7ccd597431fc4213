// Fracture through the whole solver: joints inserted in a discrete zone, loaded to
// failure.
#include <gtest/gtest.h>

#include <cmath>

#include "common/notched_bar.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/fragments.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

using test::discrete_bar_scenario;
using test::notched_bar;

// A bar of triangles and joints pulled apart breaks at sigma = ft (within 2%), along
// one crack. The mid-section is 1% weaker (a named curve) so the crack has a place to
// start, as in a notched specimen; the rest of the bar must stay bonded.
TEST(Fracture, DirectTensionBarBreaksAtTensileStrengthWithOneCrack) {
  const double L = 0.2, H = 0.02, E = 21e9, ft = 2.5e6;
  const int nx = 20, ny = 2;
  Model model = notched_bar(L, H, nx, ny, E, ft, 50);
  ASSERT_EQ(model.nodes.size(), 3 * model.triangles.size());
  solver::Solver s(model);
  io::BoundarySpec right;
  s.set_constraints(solver::build_constraints(model, test::pull_bar(right), 0.0));
  const double dt = 0.3 * solver::stable_time_step(model, 0.0).dt;
  // Light mass damping against the loading wave's ringing.
  s.set_settings({Vec2::Zero(), 2000.0, 0.0, dt, true});
  s.initialise();
  const auto& left_nodes = model.groups[model.find_group("left")].nodes;
  double peak = 0;
  while (s.time() < 6e-3 && s.broken_joints() < ny) {
    s.step();
    peak = std::max(peak, -s.reaction_on(left_nodes).x());
  }
  const double peak_stress = peak / H;
  EXPECT_NEAR(peak_stress / ft, 1.0, 0.02) << "peak stress " << peak_stress << " Pa";
  // One crack: every broken joint on the mid-section, the bar in two pieces.
  int broken = 0;
  for (std::size_t j = 0; j < model.joints.size(); ++j) {
    if (!model.joints.broken[j]) continue;
    ++broken;
    ASSERT_NE(model.joints.find_break(j), nullptr) << "joint " << j;
    EXPECT_NEAR(model.joints.find_break(j)->position.x(), L / 2, 1e-3) << "joint " << j;
    EXPECT_EQ(model.joints.break_mode(j), BreakMode::Tension);
  }
  EXPECT_EQ(broken, ny);
  std::vector<Index> label;
  EXPECT_EQ(solver::count_fragments(model, label), 2);
  EXPECT_LT(s.energy().balance_error(), 1e-2);
  EXPECT_GT(s.energy().fracture_dissipated, 0.9 * 120 * H);  // at least GI over the section
}

// The joint stiffness enters the stable step: a stiff penalty makes the joints control dt.
TEST(Fracture, StableStepAccountsForJoints) {
  RawMesh raw = mesh::rectangle_mesh(4, 2, 0.4, 0.2, mesh::Diagonal::Alternate, 0, 0, "bar");
  io::Scenario sc = discrete_bar_scenario(21e9, 2.5e6);
  sc.joints.defaults.params.values["penalty"] = 1000;
  Model model = mesh::build_model(sc, raw);
  const auto st = solver::stable_time_step(model, 0.0);
  EXPECT_NE(st.controlled_by.find("joint"), std::string::npos) << st.controlled_by;
}

// Insertion counts through the builder: every discrete triangle has its own nodes;
// joints = interior edges of the discrete zone + edges on the interface to bedrock.
TEST(Fracture, BuilderInsertsJointsAndKeepsBedrockContinuous) {
  RawMesh raw = mesh::rectangle_mesh(4, 2, 0.4, 0.2, mesh::Diagonal::Right, 0, 0.2, "slide");
  mesh::append_mesh(raw, mesh::rectangle_mesh(4, 2, 0.4, 0.2, mesh::Diagonal::Right, 0, 0, "bedrock"));
  // Merge coincident nodes along y = 0.2 so the two meshes share the interface.
  std::vector<Index> remap(raw.nodes.size());
  for (std::size_t i = 0; i < raw.nodes.size(); ++i) {
    remap[i] = static_cast<Index>(i);
    for (std::size_t k = 0; k < i; ++k)
      if ((raw.nodes[k] - raw.nodes[i]).norm() < 1e-12) {
        remap[i] = remap[k];
        break;
      }
  }
  for (auto& t : raw.triangles)
    for (auto& n : t) n = remap[n];
  io::Scenario sc = discrete_bar_scenario(21e9, 2.5e6);
  sc.regions = {io::RegionSpec{"slide", "rock", Zone::Discrete, {}, {}}, io::RegionSpec{"bedrock", "rock", Zone::Bedrock, {}, {}}};
  Model model = mesh::build_model(sc, raw);
  // slide: 16 triangles -> 48 nodes; bedrock keeps its 15 nodes.
  std::size_t used = 0;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) used += model.nodes.m[i] > 0 ? 1 : 0;
  EXPECT_EQ(used, 48u + 15u);
  // Interior edges of a 4x2 grid with diagonals: 3*2 vertical + 4*1 horizontal + 8 diagonal = 18; interface 4.
  EXPECT_EQ(model.joints.size(), 18u + 4u);
}

// A bar broken in tension and pushed back together: the two pieces meet through contact
// (no joint any more), with small overlaps and no energy blow-up.
TEST(Fracture, BrokenBarPushedBackTogetherCollidesWithoutOverlapExplosion) {
  const double L = 0.2, H = 0.02, E = 21e9, ft = 2.5e6;
  const int nx = 20, ny = 2;
  Model model = notched_bar(L, H, nx, ny, E, ft, 10);  // default penalty: a larger time step
  ASSERT_TRUE(model.contact.enabled);
  solver::Solver s(model);
  io::BoundarySpec right;
  auto bcs = test::pull_bar(right);
  s.set_constraints(solver::build_constraints(model, bcs, 0.0));
  const double dt = 0.3 * solver::stable_time_step(model, 0.0).dt;
  s.set_settings({Vec2::Zero(), 2000.0, 0.0, dt, true});
  s.initialise();
  while (s.time() < 6e-3 && s.broken_joints() < ny) s.step();
  ASSERT_EQ(s.broken_joints(), ny);
  // Push back at 0.2 m/s: the gap closes and the pieces press on each other.
  const double t_back = s.time();
  bcs[1].x = io::TimeHistory{{0.0, 1e-4}, {0.02, -0.2}};
  s.set_constraints(solver::build_constraints(model, bcs, t_back));
  const auto& left_nodes = model.groups[model.find_group("left")].nodes;
  double max_overlap = 0, max_push = 0;
  int steps_in_contact = 0;
  while (s.time() < t_back + 2e-3) {
    s.step();
    s.contact()->for_each_contact([&](const contact::ContactRecord& c) { max_overlap = std::max(max_overlap, c.overlap); });
    if (s.active_contacts() > 0) ++steps_in_contact;
    max_push = std::max(max_push, s.reaction_on(left_nodes).x());
  }
  EXPECT_GT(steps_in_contact, 100) << "the pieces never met";
  EXPECT_GT(max_push, 0.0) << "no compression reached the fixed end";
  EXPECT_LT(max_overlap, 0.01 * L / nx) << "overlap " << max_overlap << " m";
  EXPECT_EQ(s.broken_joints(), ny);  // nothing re-glued, nothing else broke
  EXPECT_LT(s.energy().balance_error(), 1e-2);
}

// docs/theory.md §3: the penalty stiffness uses the LOCAL element size. On a graded mesh
// (cells 7x narrower at one end) every joint has kn = p E / h_local, h_local the mean
// sqrt(2A) of its two triangles, and the stable step sees those stiffnesses.
TEST(Fracture, PenaltyStiffnessFollowsTheLocalElementSize) {
  RawMesh raw = mesh::rectangle_mesh(16, 4, 1.0, 0.25, mesh::Diagonal::Alternate, 0, 0, "bar");
  for (Vec2& x : raw.nodes) x.x() = x.x() * (0.25 + 0.75 * x.x());  // dx from 0.016 to 0.11 m
  io::Scenario sc = discrete_bar_scenario(21e9, 2.5e6);
  sc.joints.defaults.params.values["penalty"] = 10;
  Model model = mesh::build_model(sc, raw);
  const auto& J = model.joints;
  ASSERT_GT(J.size(), 100u);
  const JointProperties& p = model.joint_properties[0];
  ASSERT_GT(p.penalty_h, 0.0);
  double kn_min = 1e300, kn_max = 0.0, dt_joints = 1e300;
  for (std::size_t j = 0; j < J.size(); ++j) {
    const double h = joint_local_size(J, j, model.triangles.area0);
    const double kn = p.kn * J.stiffness_scale[j];
    EXPECT_NEAR(kn * h, 10 * 21e9, 1e-12 * 10 * 21e9) << "joint " << j;
    kn_min = std::min(kn_min, kn), kn_max = std::max(kn_max, kn);
    for (int e = 0; e < 2; ++e)
      dt_joints = std::min(dt_joints, joint_stable_dt(model.nodes.m[J.nodes[j][e]], model.nodes.m[J.nodes[j][2 + e]],
                                                      kn * 0.5 * J.length0[j] * model.thickness));
  }
  EXPECT_GT(kn_max / kn_min, 2.2);  // the small cells got the stiff joints (sqrt(2A) ratio ~2.6)
  const auto st = solver::stable_time_step(model, 0.0);
  EXPECT_LE(st.dt, dt_joints * (1 + 1e-12));
  if (st.controlled_by.find("joint") != std::string::npos) EXPECT_NEAR(st.dt, dt_joints, 1e-12 * dt_joints);
  // A uniform mesh keeps one stiffness: the local size is the mean size everywhere.
  Model uniform = mesh::build_model(sc, mesh::rectangle_mesh(8, 2, 0.4, 0.2, mesh::Diagonal::Alternate, 0, 0, "bar"));
  for (double s : uniform.joints.stiffness_scale) EXPECT_NEAR(s, 1.0, 1e-12);
}
