// Water at rest on meshed solids (docs/theory.md §8) through the solver: Archimedes and
// Terzaghi at every node, a floating block at its draft, the water's work in the energy
// balance, and the same bits for 1 and 2 threads and across a checkpoint.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "common/block_on_ground.hpp"
#include "common/same_bits.hpp"
#include "io/checkpoint.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

constexpr double kRhoW = 1000.0, kG = 9.81;

// One rectangular block [x0, x0 + lx] x [y0, y0 + ly] of density rho, E = 100 MPa.
Model block(int nx, int ny, double lx, double ly, double x0, double y0, double rho, Zone zone) {
  io::Scenario sc = test::impact_scenario();
  Material m;
  m.name = "soft";
  m.E = 1e8;
  m.nu = 0.25;
  m.rho = rho;
  sc.materials["soft"] = m;
  RawMesh raw = mesh::rectangle_mesh(nx, ny, lx, ly, mesh::Diagonal::Alternate, x0, y0, "block");
  sc.regions.push_back(io::RegionSpec{"block", "soft", zone, {}, {}});
  return mesh::build_model(sc, raw);
}

solver::WaterSetup level(double z) {
  solver::WaterSetup w;
  w.line = water::PiezometricLine::level(z);
  w.density = kRhoW;
  w.gravity = kG;
  return w;
}

double bottom(const Model& m) {
  double y = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodes.X[i].y() == 0.0) y += m.nodes.x(static_cast<Index>(i)).y(), ++n;
  return y / n;
}

}  // namespace

// Below a flat pool every node of a submerged block, continuous or jointed, feels the
// buoyancy of its share of the block, rho_w g m / rho upward: the net force is rho_w g A
// (Archimedes), and weight plus water are the buoyant weight node by node, so the
// effective stress is that of a dry block of density rho - rho_w (Terzaghi).
TEST(WaterOnSolids, EveryNodeOfASubmergedBlockCarriesItsBuoyancy) {
  for (const Zone zone : {Zone::Bedrock, Zone::Discrete}) {
    const double rho = 2500.0;
    Model m = block(4, 3, 2.0, 1.5, -1.0, 0.0, rho, zone);
    solver::Solver s(m);
    s.set_settings({Vec2::Zero(), 0.0, 0.0, 1e-5, true});
    s.set_water(level(4.0));
    s.initialise();
    Vec2 net = Vec2::Zero();
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
      const Vec2 f = m.nodes.m[i] * m.nodes.a[i];
      net += f;
      const double expected = kRhoW / rho * m.nodes.m[i] * kG;
      EXPECT_NEAR(f.x(), 0.0, 1e-9 * expected) << i;
      EXPECT_NEAR(f.y(), expected, 1e-9 * expected) << i;
    }
    EXPECT_NEAR(net.y(), kRhoW * kG * 2.0 * 1.5, 1e-9 * kRhoW * kG * 3.0);
    EXPECT_NEAR(net.x(), 0.0, 1e-9 * kRhoW * kG * 3.0);
  }
}

// Where moving water covers the span (docs/theory.md §11) it replaces the static water on exposed
// edges whose midpoint lies over that span; the pore pressure inside the solid stays. A
// submerged block whose left half lies under the moving water keeps the pore pressure's
// share (-p I in the elements: zero net force on a saturated block at rest, weightless here),
// so its nodes carry only the missing edge pressure: the net force is the pressure of the
// right half's faces alone, pushing the block left, with no net vertical buoyancy from the
// left half's bottom.
TEST(WaterOnSolids, MovingWaterTakesOverTheEdgePressureOverItsSpan) {
  Model m = block(4, 2, 2.0, 1.0, 0.0, 0.0, 2500.0, Zone::Bedrock);
  solver::Solver s(m);
  s.set_settings({Vec2::Zero(), 0.0, 0.0, 1e-5, true});
  solver::WaterSetup w = level(3.0);
  w.moving_x_min = -1.0;
  w.moving_x_max = 1.0;  // the left half, x in [0, 1]: its bottom and left faces
  s.set_water(w);
  s.initialise();
  Vec2 net = Vec2::Zero();
  for (std::size_t i = 0; i < m.nodes.size(); ++i) net += m.nodes.m[i] * m.nodes.a[i];
  // Left: rho g (3 - y) over the face y in [0, 1] missing, so the right face's push wins.
  const double side = kRhoW * kG * (3.0 - 0.5) * 1.0;
  EXPECT_NEAR(net.x(), -side, 1e-9 * side);
  // Up: the right half's bottom, x in [1, 2] at depth 3, less the top's at depth 2.
  const double up = kRhoW * kG * (3.0 - 2.0) * 1.0;
  EXPECT_NEAR(net.y(), up, 1e-9 * side);
}

// A block as dense as water, under water: weight and water cancel at every node, it does
// not move and its effective stress stays zero.
TEST(WaterOnSolids, NeutralBlockUnderWaterKeepsZeroEffectiveStress) {
  Model m = block(4, 4, 1.0, 1.0, 0.0, 0.0, kRhoW, Zone::Bedrock);
  solver::Solver s(m);
  s.set_settings({Vec2(0.0, -kG), 0.0, 0.0, 0.3 * solver::stable_time_step(m, 0.0).dt, true});
  s.set_water(level(3.0));
  s.initialise();
  for (int k = 0; k < 2000; ++k) s.step();
  double worst = 0.0;
  for (const Vec3& sig : m.triangles.stress) worst = std::max(worst, sig.cwiseAbs().maxCoeff());
  EXPECT_LT(worst, 1e-9 * kRhoW * kG * 3.0);
}

// A wide block of density 500 dropped into water at rest settles at a draft of half its
// height (Archimedes), and the ledger books the water's work so the balance closes.
TEST(WaterOnSolids, FloatingBlockSettlesAtItsArchimedesDraft) {
  const double H = 0.5, pool = 0.8;
  Model m = block(8, 2, 2.0, H, 0.0, 0.0, 500.0, Zone::Bedrock);
  solver::Solver s(m);
  const double alpha = 6.0;  // about 0.7 of critical for the heave (omega = sqrt(rho_w g / (rho H)))
  s.set_settings({Vec2(0.0, -kG), alpha, 0.0, 0.3 * solver::stable_time_step(m, 0.0).dt, true});
  s.set_water(level(pool));
  s.initialise();
  while (s.time() < 5.0) s.step();
  const double draft = pool - bottom(m);
  EXPECT_NEAR(draft, 0.5 * H, 0.01 * 0.5 * H);
  EXPECT_GT(s.energy().water_work, 0.0);  // the water lifted the block
  EXPECT_LT(s.energy().balance_error(), 1e-3);
}

namespace {

struct WetRun {
  std::vector<Vec2> u, v;
  double water_work = 0.0;
  long broken = 0;
};

// The jointed block hitting the ground (joints break, contacts) with the pool at its
// middle.
WetRun wet_impact(int threads, int steps) {
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  Model model = test::impact_block(24, 12);
  solver::Solver s(model);
  s.set_parallel(true);
  io::BoundarySpec fixed;
  fixed.group = "ground";
  fixed.type = io::BoundaryType::Fixed;
  s.set_constraints(solver::build_constraints(model, {fixed}, 0.0));
  s.set_settings({Vec2(0.0, -9.81), 50.0, 1e-7, 0.3 * solver::stable_time_step(model, 1e-7).dt, true});
  solver::WaterSetup w = level(0.06);
  w.line = water::PiezometricLine({Vec2(-1.0, 0.05), Vec2(1.0, 0.08)});
  s.set_water(w);
  s.initialise();
  for (int k = 0; k < steps; ++k) s.step();
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  return {model.nodes.u, model.nodes.v, s.energy().water_work, s.broken_joints()};
}

}  // namespace

TEST(WaterOnSolids, OneAndTwoThreadsGiveTheSameBits) {
  const WetRun one = wet_impact(1, 300), two = wet_impact(2, 300);
  EXPECT_GT(one.broken, 0);
  EXPECT_NE(one.water_work, 0.0);
  EXPECT_TRUE(test::same_bits(one.water_work, two.water_work));
  ASSERT_EQ(one.u.size(), two.u.size());
  for (std::size_t i = 0; i < one.u.size(); ++i) {
    ASSERT_TRUE(test::same_bits(one.u[i].x(), two.u[i].x()) && test::same_bits(one.u[i].y(), two.u[i].y())) << i;
    ASSERT_TRUE(test::same_bits(one.v[i].x(), two.v[i].x()) && test::same_bits(one.v[i].y(), two.v[i].y())) << i;
  }
}

TEST(WaterOnSolids, CheckpointRestartContinuesBitIdentically) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "dsdem_water_checkpoint.h5";
  Model a = block(8, 2, 2.0, 0.5, 0.0, 0.0, 500.0, Zone::Bedrock), b = a;
  solver::Solver sa(a), sb(b);
  for (auto* s : {&sa, &sb}) {
    s->set_settings({Vec2(0.0, -kG), 1.0, 0.0, 0.3 * solver::stable_time_step(a, 0.0).dt, true});
    s->set_water(level(0.8));
    s->initialise();
  }
  for (int k = 0; k < 500; ++k) sa.step();
  {
    io::CheckpointWriter w(path.string());
    sa.save(w);
    w.commit();
  }
  sb.restore(io::CheckpointReader(path.string()));
  std::filesystem::remove(path);
  for (int k = 0; k < 300; ++k) {
    sa.step();
    sb.step();
  }
  EXPECT_TRUE(test::same_motion(a, sa.time(), b, sb.time()));
  EXPECT_TRUE(test::same_bits(sa.energy().water_work, sb.energy().water_work));
  EXPECT_TRUE(test::same_bits(sa.energy().balance_error(), sb.energy().balance_error()));
}

// Lowering the pool (a drawdown) between stages: the block follows the water down, and
// the water's work stays booked through the change.
TEST(WaterOnSolids, DrawdownLowersTheFloatingBlock) {
  Model m = block(8, 2, 2.0, 0.5, 0.0, 0.0, 500.0, Zone::Bedrock);
  solver::Solver s(m);
  s.set_settings({Vec2(0.0, -kG), 6.0, 0.0, 0.3 * solver::stable_time_step(m, 0.0).dt, true});
  s.set_water(level(0.8));
  s.initialise();
  while (s.time() < 4.0) s.step();
  s.set_water(level(0.6));
  while (s.time() < 8.0) s.step();
  EXPECT_NEAR(0.6 - bottom(m), 0.25, 0.0025);
  EXPECT_LT(s.energy().balance_error(), 1e-3);
}

// Water standing in a crack pushes its faces apart while they are close; once the block
// in front has moved away by more than the joint's length the crack has drained.
TEST(WaterOnSolids, CrackWaterDrainsOnceTheCrackOpensWide) {
  Model m = test::impact_block(4, 2);  // jointed block: its joints' faces are the "crack" below
  const Index g = static_cast<Index>(m.groups.size());
  m.groups.push_back(Group{});
  m.groups.back().name = "crack";
  for (auto& cg : m.joints.curve_group) cg = g;
  for (auto& b : m.joints.broken) b = 1;
  solver::Solver s(m);
  s.set_settings({Vec2::Zero(), 0.0, 0.0, 1e-6, true});
  solver::WaterSetup w = level(-100.0);  // the pool far below: only the crack's water acts
  w.pore_pressure_in_matrix = false;
  w.crack_levels = {{g, 1.0}};
  s.set_water(w);
  s.initialise();
  auto net_on_first_triangle = [&] {
    Vec2 f = Vec2::Zero();
    for (Index i : m.triangles.conn[0]) f += m.nodes.m[i] * m.nodes.a[i];
    return f.norm();
  };
  EXPECT_GT(net_on_first_triangle(), 0.0);
  for (Index i : m.triangles.conn[0]) m.nodes.u[i] += Vec2(0.0, 0.5);  // far beyond its joints' 1 cm
  s.initialise();
  EXPECT_EQ(net_on_first_triangle(), 0.0);
}
