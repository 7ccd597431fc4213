// Verification of the explicit FEM against analytic solutions.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

Material rock(double E = 10e9, double nu = 0.25, double rho = 2500, bool plane_stress = false) {
  Material m;
  m.name = "rock";
  m.E = E;
  m.nu = nu;
  m.rho = rho;
  m.plane_stress = plane_stress;
  return m;
}

io::BoundarySpec bc(const std::string& group, io::BoundaryType type, int direction = 0) {
  io::BoundarySpec b;
  b.group = group;
  b.type = type;
  b.direction = direction;
  return b;
}

}  // namespace

// A step velocity at one end of a laterally confined bar: the front travels at
// cp = sqrt((lambda + 2 mu) / rho). Arrival = the half-amplitude crossing.
TEST(Verification, PWaveSpeedInBarWithinOnePercent) {
  const double L = 20.0, H = 0.1;
  const int nx = 400, ny = 1;
  Model model = mesh::build_model(mesh::rectangle_mesh(nx, ny, L, H, mesh::Diagonal::Cross), rock());
  solver::Solver s(model);
  io::BoundarySpec push = bc("left", io::BoundaryType::Velocity);
  push.x = io::TimeHistory{{0.0}, {1e-3}};
  std::vector<io::BoundarySpec> bcs{bc("bottom", io::BoundaryType::Roller, 1), bc("top", io::BoundaryType::Roller, 1), push};
  // Confine every node laterally (1D strain): all nodes y held.
  io::BoundarySpec all = bc("bottom", io::BoundaryType::Roller, 1);
  s.set_constraints(solver::build_constraints(model, bcs, 0.0));
  auto dofs = s.constraints();
  for (Index n = 0; n < static_cast<Index>(model.nodes.size()); ++n) {
    solver::PrescribedDof d;
    d.node = n;
    d.dir = 1;
    dofs.push_back(d);
  }
  s.set_constraints(dofs);
  const double cp = model.materials[0].cp();
  const double dt = 0.3 * solver::stable_time_step(model, 0.0).dt;
  s.set_settings({Vec2::Zero(), 0.0, 0.0, dt});
  s.initialise();
  // Probes at x = 5 and x = 15 m (mid-height nodes of the cross mesh would be centres; use bottom nodes).
  auto node_at = [&](double x) {
    Index best = 0;
    for (Index n = 0; n < static_cast<Index>(model.nodes.size()); ++n)
      if ((model.nodes.X[n] - Vec2(x, 0)).norm() < (model.nodes.X[best] - Vec2(x, 0)).norm()) best = n;
    return best;
  };
  const Index p1 = node_at(5.0), p2 = node_at(15.0);
  double t1 = -1, t2 = -1;
  double prev1 = 0, prev2 = 0, tprev = 0;
  while (s.time() < 18.0 / cp) {
    s.step();
    const double v1 = model.nodes.v[p1].x(), v2 = model.nodes.v[p2].x();
    auto cross = [&](double prev, double now, double& t) {
      if (t < 0 && prev < 0.5e-3 && now >= 0.5e-3) t = tprev + (s.time() - tprev) * (0.5e-3 - prev) / (now - prev);
    };
    cross(prev1, v1, t1);
    cross(prev2, v2, t2);
    prev1 = v1;
    prev2 = v2;
    tprev = s.time();
  }
  ASSERT_GT(t1, 0);
  ASSERT_GT(t2, 0);
  const double measured = (model.nodes.X[p2].x() - model.nodes.X[p1].x()) / (t2 - t1);
  std::printf("[ measured ] P-wave speed %.6g m/s, analytic %.6g m/s, ratio %.5f\n", measured, cp, measured / cp);
  EXPECT_NEAR(measured / cp, 1.0, 0.01) << "measured " << measured << " m/s, analytic " << cp << " m/s";
}

// First bending frequency of a slender cantilever (L/h = 20, plane stress) within 2%
// of Euler-Bernoulli: f1 = 1.8751^2 / (2 pi L^2) sqrt(E I / (rho A)).
TEST(Verification, CantileverFirstFrequencyWithinTwoPercentOfBeamTheory) {
  const double L = 4.0, h = 0.2, E = 10e9, rho = 2500;
  Model model = mesh::build_model(mesh::rectangle_mesh(120, 6, L, h, mesh::Diagonal::Cross), rock(E, 0.0, rho, true));
  solver::Solver s(model);
  s.set_constraints(solver::build_constraints(model, {bc("left", io::BoundaryType::Fixed)}, 0.0));
  const double dt = 0.9 * solver::stable_time_step(model, 0.0).dt;
  s.set_settings({Vec2::Zero(), 0.0, 0.0, dt});
  // Initial velocity in the first mode shape of the clamped-free beam.
  const double bl = 1.8751040687;
  const double sigma = (std::cosh(bl) + std::cos(bl)) / (std::sinh(bl) + std::sin(bl));
  for (Index n = 0; n < static_cast<Index>(model.nodes.size()); ++n) {
    const double x = model.nodes.X[n].x() / L * bl;
    const double phi = std::cosh(x) - std::cos(x) - sigma * (std::sinh(x) - std::sin(x));
    model.nodes.v[n] = Vec2(0.0, 1e-3 * phi);
  }
  s.initialise();
  const double I = h * h * h / 12.0, A = h;
  const double f_beam = bl * bl / (2 * kPi * L * L) * std::sqrt(E * I / (rho * A));
  // Tip velocity changes sign every half period: time two successive zero crossings.
  Index tip = 0;
  for (Index n = 0; n < static_cast<Index>(model.nodes.size()); ++n)
    if (model.nodes.X[n].x() > L - 1e-9 && std::abs(model.nodes.X[n].y() - h / 2) < 1e-9) tip = n;
  // Modal velocity q = sum m phi v_y filters the higher modes out of the zero crossings.
  std::vector<double> phi(model.nodes.size());
  for (Index n = 0; n < static_cast<Index>(model.nodes.size()); ++n) phi[n] = model.nodes.v[n].y();
  auto modal = [&] {
    double q = 0;
    for (Index n = 0; n < static_cast<Index>(model.nodes.size()); ++n) q += model.nodes.m[n] * phi[n] * model.nodes.v[n].y();
    return q;
  };
  (void)tip;
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
  std::printf("[ measured ] cantilever f1 %.6g Hz, beam theory %.6g Hz, ratio %.5f\n", f, f_beam, f / f_beam);
  EXPECT_NEAR(f / f_beam, 1.0, 0.02) << "ratio " << f / f_beam << " measured " << f << " Hz, beam theory " << f_beam << " Hz";
}

// Without damping, kinetic + strain energy is conserved: drift below 0.1% over 1e4 steps.
TEST(Verification, UndampedEnergyDriftBelowPointOnePercentOver1e4Steps) {
  Model model = mesh::build_model(mesh::rectangle_mesh(20, 10, 2.0, 1.0, mesh::Diagonal::Alternate), rock());
  for (Index n = 0; n < static_cast<Index>(model.nodes.size()); ++n) {
    const Vec2 X = model.nodes.X[n];
    model.nodes.v[n] = Vec2(0.01 * std::sin(kPi * X.x()), 0.02 * X.x() * X.y());  // deforming + spinning
  }
  solver::Solver s(model);
  // The default safety factor 0.3 (docs/theory.md §6).
  s.set_settings({Vec2::Zero(), 0.0, 0.0, 0.3 * solver::stable_time_step(model, 0.0).dt});
  s.initialise();
  const double e0 = s.energy().mechanical();
  double worst = 0;
  for (int i = 0; i < 10000; ++i) {
    s.step();
    worst = std::max(worst, std::abs(s.energy().mechanical() - e0) / e0);
  }
  std::printf("[ measured ] energy drift over 1e4 steps: max %.3e, balance error %.3e\n", worst, s.energy().balance_error());
  EXPECT_LT(worst, 1e-3) << "worst " << worst;
  // The ledger books velocity Verlet's kinetic offset, so its balance closes but for the
  // elements' geometric nonlinearity and rounding.
  EXPECT_LT(s.energy().balance_error(), 1e-7) << s.energy().balance_error();
  EXPECT_GT(s.energy().strain, 0.01 * e0);  // energy really did move between kinetic and strain
}

// A column under gravity, rollers on the sides, fixed base, damped to rest:
// sigma_yy = -rho g depth within 1% (plane strain, laterally confined).
TEST(Verification, GravityColumnReachesLithostaticStress) {
  const double H = 10.0, rho = 2500, g = 9.81;
  Model model = mesh::build_model(mesh::rectangle_mesh(2, 20, 1.0, H, mesh::Diagonal::Alternate), rock(1e9, 0.25, rho));
  solver::Solver s(model);
  s.set_constraints(solver::build_constraints(
      model,
      {bc("left", io::BoundaryType::Roller, 0), bc("right", io::BoundaryType::Roller, 0), bc("bottom", io::BoundaryType::Fixed)},
      0.0));
  const double cp = model.materials[0].cp();
  const double omega1 = kPi * cp / (2 * H);  // first mode of the fixed-free column
  s.set_settings({Vec2(0, -g), 2.0 * omega1, 0.0, 0.5 * solver::stable_time_step(model, 0.0).dt});
  s.initialise();
  while (s.time() < 40.0 / omega1) s.step();
  EXPECT_LT(s.energy().kinetic, 1e-8 * s.energy().strain);
  // CST stress is constant per element, so the centroid value carries an O(rho g h)
  // offset: everywhere within 1% of the base stress, and within 1% of the local value
  // below the top quarter (where rho g depth >> rho g h).
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    const auto& c = model.triangles.conn[t];
    const double yc = (model.nodes.X[c[0]].y() + model.nodes.X[c[1]].y() + model.nodes.X[c[2]].y()) / 3.0;
    const double expected = -rho * g * (H - yc);
    EXPECT_NEAR(model.triangles.stress[t][1], expected, 0.01 * rho * g * H) << "element " << t << " y " << yc;
    if (H - yc > 0.25 * H)
      EXPECT_NEAR(model.triangles.stress[t][1], expected, 0.01 * std::abs(expected)) << "element " << t << " y " << yc;
  }
  double worst_deep = 0;
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    const auto& c = model.triangles.conn[t];
    const double yc = (model.nodes.X[c[0]].y() + model.nodes.X[c[1]].y() + model.nodes.X[c[2]].y()) / 3.0;
    if (H - yc > 0.25 * H) worst_deep = std::max(worst_deep, std::abs(model.triangles.stress[t][1] / (-rho * g * (H - yc)) - 1));
  }
  std::printf("[ measured ] gravity column: worst relative sigma_yy error below the top quarter %.4f\n", worst_deep);
  // The base carries the whole weight.
  const Vec2 reaction = s.reaction_on(model.groups[model.find_group("bottom")].nodes);
  EXPECT_NEAR(reaction.y(), rho * g * H * 1.0, 1e-6 * rho * g * H);
  // Energy balance with damping and gravity.
  EXPECT_LT(s.energy().balance_error(), 1e-3);
}
