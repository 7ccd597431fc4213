// The memory savings of issue 7 change no result: stress computed on demand equals the
// stress of every step (in the model and in the checkpoint), and a run whose damping stops (buffers freed) and restarts from
// a checkpoint taken just after the switch continues bit-identically, energies included.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <unistd.h>

#include "common/block_on_ground.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

Model impact_model() {
  test::BlockOnGround b;
  b.nx = 16;
  b.ny = 8;
  return test::block_on_ground(b);
}

void setup(solver::Solver& s, const Model& model, double alpha, double beta) {
  io::BoundarySpec fixed;
  fixed.group = "ground";
  fixed.type = io::BoundaryType::Fixed;
  s.set_constraints(solver::build_constraints(model, {fixed}, 0.0));
  s.set_settings({Vec2(0.0, -9.81), alpha, beta, 0.3 * solver::stable_time_step(model, 1e-7).dt, true});
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST(StressOnDemand, EqualsTheStressOfEveryStep) {
  Model a = impact_model(), b = impact_model();
  solver::Solver sa(a), sb(b);
  sb.set_stress_on_demand(true);
  setup(sa, a, 50.0, 1e-7);
  setup(sb, b, 50.0, 1e-7);
  sa.initialise();
  sb.initialise();
  for (int k = 0; k < 300; ++k) {
    sa.step();
    sb.step();
  }
  ASSERT_EQ(a.triangles.stress.size(), a.triangles.size());  // written by every step
  EXPECT_TRUE(b.triangles.stress.empty());  // on demand: no arrays held between outputs
  EXPECT_TRUE(b.triangles.strain.empty());
  sb.update_stress();
  EXPECT_TRUE(same_bits(a.triangles.stress, b.triangles.stress));
  EXPECT_TRUE(same_bits(a.triangles.strain, b.triangles.strain));
  EXPECT_TRUE(same_bits(a.nodes.u, b.nodes.u));
  EXPECT_TRUE(same_bits(a.nodes.v, b.nodes.v));
  sb.release_stress();
  EXPECT_TRUE(b.triangles.stress.empty());
  EXPECT_TRUE(b.triangles.strain.empty());
  sa.release_stress();  // not on demand: the steps keep writing them
  EXPECT_EQ(a.triangles.stress.size(), a.triangles.size());
}

// The checkpoint holds the current stress and strain whether the steps write them or
// not (Solver::save computes them on demand), and a restore into an on-demand solver
// keeps no arrays.
TEST(StressOnDemand, CheckpointHoldsTheSameStressAsASolverThatWritesItEveryStep) {
  const auto dir = std::filesystem::temp_directory_path();
  const auto pa = dir / ("dsdem_stress_a_" + std::to_string(::getpid()) + ".h5");
  const auto pb = dir / ("dsdem_stress_b_" + std::to_string(::getpid()) + ".h5");
  Model a = impact_model(), b = impact_model();
  solver::Solver sa(a), sb(b);
  sb.set_stress_on_demand(true);
  setup(sa, a, 0.0, 0.0);
  setup(sb, b, 0.0, 0.0);
  sa.initialise();
  sb.initialise();
  for (int k = 0; k < 300; ++k) {
    sa.step();
    sb.step();
  }
  for (const auto& [s, p] : {std::pair{&sa, pa}, std::pair{&sb, pb}}) {
    io::CheckpointWriter w(p);
    s->save(w);
    w.commit();
  }
  const io::CheckpointReader ra(pa), rb(pb);
  for (const char* name : {"triangles/stress", "triangles/strain"}) {
    const std::vector<double> va = ra.doubles(name), vb = rb.doubles(name);
    ASSERT_EQ(va.size(), 3 * a.triangles.size()) << name;
    EXPECT_TRUE(same_bits(va, vb)) << name;
  }
  EXPECT_TRUE(b.triangles.stress.empty());
  Model c = impact_model();
  solver::Solver sc(c);
  sc.set_stress_on_demand(true);
  setup(sc, c, 0.0, 0.0);
  sc.initialise();
  sc.restore(rb);
  EXPECT_TRUE(c.triangles.stress.empty());
  sc.update_stress();
  EXPECT_TRUE(same_bits(a.triangles.stress, c.triangles.stress));
  EXPECT_TRUE(same_bits(a.triangles.strain, c.triangles.strain));
  std::filesystem::remove(pa);
  std::filesystem::remove(pb);
}

TEST(DampingBuffers, DampingSwitchedOffThenRestartedFromACheckpointKeepsTheBits) {
  // Damped stage, then undamped (the buffers go after the first undamped step); a
  // checkpoint right at the switch holds non-zero previous damping forces, which the
  // restored solver must bring back for the next step's damping work.
  const auto path = std::filesystem::temp_directory_path() / ("dsdem_damp_" + std::to_string(::getpid()) + ".h5");
  Model a = impact_model();
  solver::Solver sa(a);
  setup(sa, a, 50.0, 1e-7);
  sa.initialise();
  for (int k = 0; k < 200; ++k) sa.step();
  const solver::StepSettings undamped{Vec2(0.0, -9.81), 0.0, 0.0, sa.settings().dt, true};
  sa.set_settings(undamped);
  {
    io::CheckpointWriter w(path);
    sa.save(w);
    w.commit();
  }
  for (int k = 0; k < 200; ++k) sa.step();
  const double damped_work = sa.energy().damping_dissipated;
  sa.step();
  EXPECT_TRUE(same_bits(damped_work, sa.energy().damping_dissipated));  // undamped: no more damping work

  Model b = impact_model();
  solver::Solver sb(b);
  setup(sb, b, 50.0, 1e-7);
  sb.initialise();
  sb.set_settings(undamped);
  sb.restore(io::CheckpointReader(path));
  for (int k = 0; k < 201; ++k) sb.step();
  EXPECT_TRUE(same_bits(a.nodes.u, b.nodes.u));
  EXPECT_TRUE(same_bits(a.nodes.v, b.nodes.v));
  EXPECT_TRUE(same_bits(sa.energy().damping_dissipated, sb.energy().damping_dissipated));
  EXPECT_TRUE(same_bits(sa.energy().external_work, sb.energy().external_work));
  EXPECT_GT(sa.energy().damping_dissipated, 0.0);
  std::filesystem::remove(path);
}
