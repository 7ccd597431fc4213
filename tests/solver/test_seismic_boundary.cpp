// Earthquake input through the viscous-spring boundary, on triangle meshes.
#include <gtest/gtest.h>

#include <cmath>

#include "boundary/boundary_setup.hpp"
#include "common/materials.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "seismic/accelerogram.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

using namespace dsdem;

namespace {

Material soil() { return test::elastic_material("soil", 1e9, 0.25, 2000); }

// Design velocity: a Ricker wavelet of peak V at t0; acceleration is its derivative.
seismic::Accelerogram ricker(double V, double f, double t0, double dt, double duration) {
  const std::size_t n = static_cast<std::size_t>(duration / dt) + 1;
  std::vector<double> a(n);
  const double pf2 = kPi * kPi * f * f;
  for (std::size_t i = 0; i < n; ++i) {
    const double tau = i * dt - t0;
    const double g = std::exp(-pf2 * tau * tau);
    a[i] = V * g * (-2.0 * pf2 * tau) * (3.0 - 2.0 * pf2 * tau * tau);
  }
  return seismic::integrate(dt, a, {false, 3});
}

io::BoundarySpec bc(const std::string& group, io::BoundaryType type, int dir = 0) {
  io::BoundarySpec b;
  b.group = group;
  b.type = type;
  b.direction = dir;
  return b;
}

io::BoundarySpec viscous(const std::string& group, double R) {
  io::BoundarySpec b = bc(group, io::BoundaryType::ViscousSpring);
  b.R = R;
  return b;
}

}  // namespace

// A P pulse from below in a laterally confined column: the free surface moves with twice
// the incident amplitude (within 3%), and at least 95% of the energy leaves through the base.
TEST(SeismicBoundary, ColumnDoublesAtFreeSurfaceAndAbsorbsAtBase) {
  const double H = 100.0, W = 5.0;
  Model model = mesh::build_model(mesh::rectangle_mesh(2, 40, W, H, mesh::Diagonal::Alternate), soil());
  solver::Solver s(model);
  const auto sides = std::vector<io::BoundarySpec>{bc("left", io::BoundaryType::Roller, 0),
                                                   bc("right", io::BoundaryType::Roller, 0), viscous("bottom", 1e4)};
  s.set_constraints(solver::build_constraints(model, sides, 0.0));
  s.set_viscous_boundary(boundary::build_viscous_boundary(model, sides), {});
  const double dt = 0.3 * solver::stable_time_step(model, 0.0).dt;
  const double V = 0.1, f = 5.0, t0 = 0.3;
  const seismic::Accelerogram design = ricker(V, f, t0, dt, 2.0);
  s.set_settings({Vec2::Zero(), 0.0, 0.0, dt, true});
  s.set_earthquake(nullptr, &design, 0.5, 0.0);
  s.initialise();
  const Index top = model.groups[model.find_group("top")].nodes[1];
  double surface_peak = 0, energy_peak = 0;
  const double cp = model.materials[0].cp();
  while (s.time() < t0 + 3.0 * H / cp + 0.4) {
    s.step();
    surface_peak = std::max(surface_peak, std::abs(model.nodes.v[top].y()));
    energy_peak = std::max(energy_peak, s.energy().kinetic + s.energy().strain);
  }
  const double design_peak = 0.5 * 2.0 * V;  // incident = half the design; the surface doubles it
  EXPECT_NEAR(surface_peak / design_peak, 1.0, 0.03) << "surface peak " << surface_peak << " m/s";
  const double left = s.energy().kinetic + s.energy().strain;
  EXPECT_LT(left, 0.05 * energy_peak) << "energy left in the column " << left / energy_peak;
}

// A wide model with viscous-spring sides and base and the free-field input moves like
// the 1D column: horizontal surface motion uniform across the width within 2%.
TEST(SeismicBoundary, WideModelWithFreeFieldSidesMovesUniformly) {
  const double W = 200.0, H = 50.0;
  Model model = mesh::build_model(mesh::rectangle_mesh(80, 20, W, H, mesh::Diagonal::Alternate), soil());
  solver::Solver s(model);
  const auto vs = std::vector<io::BoundarySpec>{viscous("bottom", 500.0), viscous("left", 500.0), viscous("right", 500.0)};
  s.set_viscous_boundary(boundary::build_viscous_boundary(model, vs), {});
  const double dt = 0.3 * solver::stable_time_step(model, 0.0).dt;
  const double V = 0.1, f = 4.0, t0 = 0.3;
  const seismic::Accelerogram design = ricker(V, f, t0, dt, 2.0);
  s.set_settings({Vec2::Zero(), 0.0, 0.0, dt, true});
  s.set_earthquake(&design, nullptr, 0.5, 0.0);
  s.initialise();
  const auto& top = model.groups[model.find_group("top")].nodes;
  auto top_node_at = [&](double x) {
    Index best = top[0];
    for (Index n : top)
      if (std::abs(model.nodes.X[n].x() - x) < std::abs(model.nodes.X[best].x() - x)) best = n;
    return best;
  };
  const Index centre = top_node_at(W / 2), near_left = top_node_at(10.0), near_right = top_node_at(W - 10.0),
              edge = top_node_at(0.0);
  double peak = 0, worst = 0, worst_edge = 0;
  const double cs = model.materials[0].cs();
  while (s.time() < t0 + 2.0 * H / cs + 0.5) {
    s.step();
    const double vc = model.nodes.v[centre].x();
    peak = std::max(peak, std::abs(vc));
    worst = std::max({worst, std::abs(model.nodes.v[near_left].x() - vc), std::abs(model.nodes.v[near_right].x() - vc)});
    worst_edge = std::max(worst_edge, std::abs(model.nodes.v[edge].x() - vc));
  }
  EXPECT_NEAR(peak / V, 1.0, 0.03) << "surface peak " << peak;
  EXPECT_LT(worst / peak, 0.02) << "non-uniformity " << worst / peak;
  EXPECT_LT(worst_edge / peak, 0.02) << "at the very edge " << worst_edge / peak;
}

// Gravity stage on supports, then viscous-spring boundaries with the reactions kept as
// loads and no earthquake: no jump (velocities below 1e-4 m/s), the static stress kept.
TEST(SeismicBoundary, GravityThenDynamicStageSwitchesWithoutJump) {
  const double W = 40.0, H = 20.0, g = 9.81;
  Model model = mesh::build_model(mesh::rectangle_mesh(8, 4, W, H, mesh::Diagonal::Alternate), soil());
  solver::Solver s(model);
  const auto supports = std::vector<io::BoundarySpec>{bc("bottom", io::BoundaryType::Fixed),
                                                      bc("left", io::BoundaryType::Roller, 0),
                                                      bc("right", io::BoundaryType::Roller, 0)};
  s.set_constraints(solver::build_constraints(model, supports, 0.0));
  const double dt = 0.3 * solver::stable_time_step(model, 0.0).dt;
  const double omega = kPi * model.materials[0].cp() / (2 * H);
  s.set_settings({Vec2(0, -g), 2.0 * omega, 0.0, dt, false});
  s.initialise();
  while (s.time() < 60.0 / omega) s.step();
  std::vector<Vec3> static_stress = model.triangles.stress;
  // Dynamic stage: free boundaries become viscous springs; static reactions kept.
  const auto vs = std::vector<io::BoundarySpec>{viscous("bottom", 100.0), viscous("left", 100.0), viscous("right", 100.0)};
  const auto previous = s.constraints();
  s.set_constraints(solver::build_constraints(model, vs, s.time()));
  s.set_viscous_boundary(boundary::build_viscous_boundary(model, vs), previous);
  s.set_settings({Vec2(0, -g), 0.0, 0.0, dt, true});
  const double t_switch = s.time();
  double vmax = 0;
  while (s.time() < t_switch + 1.0) {
    s.step();
    for (const auto& v : model.nodes.v) vmax = std::max(vmax, v.norm());
  }
  EXPECT_LT(vmax, 1e-4) << "velocity after the switch " << vmax << " m/s";
  double worst = 0, scale = 0;
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    worst = std::max(worst, (model.triangles.stress[t] - static_stress[t]).cwiseAbs().maxCoeff());
    scale = std::max(scale, static_stress[t].cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-3 * scale) << "stress change " << worst << " Pa of " << scale;
}
