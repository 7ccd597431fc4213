// The energy ledger books each contact dissipation as velocity Verlet applies it
// (docs/theory.md §7): a head-on collision of two meshed blocks with contact damping and a
// stack of blocks at rest close their balance at the default time step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "contact/shape_map.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

struct Block {
  std::string name;
  int nx, ny;
  double lx, ly, x0, y0;
};

// Separate elastic blocks (each its own continuous mesh, contact on), E = 1 GPa; contact
// kn from its default rule (p_c E).
Model blocks_model(const std::vector<Block>& blocks, double restitution, double friction) {
  RawMesh raw;
  io::Scenario sc;
  sc.file = "(test)";
  Material m;
  m.name = "rock";
  m.E = 1e9;
  m.nu = 0.25;
  m.rho = 2500;
  sc.materials["rock"] = m;
  for (const Block& b : blocks) {
    RawMesh r = mesh::rectangle_mesh(b.nx, b.ny, b.lx, b.ly, mesh::Diagonal::Alternate, b.x0, b.y0, b.name);
    for (auto& g : r.groups)
      if (g.dim == 1) g.name = b.name + "_" + g.name;
    if (raw.nodes.empty())
      raw = r;
    else
      mesh::append_mesh(raw, r);
    sc.regions.push_back(io::RegionSpec{b.name, "rock", Zone::ContactBedrock, {}, {}});
  }
  sc.contact.friction = friction;
  sc.contact.restitution = restitution;
  sc.stages.push_back(io::StageSpec{});
  return mesh::build_model(sc, raw);
}

Vec2 group_velocity(const Model& m, const std::string& group) {
  double mass = 0.0;
  Vec2 p = Vec2::Zero();
  for (Index n : m.groups[m.find_group(group)].nodes) {
    mass += m.nodes.m[n];
    p += m.nodes.m[n] * m.nodes.v[n];
  }
  return p / mass;
}


// The work of each part of the contact forces as velocity Verlet applies it, from the
// records after each step: half of each force's work over the step's displacement, at the
// half-step velocity v(n+1/2) = v(n+1) - dt/2 a(n+1) it was computed with, and half over
// the next step's (no prescribed nodes in contact). An independent check of the ledger's
// booking; start() takes the records of initialise().
struct ContactWork {
  double elastic = 0.0, dashpot = 0.0, tangential = 0.0;  // J/m, on the bodies
  double tangential_energy = 0.0;                         // sum |ft|^2 / (2 ks) now
  std::vector<contact::ContactRecord> last;               // the previous step's records
  void start(const solver::Solver& s) {
    last.clear();
    s.contact()->for_each_contact([&](const contact::ContactRecord& r) { last.push_back(r); });
  }
  void add(const solver::Solver& s, const Model& model) {
    const double dt = s.settings().dt, ks = model.contact.defaults.ks;
    const auto& nd = model.nodes;
    auto half = [&](const contact::ContactRecord& r) {  // the halves over this step
      const auto& ci = model.triangles.conn[r.key.i];
      const auto& cj = model.triangles.conn[r.key.j];
      Vec2 du = Vec2::Zero();  // relative displacement of the step at the record's point
      for (int k = 0; k < 3; ++k)
        du += dt * (r.Ni[k] * (nd.v[ci[k]] - 0.5 * dt * nd.a[ci[k]]) - r.Nj[k] * (nd.v[cj[k]] - 0.5 * dt * nd.a[cj[k]]));
      elastic += 0.5 * (r.fn - r.dashpot_force) * r.normal.dot(du);
      dashpot += 0.5 * r.dashpot_force * r.normal.dot(du);
      tangential += 0.5 * r.ft.dot(du);
    };
    for (const contact::ContactRecord& r : last) half(r);
    last.clear();
    tangential_energy = 0.0;
    s.contact()->for_each_contact([&](const contact::ContactRecord& r) {
      half(r);
      last.push_back(r);
      if (ks > 0.0) tangential_energy += 0.5 * r.ft.squaredNorm() / ks;
    });
  }
};

struct Collision {
  double lost = 0.0;             // mechanical energy lost, J/m
  double booked = 0.0;           // contact damping booked, J/m
  double friction = 0.0;         // friction booked, J/m
  double balance_final = 0.0;    // balance error at the end
  double balance_max = 0.0;      // largest balance error over the run
  double elastic_work = 0.0;      // of the contact springs, J/m (0 for a conservative spring)
  double dashpot_work = 0.0;      // of the contact dashpots, J/m
  double restitution = 0.0;      // effective: separation over approach speed of the centres of mass
};

// Two 0.2 m square blocks (4 x 4 cells) meet head-on at 2 m/s, no gravity, no friction;
// the right one y_offset higher.
Collision head_on(double safety, double e, double y_offset) {
  Model model = blocks_model({{"left", 4, 4, 0.2, 0.2, -0.21, 0.0}, {"right", 4, 4, 0.2, 0.2, 0.01, y_offset}}, e, 0.0);
  for (Index n : model.groups[model.find_group("left")].nodes) model.nodes.v[n] = Vec2(1.0, 0.0);
  for (Index n : model.groups[model.find_group("right")].nodes) model.nodes.v[n] = Vec2(-1.0, 0.0);
  solver::Solver s(model);
  s.set_settings({Vec2::Zero(), 0.0, 0.0, safety * solver::stable_time_step(model, 0.0).dt, true});
  s.initialise();
  const double e0 = s.energy().mechanical();
  const double approach = (group_velocity(model, "left") - group_velocity(model, "right")).x();
  Collision c;
  ContactWork work;
  work.start(s);
  bool touched = false;
  int after = -1;  // steps since the last contact ended
  while (s.time() < 0.1 && after < 200) {
    s.step();
    work.add(s, model);
    c.balance_max = std::max(c.balance_max, s.energy().balance_error());
    touched = touched || s.active_contacts() > 0;
    if (touched) after = s.active_contacts() > 0 ? 0 : after + 1;
  }
  EXPECT_TRUE(touched);
  EXPECT_EQ(s.active_contacts(), 0);
  const solver::EnergyLedger& L = s.energy();
  c.lost = e0 - L.mechanical();
  c.booked = L.contact_damping_dissipated;
  c.friction = L.friction_dissipated;
  c.balance_final = L.balance_error();
  c.elastic_work = work.elastic;
  c.dashpot_work = work.dashpot;
  c.restitution = (group_velocity(model, "right") - group_velocity(model, "left")).x() / approach;
  return c;
}

}  // namespace

// Restitution 0.5, default contact kn, mu = 0: the contact damping booked is the work of
// the dashpot forces as velocity Verlet applies them, at any step; the mechanical energy
// lost is that, less the work of the contact springs, which velocity Verlet does not make
// vanish where contacts start and end (a few per cent of it at safety 0.3). That work is
// what the balance error is left with: O(dt^2), it falls ninefold from safety 0.3 to 0.1.
TEST(EnergyLedger, HeadOnCollisionBooksTheDampingItApplies) {
  for (double safety : {0.3, 0.1, 0.03}) {
    const Collision c = head_on(safety, 0.5, 0.05);
    std::printf("safety %.2f: lost %.4f J/m, contact damping booked %.4f J/m (%+.3f %%), balance error %.4f %% "
                "(largest %.4f %%), effective restitution %.4f; work of the dashpots %.4f, of the springs %.4f J/m\n",
                safety, c.lost, c.booked, 100.0 * (c.booked / c.lost - 1.0), 100.0 * c.balance_final,
                100.0 * c.balance_max, c.restitution, c.dashpot_work, c.elastic_work);
    EXPECT_GT(c.lost, 0.0);
    EXPECT_EQ(c.friction, 0.0) << "a frictionless collision books no friction";
    EXPECT_NEAR(c.booked, -c.dashpot_work, 1e-9 * c.booked) << "safety " << safety;
    if (safety == 0.3) EXPECT_LT(c.balance_final, 0.005);
    if (safety == 0.1) EXPECT_LT(c.balance_final, 0.001);
    if (safety == 0.03) EXPECT_LT(c.balance_final, 1e-4);
    if (safety == 0.03) EXPECT_NEAR(c.booked / c.lost, 1.0, 0.005);
  }
}

// The dashpot is sized on the two touching triangles' reduced mass (contact/dashpot_mass.hpp),
// not the blocks': meshed blocks meeting face to face rebound livelier than the set e
// (docs/scenario-reference.md, contact.restitution).
TEST(EnergyLedger, MeshedBlocksReboundLivelierThanTheSetRestitution) {
  const Collision c = head_on(0.3, 0.5, 0.0);
  EXPECT_GT(c.restitution, 0.75);
  EXPECT_LT(c.restitution, 0.9);
}

// Five blocks stacked (staggered) on a fixed ground, gravity, friction and contact damping,
// from touching at zero overlap: they settle; contact damping and friction are booked as
// applied, and the balance closes but for the work of the contact springs where contacts
// open and close. The nodes at the contacts keep vibrating near the stable step, so the
// ledger needs velocity Verlet's kinetic offset (EnergyLedger::verlet_kinetic_offset).
TEST(EnergyLedger, StackOfFiveBlocksBooksDampingAndFrictionAsApplied) {
  std::vector<Block> blocks{{"ground", 4, 1, 0.4, 0.1, -0.1, -0.1}};
  for (int k = 0; k < 5; ++k) blocks.push_back({"b" + std::to_string(k), 4, 2, 0.2, 0.1, 0.03 * (k % 2), 0.1 * k});
  Model model = blocks_model(blocks, 0.5, 0.5);
  solver::Solver s(model);
  io::BoundarySpec fixed;
  fixed.group = "ground";
  fixed.type = io::BoundaryType::Fixed;
  s.set_constraints(solver::build_constraints(model, {fixed}, 0.0));
  s.set_settings({Vec2(0, -9.81), 0.0, 0.0, 0.3 * solver::stable_time_step(model, 0.0).dt, true});
  s.initialise();
  double balance_max = 0.0;
  const int steps = 20000;
  ContactWork work;
  work.start(s);
  for (int i = 0; i < steps; ++i) {
    s.step();
    work.add(s, model);
    if (i >= steps / 10) balance_max = std::max(balance_max, s.energy().balance_error());
  }
  const solver::EnergyLedger& L = s.energy();
  std::printf("stack: kinetic %.3e, gravity %.4e, strain %.4e, contact elastic %.4e, contact damping %.4e, "
              "friction %.4e, Verlet kinetic offset %.4e J/m; balance error %.4f %% (largest after the first "
              "tenth %.4f %%)\n",
              L.kinetic, L.gravity_potential, L.strain, L.contact_elastic, L.contact_damping_dissipated,
              L.friction_dissipated, L.verlet_kinetic_offset, 100.0 * L.balance_error(), 100.0 * balance_max);
  std::printf("stack: work of the dashpots %.4e, springs %.4e (contact elastic %.4e), tangential %.4e, tangential "
              "energy %.4e J/m: friction by the integrator %.4e J/m\n", work.dashpot, work.elastic, L.contact_elastic,
              work.tangential, work.tangential_energy, -work.tangential - work.tangential_energy);
  EXPECT_LT(L.kinetic, 1e-3 * std::abs(L.gravity_potential)) << "not at rest";
  // The dashpots' work as applied (the last step's second halves are booked next step).
  EXPECT_NEAR(L.contact_damping_dissipated, -work.dashpot, 1e-9 * L.contact_damping_dissipated);
  // Friction: the tangential forces' work as applied less the energy their springs hold.
  EXPECT_NEAR(L.friction_dissipated, -work.tangential - work.tangential_energy, 0.01 * L.friction_dissipated);
  EXPECT_LT(L.balance_error(), 0.005);
  EXPECT_LT(balance_max, 0.005);
}
