// The Mohr-Coulomb bulk law in the time step (docs/theory.md §10): Prandtl's bearing capacity,
// the plastic work in the energy balance, and the same bits on 1 and 2 threads and across
// a checkpoint restart with plastic state.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <filesystem>
#include <numbers>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "common/same_bits.hpp"
#include "law/laws.hpp"
#include "law/registry.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}
using test::same_bits;

constexpr double kCohesion = 1e4;  // Pa
constexpr double kFooting = 1.0;   // half-width of the strip footing, m

// Half of a strip footing on weightless cohesive ground (phi = 0): [0, 5] x [-3, 0] m,
// cells of 0.25 m cut in four triangles (crossed diagonals: no volumetric locking under
// isochoric plastic flow), symmetry at x = 0, the footing's nodes on top for x <= 1 m.
Model footing_model(double friction_deg = 0.0, double dilation_deg = 0.0,
                    const law::LawDecl& law = law::mohr_coulomb_decl()) {
  RawMesh raw = mesh::rectangle_mesh(28, 16, 3.5, 2.0, mesh::Diagonal::Cross, 0.0, -2.0, "soil");
  RawPhysicalGroup footing;
  footing.name = "footing";
  footing.dim = 0;
  footing.tag = 10;
  for (Index i = 0; i < static_cast<Index>(raw.nodes.size()); ++i)
    if (std::abs(raw.nodes[i].y()) < 1e-9 && raw.nodes[i].x() <= kFooting + 1e-9) footing.nodes.push_back(i);
  raw.groups.push_back(footing);
  io::Scenario sc;
  sc.file = "(test)";
  Material m;
  m.name = "clay";
  m.model = law.name;
  m.E = 1e8;
  m.nu = 0.3;
  m.rho = 2000;
  // The declared defaults (no tension cut-off), then the values of the test.
  for (const auto& p : law.params)
    m.params.push_back(p.rule ? p.rule(law, m.params) : (p.required() || p.default_text.empty() ? 0.0 : std::stod(p.default_text)));
  const auto set = [&](std::string_view name, double value) { m.params[static_cast<std::size_t>(law.param_index(name))] = value; };
  set("E", m.E);
  set("nu", m.nu);
  set("rho", m.rho);
  set("cohesion", kCohesion);
  set("friction_angle", friction_deg);
  set("dilation_angle", dilation_deg);
  if (law.has_param("tensile_strength")) set("tensile_strength", std::numeric_limits<double>::infinity());
  sc.materials["clay"] = m;
  sc.regions = {io::RegionSpec{"soil", "clay", Zone::Bedrock, {}, {}}};
  sc.stages.push_back(io::StageSpec{});
  return mesh::build_model(sc, raw);
}

// Supports (rollers on the sides, the base fixed) and the footing pushed down at speed v,
// reached over the first `ramp` seconds.
std::vector<solver::PrescribedDof> footing_constraints(const Model& model, double v, double ramp) {
  io::BoundarySpec left{"left", io::BoundaryType::Roller, 0, {}, {}, {}, {}, true, {}};
  io::BoundarySpec right{"right", io::BoundaryType::Roller, 0, {}, {}, {}, {}, true, {}};
  io::BoundarySpec base{"bottom", io::BoundaryType::Fixed, 0, {}, {}, {}, {}, true, {}};
  io::BoundarySpec push{"footing", io::BoundaryType::Velocity, 0, {}, {}, {}, {}, true, {}};
  push.y = io::TimeHistory{{0.0, ramp}, {0.0, -v}};
  return solver::build_constraints(model, {left, right, base, push}, 0.0);
}

double footing_pressure(const solver::Solver& s, const Model& model) {
  const auto& nodes = model.groups[model.find_group("footing")].nodes;
  return -s.reaction_on(nodes).y() / kFooting;  // Pa: reaction per unit thickness over the half-width
}

}  // namespace

// Prandtl (1920): a smooth rigid strip footing on weightless ground of cohesion c and
// phi = 0 fails at q_u = (2 + pi) c, for each plastic law. The footing is pushed slowly (quasi-static: the
// loading takes ~100 times the wave's transit of the model); the pressure's peak and its
// plateau up to 9 mm of settlement are within 5 % of q_u. Further on the plateau falls slowly:
// St Venant-Kirchhoff softens at finite strain.
class PrandtlBearingCapacity : public ::testing::TestWithParam<const char*> {};

TEST_P(PrandtlBearingCapacity, OfAStripFootingWithinFivePercent) {
  Model model = footing_model(0.0, 0.0, law::material_laws().get(GetParam()));
  solver::Solver s(model);
  const double v = 0.01, ramp = 0.2;  // m/s, s
  s.set_constraints(footing_constraints(model, v, ramp));
  s.set_settings({Vec2::Zero(), 5.0, 0.0, 0.3 * solver::stable_time_step(model, 0.0).dt, true});
  s.initialise();
  const double q_u = (2.0 + std::numbers::pi) * kCohesion;
  double q_max = 0.0, q_end = 0.0;
  while (s.time() < 1.0) {  // 0.009 m of settlement, ~8 times the elastic one at q_u
    s.step();
    q_end = footing_pressure(s, model);
    q_max = std::max(q_max, q_end);
  }
  EXPECT_NEAR(q_end / q_u, 1.0, 0.05) << "q = " << q_end << " Pa, q_u = " << q_u << " Pa";
  EXPECT_LT(q_max / q_u, 1.05);
  EXPECT_GT(s.energy().plastic_dissipated, 0.0);
}

// Mohr-Coulomb, and Drucker-Prager at phi = 0: von Mises with k = c, Tresca's in plane strain.
INSTANTIATE_TEST_SUITE_P(Plasticity, PrandtlBearingCapacity, ::testing::Values("mohr_coulomb", "drucker_prager"),
                         [](const ::testing::TestParamInfo<const char*>& info) { return std::string(info.param); });

// Work put in by the footing = stored energy + plastic work + damping (docs/theory.md §7):
// the plastic work is booked in the ledger, and it only grows.
class PlasticWork : public ::testing::TestWithParam<const char*> {};

TEST_P(PlasticWork, IsBookedAndNeverDecreases) {
  Model model = footing_model(20.0, 5.0, law::material_laws().get(GetParam()));
  solver::Solver s(model);
  s.set_constraints(footing_constraints(model, 0.02, 0.2));
  s.set_settings({Vec2::Zero(), 5.0, 0.0, 0.3 * solver::stable_time_step(model, 0.0).dt, true});
  s.initialise();
  double previous = 0.0;
  while (s.time() < 1.5) {
    s.step();
    ASSERT_GE(s.energy().plastic_dissipated, previous);
    previous = s.energy().plastic_dissipated;
  }
  EXPECT_GT(s.energy().plastic_dissipated, 0.01 * s.energy().external_work);
  EXPECT_LT(s.energy().balance_error(), 5e-3);
}

INSTANTIATE_TEST_SUITE_P(Plasticity, PlasticWork, ::testing::Values("mohr_coulomb", "drucker_prager"),
                         [](const ::testing::TestParamInfo<const char*>& info) { return std::string(info.param); });

namespace {
struct PlasticRun {
  std::vector<Vec2> u, v;
  std::vector<std::vector<double>> state;
  double plastic = 0.0;
};
PlasticRun run_footing(int threads, long steps) {
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  Model model = footing_model(20.0, 5.0);
  solver::Solver s(model);
  s.set_parallel(threads > 1);
  s.set_constraints(footing_constraints(model, 0.05, 0.05));
  s.set_settings({Vec2::Zero(), 5.0, 1e-5, 0.3 * solver::stable_time_step(model, 1e-5).dt, true});
  s.initialise();
  for (long k = 0; k < steps; ++k) s.step();
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  return {model.nodes.u, model.nodes.v, model.triangles.state.values, s.energy().plastic_dissipated};
}
}  // namespace

TEST(Plasticity, OneAndTwoThreadsGiveBitIdenticalPlasticState) {
  const PlasticRun a = run_footing(1, 1500), b = run_footing(2, 1500);
  ASSERT_GT(a.plastic, 0.0);
  EXPECT_TRUE(same_bits(a.u, b.u));
  EXPECT_TRUE(same_bits(a.v, b.v));
  ASSERT_EQ(a.state.size(), b.state.size());
  for (std::size_t k = 0; k < a.state.size(); ++k) EXPECT_TRUE(same_bits(a.state[k], b.state[k])) << k;
  EXPECT_TRUE(test::same_bits(a.plastic, b.plastic));
}

TEST(Plasticity, CheckpointRestartContinuesBitIdenticallyWithPlasticState) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "dsdem_plastic_checkpoint.h5";
  Model a = footing_model(20.0, 5.0), b = footing_model(20.0, 5.0);
  solver::Solver sa(a), sb(b);
  for (auto* s : {&sa, &sb}) {
    s->set_constraints(footing_constraints(s == &sa ? a : b, 0.05, 0.05));
    s->set_settings({Vec2::Zero(), 5.0, 0.0, 0.3 * solver::stable_time_step(a, 0.0).dt, true});
    s->initialise();
  }
  for (int k = 0; k < 800; ++k) sa.step();
  ASSERT_GT(sa.energy().plastic_dissipated, 0.0);
  {
    io::CheckpointWriter w(path.string());
    sa.save(w);
    w.commit();
  }
  sb.restore(io::CheckpointReader(path.string()));
  std::filesystem::remove(path);
  for (int k = 0; k < 400; ++k) {
    sa.step();
    sb.step();
  }
  EXPECT_TRUE(same_bits(a.nodes.u, b.nodes.u));
  EXPECT_TRUE(same_bits(a.nodes.v, b.nodes.v));
  for (std::size_t k = 0; k < a.triangles.state.values.size(); ++k)
    EXPECT_TRUE(same_bits(a.triangles.state.values[k], b.triangles.state.values[k])) << k;
  EXPECT_TRUE(test::same_bits(sa.energy().plastic_dissipated, sb.energy().plastic_dissipated));
  EXPECT_TRUE(test::same_bits(sa.energy().balance_error(), sb.energy().balance_error()));
}

// The solver reads the law's state columns in the kernel's order (MohrCoulombState): the
// registry's declaration and the kernel's table name the same variables in that order.
TEST(Plasticity, RegistryDeclaresTheKernelsStateInItsOrder) {
  const law::LawDecl& decl = law::material_laws().get("mohr_coulomb");
  ASSERT_EQ(decl.state.size(), fem::kMohrCoulombStateVariables.size());
  ASSERT_EQ(decl.state.size(), static_cast<std::size_t>(law::mohr_coulomb::kStates));
  for (std::size_t k = 0; k < decl.state.size(); ++k) {
    EXPECT_EQ(decl.state[k].name, fem::kMohrCoulombStateVariables[k].name) << k;
    EXPECT_EQ(decl.state[k].unit, fem::kMohrCoulombStateVariables[k].unit) << k;
  }
}
