// The 3D continuum (solver/continuum3d): the patch test, rigid rotations, energy, a column
// settling under its weight, Mohr-Coulomb in compression, a cantilever's first frequency,
// the same bits for one and two threads, local damping and checkpoints.
#include <gtest/gtest.h>
#include <omp.h>
#include <unistd.h>

#include <filesystem>

#include <cmath>
#include <cstdio>

#include "boundary/boundary_setup3d.hpp"
#include "common/remove_at_exit.hpp"
#include "io/checkpoint.hpp"
#include "common/materials.hpp"
#include "mesh/model_builder3d.hpp"
#include "mesh/structured.hpp"
#include "seismic/accelerogram.hpp"
#include "solver/continuum3d.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

Material rock3(double E = 1e9, double nu = 0.25, double rho = 2500.0) {
  return test::elastic_material("rock", E, nu, rho);
}

std::vector<solver::PrescribedDof> fixed(const Model3& m, const std::string& group, std::initializer_list<int> dirs) {
  std::vector<solver::PrescribedDof> out;
  for (const Index n : m.groups[static_cast<std::size_t>(m.find_group(group))].nodes)
    for (const int d : dirs) out.push_back({n, d});
  return out;
}

void append(std::vector<solver::PrescribedDof>& a, const std::vector<solver::PrescribedDof>& b) {
  a.insert(a.end(), b.begin(), b.end());
}

// |E + D - W - E0 - K_v| over the largest energy in play.
double balance(const solver::EnergyLedger& e) { return e.balance_error(); }

Mat3 rotation(const Vec3& axis, double angle) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

Mat3 tensor(const Vec6& s) {
  Mat3 m;
  m << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
  return m;
}

}  // namespace

// Any affine displacement of a patch: every tetrahedron carries the same stress and the
// interior nodes no force (the patch test, docs/theory.md §2).
TEST(Continuum3D, PatchTestAffineFieldGivesUniformStressAndNoInteriorForce) {
  Model3 model = mesh::build_model_3d(mesh::box_mesh(3, 3, 3, 1.0, 1.0, 1.0), rock3());
  Mat3 G;
  G << 1e-3, 2e-4, -3e-4, 5e-4, -2e-3, 1e-4, -1e-4, 3e-4, 1.5e-3;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) model.nodes.u[i] = G * model.nodes.X[i];
  solver::Solver3 s(model);
  solver::StepSettings3 st;
  st.gravity = Vec3::Zero();
  s.set_settings(st);
  s.initialise();
  s.update_stress();
  const auto& tet = model.tetrahedra;
  double smax = 0.0;
  for (int k = 0; k < 6; ++k) smax = std::max(smax, std::abs(tet.stress[0][k]));
  for (std::size_t t = 1; t < tet.size(); ++t)
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(tet.stress[t][k], tet.stress[0][k], 1e-9 * smax) << t << " " << k;
  // Interior nodes (not on the box's faces): the forces of their tetrahedra cancel.
  const double fscale = smax * 1.0 / 9.0;  // stress times a cell face
  int interior = 0;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    const Vec3 X = model.nodes.X[i];
    if ((X.array() > 1e-9).all() && (X.array() < 1.0 - 1e-9).all()) {
      ++interior;
      EXPECT_LT((model.nodes.a[i] * model.nodes.m[i]).norm(), 1e-9 * fscale) << i;
    }
  }
  EXPECT_EQ(interior, 8);
}

// A prestressed body rotated rigidly by 90 degrees about a skew axis carries the rotated
// stress; an unstressed one stays stress-free (objectivity, docs/theory.md §2).
TEST(Continuum3D, RigidRotationCarriesThePrestressAndCreatesNone) {
  Model3 model = mesh::build_model_3d(mesh::box_mesh(2, 2, 2, 1.0, 2.0, 1.5), rock3());
  const Mat3 R = rotation(Vec3(1.0, 2.0, -0.5), kPi / 2.0);
  for (std::size_t i = 0; i < model.nodes.size(); ++i) model.nodes.u[i] = R * model.nodes.X[i] - model.nodes.X[i];
  solver::Solver3 s(model);
  s.update_stress();
  for (std::size_t t = 0; t < model.tetrahedra.size(); ++t) EXPECT_LT(model.tetrahedra.stress[t].norm(), 1e-9 * 1e9 * 1e-6);
  Vec6 S0;
  S0 << -2e6, -1e6, -3e6, 4e5, -2e5, 1e5;
  model.tetrahedra.stress0.assign(model.tetrahedra.size(), S0);
  s.update_stress();
  const Mat3 expected = R * tensor(S0) * R.transpose();
  for (std::size_t t = 0; t < model.tetrahedra.size(); ++t)
    EXPECT_LT((tensor(model.tetrahedra.stress[t]) - expected).norm(), 1e-9 * tensor(S0).norm()) << t;
}

// A block vibrating freely: with velocity Verlet's offset the ledger closes to round-off
// over 3000 steps (docs/theory.md §7).
TEST(Continuum3D, UndampedVibrationKeepsTheEnergyBalance) {
  Model3 model = mesh::build_model_3d(mesh::box_mesh(4, 2, 2, 2.0, 1.0, 1.0), rock3());
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    const Vec3 X = model.nodes.X[i];
    model.nodes.v[i] = Vec3(0.01 * X.y() * X.x(), -0.02 * X.z() * X.x(), 0.03 * X.x() * X.x());
  }
  solver::Solver3 s(model);
  s.set_constraints(fixed(model, "xmin", {0, 1, 2}));
  s.initialise();
  double kmax = 0.0;
  for (int k = 0; k < 3000; ++k) {
    s.step();
    kmax = std::max(kmax, s.energy().kinetic);
  }
  EXPECT_GT(kmax, 0.0);
  EXPECT_GT(s.energy().strain, 0.0);
  // Velocity Verlet conserves its shadow energy exactly only for a quadratic one; St
  // Venant-Kirchhoff's is quartic, so a residual of order dt^2 strain^2 remains.
  EXPECT_LT(balance(s.energy()), 1e-6) << "kinetic " << s.energy().kinetic << " strain " << s.energy().strain;
}

// A column on rollers settles under its weight to sigma_zz = -rho g (H - z) and
// sigma_xx = sigma_yy = nu / (1 - nu) sigma_zz (uniaxial strain), within 1%.
TEST(Continuum3D, ColumnSettlesToTheUniaxialStrainState) {
  const double H = 10.0, E = 1e8, nu = 0.25, rho = 2000.0, g = 9.81;
  Model3 model = mesh::build_model_3d(mesh::box_mesh(2, 2, 20, 1.0, 1.0, H), rock3(E, nu, rho));
  solver::Solver3 s(model);
  std::vector<solver::PrescribedDof> dofs = fixed(model, "zmin", {2});
  append(dofs, fixed(model, "xmin", {0}));
  append(dofs, fixed(model, "xmax", {0}));
  append(dofs, fixed(model, "ymin", {1}));
  append(dofs, fixed(model, "ymax", {1}));
  s.set_constraints(dofs);
  // Critical damping of the column's first mode, omega = pi cp / (2 H).
  const double cp = model.materials[0].cp();
  solver::StepSettings3 st;
  st.gravity = Vec3(0.0, 0.0, -g);
  st.alpha = 2.0 * kPi * cp / (2.0 * H);
  s.set_settings(st);
  s.initialise();
  const double period = 4.0 * H / cp;
  while (s.time() < 12.0 * period) s.step();
  s.update_stress();
  const auto& tet = model.tetrahedra;
  const double K0 = nu / (1.0 - nu);
  for (std::size_t t = 0; t < tet.size(); ++t) {
    const auto& c = tet.conn[t];
    double zc = 0.0;
    for (const Index v : c) zc += 0.25 * model.nodes.X[v].z();
    // Constant-strain elements carry their layer's mean: the stress at the layer's middle.
    const double dz = H / 20.0, z = (std::floor(zc / dz) + 0.5) * dz;
    const double szz = -rho * g * (H - z);
    EXPECT_NEAR(tet.stress[t][2], szz, 0.01 * rho * g * H) << "z " << z;
    EXPECT_NEAR(tet.stress[t][0], K0 * szz, 0.01 * rho * g * H) << "z " << z;
    EXPECT_NEAR(tet.stress[t][1], K0 * szz, 0.01 * rho * g * H) << "z " << z;
  }
  // The base carries the weight.
  const Vec3 base = s.reaction_on(model.groups[static_cast<std::size_t>(model.find_group("zmin"))].nodes);
  EXPECT_NEAR(base.z(), rho * g * H * 1.0, 1e-3 * rho * g * H);
}

// Unconfined compression of a Mohr-Coulomb block: the axial stress rises elastically and
// levels off at the uniaxial strength 2 c cos(phi) / (1 - sin(phi)); the plastic work is
// positive and the ledger closes.
TEST(Continuum3D, MohrCoulombBlockYieldsAtTheUniaxialStrength) {
  const double c = 1e5, phi = 30.0, E = 1e8, rho = 2000.0, v = 0.02;
  Model3 model = mesh::build_model_3d(mesh::box_mesh(2, 2, 2, 1.0, 1.0, 1.0),
                                      test::mohr_coulomb_material("rock", E, 0.25, rho, c, phi, 0.0));
  solver::Solver3 s(model);
  // Base on rollers, one corner pinned in x and y; the top pushed down at v, slowly against
  // the block's period (0.016 s): quasi-static.
  std::vector<solver::PrescribedDof> dofs = fixed(model, "zmin", {2});
  dofs.push_back({0, 0});
  dofs.push_back({0, 1});
  const auto push = std::make_shared<io::TimeHistory>(io::TimeHistory{{0.0, 1e6}, {-v, -v}});
  for (const Index n : model.groups[static_cast<std::size_t>(model.find_group("zmax"))].nodes)
    dofs.push_back({n, 2, solver::PrescribedDof::Velocity, push});
  s.set_constraints(dofs);
  solver::StepSettings3 st;
  st.gravity = Vec3::Zero();
  st.alpha = 20.0;  // settles the block; its force on the moving top is 0.1% of the load
  s.set_settings(st);
  s.initialise();
  const double ucs = 2.0 * c * std::cos(phi * kPi / 180.0) / (1.0 - std::sin(phi * kPi / 180.0));
  const auto& top = model.groups[static_cast<std::size_t>(model.find_group("zmax"))].nodes;
  // To an axial strain of 0.6% (ucs / E is 0.35%): yielding since about 0.35%.
  const double strain = 0.006;
  while (s.time() < strain / v) s.step();
  // The reaction over the 1 m^2 top is the nominal stress F_zz S_zz; the envelope bounds the
  // second Piola-Kirchhoff stress S.
  const double axial = -s.reaction_on(top).z() / (1.0 - strain);
  EXPECT_NEAR(axial, ucs, 0.005 * ucs) << "axial -S_zz " << axial << " Pa, uniaxial strength " << ucs << " Pa";
  EXPECT_GT(s.energy().plastic_dissipated, 0.0);
  EXPECT_LT(balance(s.energy()), 1e-3);
}

// One thread and two give the same bits: elements, gather and sums in fixed orders.
TEST(Continuum3D, OneAndTwoThreadsGiveTheSameBits) {
  auto run = [](int threads) {
    Model3 model = mesh::build_model_3d(mesh::box_mesh(8, 4, 4, 2.0, 1.0, 1.0),
                                        test::mohr_coulomb_material("rock", 1e8, 0.3, 2000.0, 2e4, 30.0, 5.0));
    solver::Solver3 s(model);
    s.set_constraints(fixed(model, "xmin", {0, 1, 2}));
    solver::StepSettings3 st;
    st.alpha = 1.0;
    st.beta = 1e-5;
    s.set_settings(st);
    s.set_parallel(threads > 1);
    omp_set_num_threads(threads);
    s.initialise();
    for (int k = 0; k < 300; ++k) s.step();
    omp_set_num_threads(1);
    return std::make_pair(model.nodes.u, s.energy().plastic_dissipated + s.energy().damping_dissipated);
  };
  const auto one = run(1), two = run(2);
  ASSERT_EQ(one.first.size(), two.first.size());
  for (std::size_t i = 0; i < one.first.size(); ++i)
    for (int d = 0; d < 3; ++d) ASSERT_EQ(one.first[i][d], two.first[i][d]) << i;
  EXPECT_EQ(one.second, two.second);
  EXPECT_GT(one.second, 0.0);
}

// A tetrahedron crushed flat stops the run with its id, time and position.
TEST(Continuum3D, AnInvertedTetrahedronStopsTheRunWithItsPlace) {
  Model3 model = mesh::build_model_3d(mesh::box_mesh(1, 1, 1, 1.0, 1.0, 1.0), rock3(1e6, 0.25, 2000.0));
  solver::Solver3 s(model);
  const auto crush = std::make_shared<io::TimeHistory>(io::TimeHistory{{0.0, 1e6}, {-500.0, -500.0}});
  std::vector<solver::PrescribedDof> dofs = fixed(model, "zmin", {0, 1, 2});
  for (const Index n : model.groups[static_cast<std::size_t>(model.find_group("zmax"))].nodes)
    dofs.push_back({n, 2, solver::PrescribedDof::Velocity, crush});
  s.set_constraints(dofs);
  s.initialise();
  try {
    for (int k = 0; k < 100000; ++k) s.step();
    FAIL() << "no inversion";
  } catch (const solver::InstabilityError& e) {
    EXPECT_EQ(e.kind, "inverted_element");
    EXPECT_GE(e.id, 0);
    EXPECT_NE(std::string(e.what()).find("tetrahedron"), std::string::npos) << e.what();
    EXPECT_GT(e.time, 0.0);
  }
}

// The first bending frequency of a clamped beam within 2% of Euler-Bernoulli (nu = 0, so
// the beam's width takes no part).
TEST(Continuum3D, CantileverFirstFrequencyWithinTwoPercentOfBeamTheory) {
  const double L = 4.0, h = 0.2, b = 0.2, E = 10e9, rho = 2500.0;
  Model3 model = mesh::build_model_3d(mesh::box_mesh(160, 1, 8, L, b, h), rock3(E, 0.0, rho));
  solver::Solver3 s(model);
  s.set_constraints(fixed(model, "xmin", {0, 1, 2}));
  solver::StepSettings3 st;
  st.gravity = Vec3::Zero();
  st.safety = 0.45;
  s.set_settings(st);
  const double bl = 1.8751040687;
  const double sigma = (std::cosh(bl) + std::cos(bl)) / (std::sinh(bl) + std::sin(bl));
  std::vector<double> phi(model.nodes.size());
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    const double x = model.nodes.X[n].x() / L * bl;
    phi[n] = std::cosh(x) - std::cos(x) - sigma * (std::sinh(x) - std::sin(x));
    model.nodes.v[n] = Vec3(0.0, 0.0, 1e-3 * phi[n]);
  }
  s.initialise();
  const double I = b * h * h * h / 12.0, A = b * h;
  const double f_beam = bl * bl / (2 * kPi * L * L) * std::sqrt(E * I / (rho * A));
  // The modal velocity q = sum m phi v_z filters the higher modes out of the zero crossings.
  auto modal = [&] {
    double q = 0;
    for (std::size_t n = 0; n < model.nodes.size(); ++n) q += model.nodes.m[n] * phi[n] * model.nodes.v[n].z();
    return q;
  };
  std::vector<double> crossings;
  double prev = modal(), tprev = 0;
  while (crossings.size() < 3 && s.time() < 3.0 / f_beam) {
    s.step();
    const double now = modal();
    if ((prev > 0) != (now > 0)) crossings.push_back(tprev + (s.time() - tprev) * prev / (prev - now));
    prev = now;
    tprev = s.time();
  }
  ASSERT_EQ(crossings.size(), 3u);
  const double f = 1.0 / (crossings[2] - crossings[0]);
  std::printf("[ measured ] 3D cantilever f1 %.6g Hz, beam theory %.6g Hz, ratio %.5f, %zu tetrahedra, %ld steps\n", f,
              f_beam, f / f_beam, model.tetrahedra.size(), s.step_count());
  EXPECT_NEAR(f / f_beam, 1.0, 0.02);
}

namespace {

// Design velocity: a Ricker wavelet of peak V at t0; acceleration is its derivative.
seismic::Accelerogram ricker(double V, double f, double t0, double dt, double duration) {
  const std::size_t n = static_cast<std::size_t>(duration / dt) + 1;
  std::vector<double> a(n);
  const double pf2 = kPi * kPi * f * f;
  for (std::size_t i = 0; i < n; ++i) {
    const double tau = static_cast<double>(i) * dt - t0;
    const double g = std::exp(-pf2 * tau * tau);
    a[i] = V * g * (-2.0 * pf2 * tau) * (3.0 - 2.0 * pf2 * tau * tau);
  }
  return seismic::integrate(dt, a, {false, 3});
}

struct ColumnResult {
  double surface_peak_ratio;  // the surface's peak velocity over the design (outcrop) peak
  double energy_left;         // energy in the column at the end over its peak
};

// A soil column hit from below by a Ricker pulse moving along `dir` (0, 1: SV in x, y; 2: P
// in z); its sides held in the two other directions, a viscous-spring base with the free field.
ColumnResult column_under_pulse(int dir) {
  const double H = 100.0, W = 5.0;
  Model3 model = mesh::build_model_3d(mesh::box_mesh(2, 2, 40, W, W, H), test::elastic_material("soil", 1e9, 0.25, 2000));
  solver::Solver3 s(model);
  std::vector<solver::PrescribedDof> dofs;
  for (const char* side : {"xmin", "xmax", "ymin", "ymax"})
    for (int d = 0; d < 3; ++d)
      if (d != dir) append(dofs, fixed(model, side, {d}));
  s.set_constraints(dofs);
  s.set_viscous_boundary(boundary::build_viscous_boundary_3d(model, {{"zmin", 1e4, std::nullopt, true}}), {});
  solver::StepSettings3 st;
  st.gravity = Vec3::Zero();
  s.set_settings(st);
  const double V = 0.1, f = 5.0, t0 = 0.3;
  const seismic::Accelerogram design = ricker(V, f, t0, s.dt(), 2.0);
  s.set_earthquake(dir == 0 ? &design : nullptr, dir == 1 ? &design : nullptr, dir == 2 ? &design : nullptr, 0.5, 0.0);
  s.initialise();
  const auto& top = model.groups[static_cast<std::size_t>(model.find_group("zmax"))].nodes;
  const double c = dir == 2 ? model.materials[0].cp() : model.materials[0].cs();
  double surface_peak = 0, energy_peak = 0;
  while (s.time() < t0 + 3.0 * H / c + 0.4) {
    s.step();
    surface_peak = std::max(surface_peak, std::abs(model.nodes.v[top[4]][dir]));
    energy_peak = std::max(energy_peak, s.energy().kinetic + s.energy().strain);
  }
  const double design_peak = 0.5 * 2.0 * V;  // incident = half the design; the surface doubles it
  return {surface_peak / design_peak, (s.energy().kinetic + s.energy().strain) / energy_peak};
}

}  // namespace

// Vertically incident SV (in x and in y) and P pulses: the free surface moves with twice the
// incident amplitude and the base lets the reflection out, each within 5%.
TEST(Continuum3D, SoilColumnDoublesAtTheSurfaceAndAbsorbsAtTheBase) {
  for (int dir = 0; dir < 3; ++dir) {
    const ColumnResult r = column_under_pulse(dir);
    std::printf("[ measured ] column, pulse along %c: surface/design peak %.4f, energy left %.4f\n", "xyz"[dir],
                r.surface_peak_ratio, r.energy_left);
    EXPECT_NEAR(r.surface_peak_ratio, 1.0, 0.05) << "direction " << dir;
    EXPECT_LT(r.energy_left, 0.05) << "direction " << dir;
  }
}

// Cundall's local damping alone (docs/theory.md §9) brings a column settling under its
// weight to rest, with its work booked as the integrator applies it: the ledger closes.
TEST(Continuum3D, LocalDampingBringsAColumnToRestWithItsWorkBooked) {
  const double H = 10.0, rho = 2000.0, g = 9.81;
  Model3 model = mesh::build_model_3d(mesh::box_mesh(2, 2, 10, 1.0, 1.0, H), rock3(1e8, 0.25, rho));
  solver::Solver3 s(model);
  std::vector<solver::PrescribedDof> dofs = fixed(model, "zmin", {0, 1, 2});
  append(dofs, fixed(model, "xmin", {0}));
  append(dofs, fixed(model, "xmax", {0}));
  append(dofs, fixed(model, "ymin", {1}));
  append(dofs, fixed(model, "ymax", {1}));
  s.set_constraints(dofs);
  solver::StepSettings3 st;
  st.gravity = Vec3(0.0, 0.0, -g);
  st.local_damping = 0.8;
  s.set_settings(st);
  s.initialise();
  double kmax = 0.0;
  for (int k = 0; k < 4000; ++k) {
    s.step();
    kmax = std::max(kmax, s.kinetic_energy());
  }
  const auto& e = s.energy();
  EXPECT_GT(e.damping_dissipated, 0.0);
  EXPECT_LT(e.kinetic, 1e-6 * kmax);
  EXPECT_LT(balance(e), 1e-6) << "damping " << e.damping_dissipated << " strain " << e.strain;
  // The unbalanced force is the damping's own at rest: m a - f_d is small beside the weight.
  const auto fd = s.damping_forces();
  ASSERT_EQ(fd.size(), model.nodes.size());
  double worst = 0.0, weight = 0.0;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    worst = std::max(worst, (model.nodes.m[i] * model.nodes.a[i] - fd[i]).norm());
    weight = std::max(weight, model.nodes.m[i] * g);
  }
  EXPECT_LT(worst, 1e-4 * weight);
}

// A checkpoint taken mid-run and restored into a new solver set up the same way continues
// with the same bits: nodes, law state (Mohr-Coulomb), damping and the ledger.
TEST(Continuum3D, ACheckpointContinuesWithTheSameBits) {
  const auto path = std::filesystem::temp_directory_path() / ("dsdem_ckpt3d_" + std::to_string(::getpid()) + ".h5");
  test::remove_at_exit(path);
  auto make = [](Model3& model) {
    auto s = std::make_unique<solver::Solver3>(model);
    s->set_constraints(fixed(model, "xmin", {0, 1, 2}));
    solver::StepSettings3 st;
    st.alpha = 2.0;
    st.beta = 1e-5;
    st.local_damping = 0.3;
    s->set_settings(st);
    s->initialise();
    return s;
  };
  auto model_of = [] {
    return mesh::build_model_3d(mesh::box_mesh(6, 2, 2, 3.0, 1.0, 1.0),
                                test::mohr_coulomb_material("rock", 1e8, 0.3, 2000.0, 1e4, 30.0, 5.0));
  };
  Model3 a = model_of();
  auto sa = make(a);
  for (int k = 0; k < 200; ++k) sa->step();
  {
    io::CheckpointWriter w(path);
    sa->save(w);
    w.commit();
  }
  for (int k = 0; k < 200; ++k) sa->step();
  ASSERT_GT(sa->energy().plastic_dissipated, 0.0);  // the law state matters

  Model3 b = model_of();
  auto sb = make(b);
  sb->restore(io::CheckpointReader(path));
  EXPECT_EQ(sb->step_count(), 200);
  for (int k = 0; k < 200; ++k) sb->step();
  for (std::size_t i = 0; i < a.nodes.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      ASSERT_EQ(a.nodes.u[i][d], b.nodes.u[i][d]) << i;
      ASSERT_EQ(a.nodes.v[i][d], b.nodes.v[i][d]) << i;
    }
  EXPECT_EQ(sa->time(), sb->time());
  EXPECT_EQ(sa->energy().plastic_dissipated, sb->energy().plastic_dissipated);
  EXPECT_EQ(sa->energy().damping_dissipated, sb->energy().damping_dissipated);
  EXPECT_EQ(sa->energy().balance_error(), sb->energy().balance_error());

  // Another model's checkpoint is refused, naming the entry, and changes nothing.
  Model3 c = mesh::build_model_3d(mesh::box_mesh(4, 2, 2, 3.0, 1.0, 1.0),
                                  test::mohr_coulomb_material("rock", 1e8, 0.3, 2000.0, 1e4, 30.0, 5.0));
  auto sc = make(c);
  const auto u_before = c.nodes.u;
  try {
    sc->restore(io::CheckpointReader(path));
    FAIL() << "restored another model's checkpoint";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nodes/u"), std::string::npos) << e.what();
  }
  EXPECT_EQ(c.nodes.u, u_before);
  EXPECT_EQ(sc->step_count(), 0);
}
