// Law state arrays (law/registry.hpp, Triangles::state): sized by the model builder from
// the laws in use, restored bit for bit from a checkpoint, and absent (in memory and in
// the file) for a purely elastic model.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include <unistd.h>

#include "law/laws.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

// A continuous ground (rock) under a continuous layer of `layer_law`.
Model two_layers(const std::string& layer_law) {
  RawMesh raw = mesh::rectangle_mesh(6, 2, 0.6, 0.2, mesh::Diagonal::Alternate, 0.0, -0.2, "ground");
  for (auto& g : raw.groups)
    if (g.dim == 1) g.name = "ground_" + g.name;
  io::Scenario sc;
  sc.file = "(test)";
  Material rock;
  rock.name = "rock";
  rock.E = 1e9;
  rock.nu = 0.25;
  rock.rho = 2500;
  Material soil = rock;
  soil.name = "soil";
  soil.model = layer_law;
  soil.E = 5e7;
  soil.rho = 1800;
  if (layer_law == "mohr_coulomb") {  // the parameters the scenario reader would give it
    namespace mc = law::mohr_coulomb;
    soil.params.assign(mc::kParams, 0.0);
    soil.params[mc::E] = soil.E;
    soil.params[mc::nu] = soil.nu;
    soil.params[mc::rho] = soil.rho;
    soil.params[mc::cohesion] = 1e4;
    soil.params[mc::friction_angle] = 30.0;
    soil.params[mc::tensile_strength] = std::numeric_limits<double>::infinity();
  }
  sc.materials = {{"rock", rock}, {"soil", soil}};
  mesh::append_mesh(raw, mesh::rectangle_mesh(6, 2, 0.6, 0.2, mesh::Diagonal::Alternate, 0.0, 0.0, "layer"));
  sc.regions = {io::RegionSpec{"ground", "rock", Zone::Bedrock, {}, {}},
                io::RegionSpec{"layer", "soil", Zone::Bedrock, {}, {}}};
  sc.stages.push_back(io::StageSpec{});
  return mesh::build_model(sc, raw);
}

void setup(solver::Solver& s, const Model& model, double dt) {
  io::BoundarySpec fixed;
  fixed.group = "ground_bottom";
  fixed.type = io::BoundaryType::Fixed;
  s.set_constraints(solver::build_constraints(model, {fixed}, 0.0));
  s.set_settings({Vec2(0, -9.81), 0.0, 0.0, dt, true});
}

std::filesystem::path temp_file(const std::string& stem) {
  return std::filesystem::temp_directory_path() / (stem + "_" + std::to_string(::getpid()) + ".h5");
}

// Values of every kind a state variable may hold, so that a lossy copy shows.
double awkward(std::size_t k, std::size_t t) {
  switch ((k + t) % 5) {
    case 0: return -0.0;
    case 1: return std::numeric_limits<double>::denorm_min() * static_cast<double>(t + 1);
    case 2: return 1.0 / 3.0 + static_cast<double>(k);
    case 3: return -std::sqrt(2.0) * 1e-9 * static_cast<double>(t);
    default: return std::numeric_limits<double>::infinity();
  }
}

}  // namespace

TEST(LawState, BuilderSizesTheDeclaredArrays) {
  const Model m = two_layers("mohr_coulomb");
  const auto& decl = law::material_laws().get("mohr_coulomb");
  const StateArrays& s = m.triangles.state;
  ASSERT_EQ(s.columns(), decl.state.size());
  for (std::size_t k = 0; k < decl.state.size(); ++k) {
    EXPECT_EQ(s.names[k], decl.state[k].name);
    EXPECT_EQ(s.units[k], decl.state[k].unit);
    ASSERT_EQ(s.values[k].size(), m.triangles.size());
    for (double v : s.values[k]) EXPECT_EQ(std::bit_cast<std::uint64_t>(v), 0u);  // +0
  }
  // The material's columns in declaration order; the elastic one has none.
  for (const Material& mat : m.materials) {
    if (mat.name == "soil") {
      EXPECT_EQ(mat.law, law::material_laws().index("mohr_coulomb"));
      ASSERT_EQ(mat.state_columns.size(), decl.state.size());
      for (std::size_t k = 0; k < decl.state.size(); ++k)
        EXPECT_EQ(s.names[static_cast<std::size_t>(mat.state_columns[k])], decl.state[k].name);
    } else {
      EXPECT_EQ(mat.law, 0);
      EXPECT_TRUE(mat.state_columns.empty());
    }
  }
}

TEST(LawState, ElasticModelHoldsAndWritesNoState) {
  Model m = two_layers("linear_elastic");
  EXPECT_TRUE(m.triangles.state.empty());
  EXPECT_TRUE(m.triangles.state.values.empty());
  solver::Solver s(m);
  setup(s, m, 0.3 * solver::stable_time_step(m, 0.0).dt);
  s.initialise();
  const auto path = temp_file("dsdem_law_state_elastic");
  {
    io::CheckpointWriter w(path);
    s.save(w);
    w.commit();
  }
  const io::CheckpointReader r(path);
  EXPECT_FALSE(r.has("triangles/state/count"));
  EXPECT_FALSE(r.has("triangles/state/plastic_strain_xx"));
  EXPECT_TRUE(r.has("triangles/stress0"));
  std::filesystem::remove(path);
}

TEST(LawState, CheckpointRestoresStateBitForBit) {
  Model a = two_layers("mohr_coulomb");
  solver::Solver sa(a);
  const double dt = 0.3 * solver::stable_time_step(a, 0.0).dt;
  setup(sa, a, dt);
  sa.initialise();
  for (int i = 0; i < 50; ++i) sa.step();
  StateArrays& st = a.triangles.state;
  const std::vector<std::vector<double>> reached = st.values;  // the run's own state
  for (std::size_t k = 0; k < st.columns(); ++k)
    for (std::size_t t = 0; t < a.triangles.size(); ++t) st.values[k][t] = awkward(k, t);
  const auto path = temp_file("dsdem_law_state");
  {
    io::CheckpointWriter w(path);
    sa.save(w);
    w.commit();
  }
  Model b = two_layers("mohr_coulomb");
  solver::Solver sb(b);
  setup(sb, b, dt);
  sb.initialise();
  const double* before = b.triangles.state.values[0].data();
  sb.restore(io::CheckpointReader(path));
  EXPECT_EQ(b.triangles.state.values[0].data(), before) << "restored in place";
  ASSERT_EQ(b.triangles.state.names, st.names);
  for (std::size_t k = 0; k < st.columns(); ++k)
    ASSERT_EQ(std::memcmp(st.values[k].data(), b.triangles.state.values[k].data(), st.values[k].size() * sizeof(double)), 0)
        << st.names[k];
  // The same run continues identically from there (from the run's own state: the awkward
  // values above, read as plastic strains, would not make a run).
  for (auto* m : {&a, &b})
    for (std::size_t k = 0; k < st.columns(); ++k)
      std::copy(reached[k].begin(), reached[k].end(), m->triangles.state.values[k].begin());
  for (int i = 0; i < 50; ++i) {
    sa.step();
    sb.step();
  }
  for (std::size_t n = 0; n < a.nodes.size(); ++n) ASSERT_EQ(a.nodes.u[n], b.nodes.u[n]) << "node " << n;

  // A model whose laws declare no state refuses the file, and the other way round.
  Model e = two_layers("linear_elastic");
  solver::Solver se(e);
  setup(se, e, dt);
  se.initialise();
  try {
    se.restore(io::CheckpointReader(path));
    FAIL() << "a checkpoint with law state was restored into an elastic model";
  } catch (const std::runtime_error& err) {
    EXPECT_NE(std::string(err.what()).find("law state"), std::string::npos) << err.what();
  }
  const auto elastic_path = temp_file("dsdem_law_state_e");
  {
    io::CheckpointWriter w(elastic_path);
    se.save(w);
    w.commit();
  }
  Model c = two_layers("mohr_coulomb");
  solver::Solver sc(c);
  setup(sc, c, dt);
  sc.initialise();
  EXPECT_THROW(sc.restore(io::CheckpointReader(elastic_path)), std::runtime_error);
  std::filesystem::remove(path);
  std::filesystem::remove(elastic_path);
}

// Joints carry the state their laws declare the same way; the cohesive law declares none
// (its history is Joints::state), so a jointed model writes nothing new either.
TEST(LawState, JointsOfTheCohesiveLawHoldNoLawState) {
  io::Scenario sc;
  sc.file = "(test)";
  Material rock;
  rock.name = "rock";
  rock.E = 1e9;
  rock.nu = 0.25;
  rock.rho = 2500;
  sc.materials["rock"] = rock;
  sc.regions = {io::RegionSpec{"block", "rock", Zone::Discrete, {}, {}}};
  sc.joints.present = true;
  sc.joints.defaults.params.values["ft"] = 2e4;
  sc.joints.defaults.params.values["c"] = 5e4;
  sc.joints.defaults.params.values["phi"] = 30;
  sc.joints.defaults.params.values["GI"] = 1;
  sc.joints.defaults.params.values["GII"] = 5;
  sc.stages.push_back(io::StageSpec{});
  Model m = mesh::build_model(sc, mesh::rectangle_mesh(3, 3, 0.3, 0.3, mesh::Diagonal::Alternate, 0.0, 0.0, "block"));
  ASSERT_GT(m.joints.size(), 0u);
  EXPECT_TRUE(m.joints.law_state.empty());
  for (const auto& p : m.joint_properties) EXPECT_EQ(p.law, law::joint_laws().index("cohesive"));
  solver::Solver s(m);
  io::BoundarySpec fixed;
  fixed.group = "bottom";
  fixed.type = io::BoundaryType::Fixed;
  s.set_constraints(solver::build_constraints(m, {fixed}, 0.0));
  s.set_settings({Vec2(0, -9.81), 0.0, 0.0, 0.3 * solver::stable_time_step(m, 0.0).dt, true});
  s.initialise();
  const auto path = temp_file("dsdem_law_state_joints");
  {
    io::CheckpointWriter w(path);
    s.save(w);
    w.commit();
  }
  const io::CheckpointReader r(path);
  EXPECT_FALSE(r.has("joints/law_state/count"));
  EXPECT_TRUE(r.has("joints/state"));
  s.restore(r);
  std::filesystem::remove(path);
}
