// The memory savings change no result: stress computed on demand equals the
// stress of every step (in the model and in the checkpoint), and a run whose damping stops (buffers freed) and restarts from
// a checkpoint taken just after the switch continues bit-identically, energies included.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <random>
#include <unistd.h>

#include "common/block_on_ground.hpp"
#include "joint/joint_phase.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

Model impact_model() { return test::impact_block(16, 8); }

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

// Own triangles (discrete block) add their element and joint forces to their nodes
// themselves and shared ones (the continuous ground) go through buffers and incidence
// lists (memory): every node's force must still be the per-node gather
// m g + ((sum of element forces + sum of damping forces) + joint forces in joint order),
// bit for bit, with stiffness damping, a broken joint, and on 1 and 2 threads.
TEST(ForceGather, OwnAndSharedTrianglesGiveThePerNodeGatherBitForBit) {
  for (bool parallel : {false, true}) {
    Model model = impact_model();
    model.contact.enabled = false;  // no contact forces at this state: the sums above only
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> d(-1e-6, 1e-6);
    for (std::size_t i = 0; i < model.nodes.size(); ++i) {
      model.nodes.u[i] += Vec2(d(rng), d(rng));
      model.nodes.v[i] += Vec2(1e3 * d(rng), 1e3 * d(rng));
    }
    model.joints.set_initially_broken(5, model.nodes.X[model.joints.nodes[5][0]], model.nodes.X[model.joints.nodes[5][1]]);
    Model ref = model;
    const Vec2 g(0.0, -9.81);
    const double beta = 1e-6;
    solver::Solver s(model);
    s.set_parallel(parallel);
    s.set_settings({g, 0.0, beta, 1e-7, true});
    s.initialise();

    // The reference: element forces by incidence in triangle order, joint forces
    // scattered in joint order into zeros (add_joint_forces), per node.
    const std::size_t nn = ref.nodes.size();
    std::vector<Vec2> f(nn, Vec2::Zero()), fd(nn, Vec2::Zero()), fj(nn, Vec2::Zero());
    for (std::size_t t = 0; t < ref.triangles.size(); ++t) {
      fem::TriangleInput in = s.triangle_input(t);
      for (int k = 0; k < 3; ++k) in.v[k] = ref.nodes.v[ref.triangles.conn[t][k]];
      in.beta = beta;
      const Material& m = ref.materials[ref.triangles.material[t]];
      fem::TriangleResponse r;
      std::array<Vec2, 3> damping;
      fem::triangle_internal_force(in, {m.lambda(), m.mu()}, r, damping);
      for (int k = 0; k < 3; ++k) {
        f[ref.triangles.conn[t][k]] += r.force[k];
        fd[ref.triangles.conn[t][k]] += damping[k];
      }
    }
    add_joint_forces(ref.nodes, fj, ref.joints, ref.joint_properties, 0.0, true, ref.thickness);
    std::size_t moving = 0;
    for (std::size_t i = 0; i < nn; ++i) {
      const Vec2 sum = ref.nodes.m[i] * g + (f[i] + fd[i] + fj[i]);
      const Vec2 a = ref.nodes.m[i] > 0.0 ? Vec2(sum / ref.nodes.m[i]) : Vec2(Vec2::Zero());
      ASSERT_TRUE(std::memcmp(a.data(), model.nodes.a[i].data(), sizeof(Vec2)) == 0)
          << "node " << i << (parallel ? " (2 threads)" : " (1 thread)");
      moving += fj[i].norm() > 0.0 && fd[i].norm() > 0.0;
    }
    EXPECT_GT(moving, nn / 2);  // joint and damping forces really were in the sums
    EXPECT_TRUE(model.joints.broken[5]);
  }
}
