// The joint phase on a model built by joint insertion: forces into a per-node array, breaking
// with time, position and mode, energy bookkeeping.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "joint/joint_phase.hpp"
#include "joint/joint_test_props.hpp"
#include "mesh/joint_insertion.hpp"

using namespace dsdem;

namespace {

// Two breakable triangles of the unit square (diagonal (0,0)-(1,1)) far from the
// origin, one joint on the diagonal.
struct TwoTriangles {
  Nodes nodes;
  std::vector<Vec2> f;  // joint forces per node
  Joints joints;
  std::vector<Index> b_nodes;  // nodes of tri_b
};

TwoTriangles make_two_triangles() {
  RawMesh m;
  const Vec2 o(1000.0, 500.0);
  m.nodes = {o + Vec2(0, 0), o + Vec2(1, 0), o + Vec2(1, 1), o + Vec2(0, 1)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.triangle_surface_group = {0, 0};
  RawPhysicalGroup g;
  g.name = "slide";
  g.triangles = {0, 1};
  m.groups = {g};
  JointInsertionOptions opt;
  opt.breakable = {true};
  JointInsertionResult r = insert_joints(m, opt);
  TwoTriangles out;
  out.nodes.resize(r.nodes.size());
  out.nodes.X = r.nodes;
  out.nodes.origin = r.origin;
  out.f.assign(r.nodes.size(), Vec2::Zero());
  out.joints = r.joints;
  const auto& cb = r.triangles[r.joints.tri_b[0]];
  out.b_nodes.assign(cb.begin(), cb.end());
  return out;
}

}  // namespace

TEST(JointPhase, PullApartBreaksOnceWithTimePositionModeAndEnergy) {
  const std::vector<JointProperties> props{test::disc_rock()};
  const JointProperties& p = props[0];
  TwoTriangles m = make_two_triangles();
  ASSERT_EQ(m.joints.size(), 1u);
  const double L = std::sqrt(2.0);
  EXPECT_NEAR(m.joints.length0[0], L, 1e-15);
  // Joint normal: outward of tri_a = triangle 0 (below the diagonal) -> (-1, 1)/sqrt2.
  const Vec2 n = Vec2(-1.0, 1.0) / L;
  const double wt = p.ft / p.kn, wn = 2 * p.GI / p.ft, dt = 1e-4;
  // Openings through the kinks of the law (wt, wt + wn), so the trapezoid is exact.
  std::vector<double> path;
  for (int i = 1; i <= 10; ++i) path.push_back(wt * i / 10);
  for (int i = 1; i <= 400; ++i) path.push_back(wt + wn * i / 400);
  for (int i = 1; i <= 10; ++i) path.push_back(wt + wn + wn * i / 10);
  double work = 0.0, f_old = 0.0, d_old = 0.0, dissipated = 0.0;
  int broke_at = -1;
  for (int i = 1; i <= int(path.size()); ++i) {
    const double d = path[i - 1];
    for (Index k : m.b_nodes) m.nodes.u[k] = d * n;
    std::fill(m.f.begin(), m.f.end(), Vec2::Zero());
    const JointPhaseTotals tot = add_joint_forces(m.nodes, m.f, m.joints, props, i * dt);
    dissipated += tot.dissipation;
    // Force on face b, pulling it back; forces sum to zero over the pair.
    Vec2 fb = Vec2::Zero(), fsum = Vec2::Zero();
    for (Index k : m.b_nodes) fb += m.f[k];
    for (const Vec2& f : m.f) fsum += f;
    EXPECT_EQ(fsum.norm(), 0.0);
    const double expected = d < wt ? p.kn * d : (d < wt + wn ? p.ft * (1 - (d - wt) / wn) : 0.0);
    if (!m.joints.broken[0] || tot.broken_now) {
      const double got = tot.broken_now ? 0.0 : -fb.dot(n) / L;
      EXPECT_NEAR(got, expected, 1e-9 * p.ft) << "d = " << d;
    } else {
      EXPECT_EQ(fb.norm(), 0.0);  // broken: contact takes over, the joint is silent
    }
    const double f = -fb.dot(n);
    work += 0.5 * (f + f_old) * (d - d_old);
    f_old = f;
    d_old = d;
    if (tot.broken_now) {
      EXPECT_EQ(broke_at, -1);
      broke_at = i;
    }
  }
  ASSERT_GT(broke_at, 0);
  EXPECT_TRUE(broke_at == 410 || broke_at == 411) << broke_at;  // path[409] = wt + wn
  EXPECT_EQ(m.joints.broken[0], 1);  // recorded, not left pending
  ASSERT_EQ(m.joints.breaks.size(), 1u);
  EXPECT_EQ(m.joints.breaks[0].joint, 0);
  EXPECT_EQ(m.joints.breaks[0].time, broke_at * dt);
  EXPECT_EQ(m.joints.break_mode(0), BreakMode::Tension);
  EXPECT_EQ(m.joints.damage(0), 1.0);
  // Mid-point of the opened joint: the diagonal's centre moved by half the opening.
  const double d_break = path[broke_at - 1];
  const Vec2 mid = Vec2(1000.5, 500.5) + 0.5 * d_break * n;
  EXPECT_NEAR((m.joints.breaks[0].position - mid).norm(), 0.0, 1e-12);
  // Everything the pull did went into fracture: L (GI + ft^2 / 2kn).
  const double exact = L * (p.GI + p.ft * p.ft / (2 * p.kn));
  EXPECT_NEAR(work, exact, 1e-9 * exact);
  EXPECT_NEAR(dissipated, exact, 1e-9 * exact);
}

TEST(JointPhase, GravityStageFreezesDamageAndNeverBreaks) {
  const std::vector<JointProperties> props{test::disc_rock()};
  const JointProperties& p = props[0];
  TwoTriangles m = make_two_triangles();
  const Vec2 n = Vec2(-1.0, 1.0) / std::sqrt(2.0);
  const double d = 5 * (p.ft / p.kn + 2 * p.GI / p.ft);  // far past failure
  for (Index k : m.b_nodes) m.nodes.u[k] = d * n;
  const JointPhaseTotals tot = add_joint_forces(m.nodes, m.f, m.joints, props, 0.0, false);
  EXPECT_EQ(tot.broken_now, 0);
  EXPECT_FALSE(m.joints.broken[0]);
  EXPECT_EQ(m.joints.damage(0), 0.0);
  Vec2 fb = Vec2::Zero();
  for (Index k : m.b_nodes) fb += m.f[k];
  EXPECT_NEAR(-fb.dot(n), p.kn * d * std::sqrt(2.0), 1e-9 * p.kn * d);  // elastic
  EXPECT_NEAR(tot.energy, 0.5 * p.kn * d * d * std::sqrt(2.0), 1e-9 * p.kn * d * d);
}

TEST(JointPhase, JointsWithAnInitiallyBrokenPropertyStartBrokenAndCarryNothing) {
  std::vector<JointProperties> props{test::disc_rock(), test::disc_rock()};
  props[1].name = "pre_existing_crack";
  props[1].initially_broken = true;
  TwoTriangles m = make_two_triangles();
  m.joints.property[0] = 1;
  mark_initially_broken(m.joints, props, m.nodes.X);
  EXPECT_TRUE(m.joints.broken[0]);
  EXPECT_EQ(m.joints.break_mode(0), BreakMode::Initial);
  ASSERT_EQ(m.joints.breaks.size(), 1u);
  EXPECT_EQ(m.joints.breaks[0].time, 0.0);
  EXPECT_EQ(m.joints.damage(0), 1.0);
  EXPECT_EQ(m.joints.breaks[0].position, Vec2(1000.5, 500.5));  // centre of the diagonal
  // Even pressed into each other, a broken joint adds nothing (contact's job).
  for (Index k : m.b_nodes) m.nodes.u[k] = Vec2(1e-6, -1e-6);
  const JointPhaseTotals tot = add_joint_forces(m.nodes, m.f, m.joints, props, 1.0);
  for (const Vec2& f : m.f) EXPECT_EQ(f.norm(), 0.0);
  EXPECT_EQ(tot.energy, 0.0);
  EXPECT_EQ(tot.broken_now, 0);
}

// docs/theory.md §3: a penalty joint's stiffness follows its local element size. A joint with
// stiffness_scale s behaves as one whose property has kn, ks times s: s times the force
// at the same small opening, and the same strength ft (reached at an opening 1/s).
TEST(JointPhase, StiffnessScaleMultipliesPenaltyStiffnessButNotStrength) {
  JointProperties p = test::disc_rock();
  p.penalty_h = 5e-3;
  for (bool ks_given : {false, true}) {
    p.ks_given = ks_given;
    const JointLawConstants k = law_constants(p), k2 = scaled(k, 2.5);
    JointProperties p2 = p;
    p2.kn *= 2.5;
    if (!ks_given) p2.ks *= 2.5;
    const JointLawConstants ref = law_constants(p2);
    EXPECT_EQ(k2.kn, ref.kn);
    EXPECT_EQ(k2.ks, ref.ks);
    EXPECT_EQ(k2.ft, k.ft);
    EXPECT_EQ(k2.wn, k.wn);
    EXPECT_EQ(joint_end_stiffness(p, 2.0, 2.5), std::max(p2.kn, p2.ks));
  }
  p.ks_given = false;
  const std::vector<JointProperties> props{p};
  const Vec2 n = Vec2(-1.0, 1.0) / std::sqrt(2.0);
  const double opening = 0.5 * p.ft / p.kn / 2.5;  // elastic for both scales
  std::array<double, 2> force{};
  for (int run = 0; run < 2; ++run) {
    TwoTriangles m = make_two_triangles();
    m.joints.stiffness_scale[0] = run == 0 ? 1.0 : 2.5;
    for (Index b : m.b_nodes) m.nodes.u[b] = opening * n;
    m.f.assign(m.nodes.size(), Vec2::Zero());
    add_joint_forces(m.nodes, m.f, m.joints, props, 0.0);
    force[run] = m.f[m.b_nodes[0]].norm() + m.f[m.b_nodes[1]].norm() + m.f[m.b_nodes[2]].norm();
  }
  EXPECT_GT(force[0], 0.0);
  EXPECT_NEAR(force[1] / force[0], 2.5, 1e-12);
  // Strength: pulled past the scaled wt the traction is ft (times the length), not more.
  TwoTriangles m = make_two_triangles();
  m.joints.stiffness_scale[0] = 2.5;
  for (Index b : m.b_nodes) m.nodes.u[b] = (p.ft / p.kn / 2.5) * n;
  m.f.assign(m.nodes.size(), Vec2::Zero());
  add_joint_forces(m.nodes, m.f, m.joints, props, 0.0);
  EXPECT_NEAR(last_tractions(m.joints.state[0][0], scaled(law_constants(p), 2.5)).sn, p.ft, 1e-9 * p.ft);
}

// evaluate_joints on block ranges (the solver hands each thread a tuned range of blocks):
// the ranges done in any order and split anywhere give the forces, block sums, histories
// and breaks of one call on all blocks, bit for bit.
TEST(JointPhase, BlockRangesInAnyOrderEqualOneCallOnAllBlocks) {
  // A strip of 40 x 3 unit squares, two breakable triangles each: about 400 joints, 7 blocks.
  RawMesh mesh;
  const int nx = 40, ny = 3;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) mesh.nodes.push_back(Vec2(i, j));
  auto id = [&](int i, int j) { return static_cast<Index>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  mesh.triangle_surface_group.assign(mesh.triangles.size(), 0);
  RawPhysicalGroup g;
  g.name = "slide";
  for (Index t = 0; t < static_cast<Index>(mesh.triangles.size()); ++t) g.triangles.push_back(t);
  mesh.groups = {g};
  JointInsertionOptions opt;
  opt.breakable = {true};
  const JointInsertionResult r = insert_joints(mesh, opt);
  const std::vector<JointProperties> props{test::disc_rock()};
  const JointProperties& p = props[0];
  const std::size_t nb = joint_blocks(r.joints.size());
  ASSERT_GE(nb, 5u);

  struct Run {
    Nodes nodes;
    Joints joints;
    JointPhaseBuffers buf;
    Index broken = 0;
  };
  auto make = [&] {
    Run run;
    run.nodes.resize(r.nodes.size());
    run.nodes.X = r.nodes;
    run.nodes.origin = r.origin;
    run.joints = r.joints;
    run.buf.prepare(run.joints, props);
    return run;
  };
  // Node motions that leave some joints elastic, soften others and break a few.
  const double wt = p.ft / p.kn, wn = 2 * p.GI / p.ft;
  auto displace = [&](Run& run, int step) {
    for (std::size_t i = 0; i < run.nodes.size(); ++i) {
      const double s = std::sin(0.37 * static_cast<double>(i) + 0.9 * step);
      const double scale = i % 11 == 0 ? 3.0 * (wt + wn) : (i % 7 == 0 ? wt + 0.3 * wn : 0.4 * wt);
      run.nodes.u[i] = scale * step / 4.0 * Vec2(s, std::cos(1.3 * static_cast<double>(i)));
    }
  };
  Run whole = make();
  std::vector<Run> split;
  const std::vector<std::size_t> cuts{0, 1, nb / 2, nb - 1, nb};
  for (std::size_t k = 0; k < cuts.size(); ++k) split.push_back(make());
  for (int step = 1; step <= 4; ++step) {
    displace(whole, step);
    evaluate_joints(whole.nodes, whole.joints, true, 1.0, whole.buf, whole.broken, 0, nb);
    for (std::size_t k = 0; k < cuts.size(); ++k) {
      Run& run = split[k];
      displace(run, step);
      // The second range first, and a range past the end (clipped).
      evaluate_joints(run.nodes, run.joints, true, 1.0, run.buf, run.broken, cuts[k], nb + 3);
      evaluate_joints(run.nodes, run.joints, true, 1.0, run.buf, run.broken, 0, cuts[k]);
      ASSERT_EQ(run.broken, whole.broken) << "cut " << cuts[k] << ", step " << step;
      ASSERT_EQ(std::memcmp(run.buf.force.data(), whole.buf.force.data(), whole.buf.force.size() * sizeof(whole.buf.force[0])), 0);
      ASSERT_EQ(std::memcmp(run.buf.block_energy.data(), whole.buf.block_energy.data(), nb * sizeof(double)), 0);
      ASSERT_EQ(std::memcmp(run.buf.block_dissipation.data(), whole.buf.block_dissipation.data(), nb * sizeof(double)), 0);
      ASSERT_EQ(std::memcmp(run.joints.state.data(), whole.joints.state.data(), whole.joints.state.size() * sizeof(whole.joints.state[0])), 0);
      ASSERT_EQ(run.joints.broken, whole.joints.broken);
    }
  }
  // The motions did what they were meant to: elastic, softening and broken joints.
  std::size_t elastic = 0, softening = 0;
  for (std::size_t j = 0; j < whole.joints.size(); ++j) {
    const double d = whole.joints.damage(j);
    elastic += d == 0.0;
    softening += d > 0.0 && d < 1.0;
  }
  EXPECT_GT(elastic, 10u);
  EXPECT_GT(softening, 3u);
  EXPECT_GT(whole.broken, 0);
}
