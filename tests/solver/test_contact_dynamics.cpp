// Contact through the whole solver: sliding, sticking, collisions, stacks.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

struct BodySpec {
  std::string name;
  int nx, ny;
  double lx, ly, x0, y0;
  Zone zone = Zone::ContactBedrock;
  double E = 1e9;
};

// Builds a model of separate rectangular bodies (each its own continuous mesh).
Model bodies_model(const std::vector<BodySpec>& bodies, const io::ContactSpec& contact) {
  RawMesh raw;
  io::Scenario sc;
  sc.file = "(test)";
  for (const auto& b : bodies) {
    RawMesh m = mesh::rectangle_mesh(b.nx, b.ny, b.lx, b.ly, mesh::Diagonal::Alternate, b.x0, b.y0, b.name);
    for (auto& g : m.groups)
      if (g.dim == 1) g.name = b.name + "_" + g.name;
    if (raw.nodes.empty()) {
      raw = m;
    } else {
      mesh::append_mesh(raw, m);
    }
    Material mat;
    mat.name = b.name + "_mat";
    mat.E = b.E;
    mat.nu = 0.25;
    mat.rho = 2500;
    sc.materials[mat.name] = mat;
    sc.regions.push_back(io::RegionSpec{b.name, mat.name, b.zone, {}, {}});
  }
  sc.contact = contact;
  sc.stages.push_back(io::StageSpec{});
  return mesh::build_model(sc, raw);
}

io::BoundarySpec fixed(const std::string& group) {
  io::BoundarySpec b;
  b.group = group;
  b.type = io::BoundaryType::Fixed;
  return b;
}

// Centre-of-mass position and velocity of one surface group.
std::pair<Vec2, Vec2> centre_of_mass(const Model& m, const std::string& group) {
  const auto& nodes = m.groups[m.find_group(group)].nodes;
  double mass = 0;
  Vec2 x = Vec2::Zero(), v = Vec2::Zero();
  for (Index n : nodes) {
    mass += m.nodes.m[n];
    x += m.nodes.m[n] * m.nodes.x(n);
    v += m.nodes.m[n] * m.nodes.v[n];
  }
  return {x / mass, v / mass};
}

}  // namespace

// Gravity tilted by 30 degrees stands in for a 30-degree incline (exact, no geometry
// error): x(t) = g (sin t - mu cos t) t^2 / 2 within 1% at t = 1 s.
TEST(ContactDynamics, BlockSlidesDownThirtyDegreeInclineAsCoulombPredicts) {
  io::ContactSpec cs;
  cs.friction = 0.3;
  cs.restitution = 0.5;
  Model model = bodies_model({{"ground", 40, 1, 4.0, 0.2, -0.2, -0.2}, {"block", 2, 2, 0.2, 0.2, 0.0, 0.0}}, cs);
  solver::Solver s(model);
  s.set_constraints(solver::build_constraints(model, {fixed("ground")}, 0.0));
  const double g = 9.81, theta = 30.0 * kPi / 180.0, mu = 0.3;
  s.set_settings({Vec2(g * std::sin(theta), -g * std::cos(theta)), 0.0, 0.0, 0.3 * solver::stable_time_step(model, 0.0).dt, true});
  s.initialise();
  const Vec2 x0 = centre_of_mass(model, "block").first;
  while (s.time() < 1.0) s.step();
  const double expected = 0.5 * g * (std::sin(theta) - mu * std::cos(theta)) * s.time() * s.time();
  const double moved = centre_of_mass(model, "block").first.x() - x0.x();
  EXPECT_NEAR(moved / expected, 1.0, 0.01) << "moved " << moved << " m, Coulomb " << expected << " m";
  EXPECT_GT(s.active_contacts(), 0);
}

// tan(10 deg) < mu = 0.3: the block sticks; creep below 1e-4 of its size in 2 s.
TEST(ContactDynamics, BlockOnGentleInclineDoesNotCreep) {
  io::ContactSpec cs;
  cs.friction = 0.3;
  cs.restitution = 0.2;
  Model model = bodies_model({{"ground", 10, 1, 1.0, 0.2, -0.4, -0.2}, {"block", 2, 2, 0.2, 0.2, 0.0, 0.0}}, cs);
  solver::Solver s(model);
  s.set_constraints(solver::build_constraints(model, {fixed("ground")}, 0.0));
  const double g = 9.81, theta = 10.0 * kPi / 180.0;
  s.set_settings({Vec2(g * std::sin(theta), -g * std::cos(theta)), 0.0, 0.0, 0.3 * solver::stable_time_step(model, 0.0).dt, true});
  s.initialise();
  while (s.time() < 0.2) s.step();  // landing transient
  const double x_settled = centre_of_mass(model, "block").first.x();
  while (s.time() < 2.2) s.step();
  const double creep = std::abs(centre_of_mass(model, "block").first.x() - x_settled);
  EXPECT_LT(creep, 1e-4 * 0.2) << "creep " << creep << " m";
}

// Two single-triangle bodies meeting tip to tip on their axis of symmetry: the rebound
// follows the set coefficient of restitution within 2%, and momentum is conserved.
TEST(ContactDynamics, TipToTipImpactHonoursRestitution) {
  for (double e : {0.9, 0.5, 0.2}) {
    RawMesh raw;
    raw.source = "tips";
    raw.nodes = {Vec2(-0.3, -0.1), Vec2(-0.05, 0.0), Vec2(-0.3, 0.1), Vec2(0.05, 0.0), Vec2(0.3, 0.1), Vec2(0.3, -0.1)};
    raw.triangles = {{0, 1, 2}, {3, 5, 4}};
    RawPhysicalGroup a, b;
    a.name = "a";
    a.triangles = {0};
    b.name = "b";
    b.triangles = {1};
    raw.groups = {a, b};
    raw.triangle_surface_group = {0, 1};
    io::Scenario sc;
    sc.file = "(test)";
    Material m;
    m.name = "steel";
    m.E = 200e9;
    m.nu = 0.3;
    m.rho = 7800;
    sc.materials["steel"] = m;
    sc.regions = {io::RegionSpec{"a", "steel", Zone::ContactBedrock, {}, {}}, io::RegionSpec{"b", "steel", Zone::ContactBedrock, {}, {}}};
    sc.contact.kn = 1e8;  // much softer than the triangles
    sc.contact.friction = 0.0;
    sc.contact.restitution = e;
    sc.stages.push_back(io::StageSpec{});
    Model model = mesh::build_model(sc, raw);
    for (Index n : {0, 1, 2}) model.nodes.v[n] = Vec2(2.0, 0.0);
    solver::Solver s(model);
    s.set_settings({Vec2::Zero(), 0.0, 0.0, 0.3 * solver::stable_time_step(model, 0.0).dt, true});
    s.initialise();
    bool touched = false;
    while (s.time() < 0.5) {
      s.step();
      touched = touched || s.active_contacts() > 0;
      if (touched && s.active_contacts() == 0) break;
    }
    ASSERT_TRUE(touched);
    const double va = centre_of_mass(model, "a").second.x(), vb = centre_of_mass(model, "b").second.x();
    EXPECT_NEAR((vb - va) / 2.0, e, 0.02 * e) << "restitution";
    EXPECT_NEAR(va + vb, 2.0, 1e-10 * 2.0) << "momentum";
  }
}

// Head-on collision of two meshed blocks, no gravity: momentum conserved, a damped
// contact rebounds less, a frictionless elastic one gains no energy.
TEST(ContactDynamics, HeadOnCollisionOfBlocksConservesMomentumAndGainsNoEnergy) {
  double previous_rebound = 2.0;
  for (double e : {1.0, 0.5}) {
    io::ContactSpec cs;
    cs.friction = 0.0;
    cs.restitution = e;
    cs.kn = 1e7;  // soft contact against stiff blocks: the blocks move almost rigidly
    Model model = bodies_model({{"left", 2, 2, 0.2, 0.2, -0.25, 0.0, Zone::ContactBedrock, 50e9},
                                {"right", 2, 2, 0.2, 0.2, 0.05, 0.0, Zone::ContactBedrock, 50e9}},
                               cs);
    for (Index n : model.groups[model.find_group("left")].nodes) model.nodes.v[n] = Vec2(1.0, 0.0);
    for (Index n : model.groups[model.find_group("right")].nodes) model.nodes.v[n] = Vec2(-0.5, 0.0);
    solver::Solver s(model);
    s.set_settings({Vec2::Zero(), 0.0, 0.0, 0.3 * solver::stable_time_step(model, 0.0).dt, true});
    s.initialise();
    auto momentum = [&] {
      Vec2 p = Vec2::Zero();
      for (std::size_t i = 0; i < model.nodes.size(); ++i) p += model.nodes.m[i] * model.nodes.v[i];
      return p;
    };
    const Vec2 p0 = momentum();
    const double ke0 = s.energy().kinetic;
    bool touched = false;
    while (s.time() < 0.2) {
      s.step();
      touched = touched || s.active_contacts() > 0;
      if (touched && s.active_contacts() == 0) break;
    }
    ASSERT_TRUE(touched);
    EXPECT_LT((momentum() - p0).norm(), 1e-10 * p0.norm());
    const double v_left = centre_of_mass(model, "left").second.x(), v_right = centre_of_mass(model, "right").second.x();
    const double rebound = (v_right - v_left) / (1.0 - (-0.5));
    EXPECT_LT(rebound, previous_rebound);
    previous_rebound = rebound;
    const double after = s.energy().kinetic + s.energy().strain;
    EXPECT_LE(after, ke0 * (1 + 1e-3)) << "energy gained " << after / ke0 - 1;
    // The ledger books the dashpots as velocity Verlet applies them (docs/theory.md §7);
    // what is left is the contact springs' own net work where contacts open and close
    // within a step, which no smaller time step removes.
    EXPECT_LT(s.energy().balance_error(), 2e-3);
  }
}

// Ten blocks stacked on the ground settle and stay at rest: no drift, no jitter growth.
TEST(ContactDynamics, StackOfTenBlocksSettlesAndStaysAtRest) {
  io::ContactSpec cs;
  cs.friction = 0.5;
  cs.restitution = 0.3;
  std::vector<BodySpec> bodies{{"ground", 4, 1, 0.4, 0.1, -0.1, -0.1}};
  for (int k = 0; k < 10; ++k) bodies.push_back({"b" + std::to_string(k), 1, 1, 0.2, 0.1, 0.0, 0.1 * k});
  Model model = bodies_model(bodies, cs);
  solver::Solver s(model);
  s.set_constraints(solver::build_constraints(model, {fixed("ground")}, 0.0));
  const double dt = 0.3 * solver::stable_time_step(model, 0.0).dt;
  s.set_settings({Vec2(0, -9.81), 0.0, 0.0, dt, true});
  s.initialise();
  const int steps = 100000;
  double ke_mid_max = 0, ke_late_max = 0;
  Vec2 top_mid = Vec2::Zero();
  for (int i = 0; i < steps; ++i) {
    s.step();
    if (i >= steps / 2 && i < 3 * steps / 4) ke_mid_max = std::max(ke_mid_max, s.energy().kinetic);
    if (i == 3 * steps / 4) top_mid = centre_of_mass(model, "b9").first;
    if (i >= 3 * steps / 4) ke_late_max = std::max(ke_late_max, s.energy().kinetic);
  }
  const Vec2 top_end = centre_of_mass(model, "b9").first;
  const double weight_work = 10 * 0.02 * 2500 * 9.81 * 0.1;  // scale: weight x one block height
  EXPECT_LE(ke_late_max, ke_mid_max * 1.0001 + 1e-12) << "jitter grew";
  EXPECT_LT(ke_late_max, 1e-6 * weight_work) << "not at rest";
  EXPECT_LT((top_end - top_mid).norm(), 1e-6) << "drift";
  EXPECT_NEAR(top_end.x(), 0.1, 1e-4);  // still stacked
}
