#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "boundary/free_field.hpp"
#include "boundary/viscous_spring.hpp"

using namespace dsdem;
using namespace dsdem::boundary;
using seismic::Accelerogram;

namespace {

// Ricker displacement pulse d(t) = amp (1 - 2p^2) exp(-p^2), p = pi f (t - t0), with its
// exact velocity and acceleration.
struct Ricker {
  double amp, f, t0;
  double d(double t) const {
    const double p = kPi * f * (t - t0);
    return amp * (1 - 2 * p * p) * std::exp(-p * p);
  }
  double v(double t) const {
    const double s = kPi * f, p = s * (t - t0);
    return amp * s * std::exp(-p * p) * (4 * p * p * p - 6 * p);
  }
  double a(double t) const {
    const double s = kPi * f, p = s * (t - t0);
    return amp * s * s * std::exp(-p * p) * (-8 * p * p * p * p + 24 * p * p - 6);
  }
};

Accelerogram sampled(const Ricker& r, double dt, double T) {
  Accelerogram rec;
  rec.dt = dt;
  const int n = static_cast<int>(std::round(T / dt)) + 1;
  for (int i = 0; i < n; ++i) {
    rec.a.push_back(r.a(i * dt));
    rec.v.push_back(r.v(i * dt));
    rec.d.push_back(r.d(i * dt));
  }
  return rec;
}

ElasticMedium soil() { return ElasticMedium{2000.0, 2000.0 * 200.0 * 200.0, 2.0 * 2000.0 * 200.0 * 200.0}; }

}  // namespace

TEST(FreeField, IncidentMotionIsZeroBeforeStartAndScaled) {
  const Ricker r{0.01, 5.0, 0.3};
  const Accelerogram rec = sampled(r, 1e-3, 1.0);
  const IncidentMotion m{&rec};  // default: half the design motion
  EXPECT_EQ(m.at(-0.1).d, 0.0);
  EXPECT_EQ(m.at(-0.1).v, 0.0);
  EXPECT_NEAR(m.at(0.3).d, 0.5 * 0.01, 1e-15);
  // Linear interpolation between samples: exact at samples, O(dt^2 d'') between.
  EXPECT_NEAR(m.at(0.3005).d, 0.5 * r.d(0.3005), 0.5 * 0.125e-6 * std::abs(r.a(0.3)) * 1.01);
}

// docs/theory.md §5: at a bottom node, SV gives
//   Fx = A (aT G/R (u0(t) + u0(t - 2H/cs)) + 2 rho cs v0(t)),  Fy = 0,
// and P gives the same in y with aN and cp.
TEST(FreeField, BottomNodeReducesToDesignExpression) {
  const Ricker r{0.02, 3.0, 0.4};
  const Accelerogram rec = sampled(r, 1e-3, 3.0);
  const IncidentMotion m{&rec, 1.0};
  const ElasticMedium md = soil();
  const double A = 1.7, R = 150.0, H = 60.0, rho = md.rho, G = md.G;
  const ViscousSpringCoefficients c = viscous_spring_coefficients(A, md, R);
  const Vec2 n(0, -1);
  for (double t : {0.1, 0.35, 0.5, 0.72, 0.9, 1.3}) {
    const Vec2 fsv = free_field_input_force(c, A, n, free_field_column(IncidentWave::SV, m, md, 0.0, H, t));
    const double cs = md.cs(), cp = md.cp();
    const double fx = A * (0.5 * G / R * (m.at(t).d + m.at(t - 2 * H / cs).d) + 2 * rho * cs * m.at(t).v);
    EXPECT_NEAR(fsv.x(), fx, 1e-12 * (std::abs(fx) + A * rho * cs * 0.02 * 20));
    EXPECT_EQ(fsv.y(), 0.0);
    const Vec2 fp = free_field_input_force(c, A, n, free_field_column(IncidentWave::P, m, md, 0.0, H, t));
    const double fy = A * (1.0 * G / R * (m.at(t).d + m.at(t - 2 * H / cp).d) + 2 * rho * cp * m.at(t).v);
    EXPECT_NEAR(fp.y(), fy, 1e-12 * (std::abs(fy) + A * rho * cp * 0.02 * 20));
    EXPECT_EQ(fp.x(), 0.0);
  }
}

// Sides: the normal spring/dashpot act on u_ff (SV is normal to a side), the same on
// both sides; the free-field shear gives Fy = +-A rho cs (v0(t - y/cs) - v0(t - (2H-y)/cs)),
// + on the left side (outward normal -x), - on the right. P: the tangential pair acts on
// u_ff and the side traction is +-A lambda/cp (...) in x.
TEST(FreeField, SideNodesLeftRightSymmetry) {
  const Ricker r{0.02, 4.0, 0.3};
  const Accelerogram rec = sampled(r, 1e-3, 3.0);
  const IncidentMotion m{&rec, 1.0};
  const ElasticMedium md = soil();
  const double A = 0.8, R = 200.0, H = 80.0, y = 23.0;
  const ViscousSpringCoefficients c = viscous_spring_coefficients(A, md, R);
  const double cs = md.cs(), cp = md.cp();
  for (double t : {0.2, 0.33, 0.41, 0.6, 0.85, 1.1}) {
    const FreeFieldState sv = free_field_column(IncidentWave::SV, m, md, y, H, t);
    const Vec2 left = free_field_input_force(c, A, Vec2(-1, 0), sv);
    const Vec2 right = free_field_input_force(c, A, Vec2(1, 0), sv);
    const double u_ff = m.at(t - y / cs).d + m.at(t - (2 * H - y) / cs).d;
    const double v_ff = m.at(t - y / cs).v + m.at(t - (2 * H - y) / cs).v;
    const double fx = c.kn * u_ff + c.cn * v_ff;
    const double fy = A * md.rho * cs * (m.at(t - y / cs).v - m.at(t - (2 * H - y) / cs).v);
    const double scale = A * md.rho * cp * 1.0;
    EXPECT_NEAR(left.x(), fx, 1e-12 * scale);
    EXPECT_NEAR(right.x(), fx, 1e-12 * scale);
    EXPECT_NEAR(left.y(), fy, 1e-12 * scale);
    EXPECT_NEAR(right.y(), -fy, 1e-12 * scale);

    const FreeFieldState p = free_field_column(IncidentWave::P, m, md, y, H, t);
    const Vec2 lp = free_field_input_force(c, A, Vec2(-1, 0), p);
    const Vec2 rp = free_field_input_force(c, A, Vec2(1, 0), p);
    const double uy = m.at(t - y / cp).d + m.at(t - (2 * H - y) / cp).d;
    const double vy = m.at(t - y / cp).v + m.at(t - (2 * H - y) / cp).v;
    const double fpy = c.kt * uy + c.ct * vy;
    const double fpx = A * md.lambda / cp * (m.at(t - y / cp).v - m.at(t - (2 * H - y) / cp).v);
    EXPECT_NEAR(lp.y(), fpy, 1e-12 * scale);
    EXPECT_NEAR(rp.y(), fpy, 1e-12 * scale);
    EXPECT_NEAR(lp.x(), fpx, 1e-12 * scale);
    EXPECT_NEAR(rp.x(), -fpx, 1e-12 * scale);
  }
}

TEST(FreeField, FreeSurfaceDoublesAndIsTractionFree) {
  const Ricker r{0.02, 4.0, 0.3};
  const Accelerogram rec = sampled(r, 1e-3, 3.0);
  const IncidentMotion m{&rec, 1.0};
  const ElasticMedium md = soil();
  const double H = 50.0;
  for (double t : {0.4, 0.55, 0.7}) {
    const FreeFieldState sv = free_field_column(IncidentWave::SV, m, md, H, H, t);
    EXPECT_NEAR(sv.u.x(), 2.0 * m.at(t - H / md.cs()).d, 1e-15);
    EXPECT_NEAR(sv.stress.norm(), 0.0, 1e-6);  // Pa, against stresses of ~1e5 Pa
    const FreeFieldState p = free_field_column(IncidentWave::P, m, md, H, H, t);
    EXPECT_NEAR(p.u.y(), 2.0 * m.at(t - H / md.cp()).d, 1e-15);
    EXPECT_NEAR(p.stress.norm(), 0.0, 1e-6);
  }
  // Inside the column the stress is not zero while the pulse passes.
  const FreeFieldState mid = free_field_column(IncidentWave::SV, m, md, 0.0, H, 0.32);
  EXPECT_GT(std::abs(mid.stress[2]), 1e3);
}

// A node that moves exactly with the free field feels, from its spring, dashpot and
// input force together, just the free-field traction A sigma_ff.n: the boundary is then
// invisible to the free field.
TEST(FreeField, NodeMovingWithFreeFieldFeelsOnlyFreeFieldTraction) {
  const Ricker r{0.02, 4.0, 0.3};
  const Accelerogram rec = sampled(r, 1e-3, 3.0);
  const IncidentMotion m{&rec};
  const ElasticMedium md = soil();
  const double A = 1.3, H = 70.0, y = 12.0;
  const ViscousSpringCoefficients c = viscous_spring_coefficients(A, md, 90.0);
  for (const Vec2 n : {Vec2(-1, 0), Vec2(1, 0), Vec2(0, -1)}) {
    FreeFieldState ff = free_field_column(IncidentWave::SV, m, md, n.y() < 0 ? 0.0 : y, H, 0.41);
    ff += free_field_column(IncidentWave::P, m, md, n.y() < 0 ? 0.0 : y, H, 0.41);
    const Vec2 total = free_field_input_force(c, A, n, ff) + viscous_spring_force(c, n, ff.u, ff.v);
    const Vec2 traction(ff.stress[0] * n.x() + ff.stress[2] * n.y(), ff.stress[2] * n.x() + ff.stress[1] * n.y());
    EXPECT_NEAR((total - A * traction).norm(), 0.0, 1e-9 * (A * traction).norm() + 1e-9);
  }
}

TEST(FreeField, BadGeometryThrows) {
  const Ricker r{0.02, 4.0, 0.3};
  const Accelerogram rec = sampled(r, 1e-3, 1.0);
  const IncidentMotion m{&rec};
  EXPECT_THROW(free_field_column(IncidentWave::SV, m, soil(), 1.0, 0.0, 0.1), std::runtime_error);
  EXPECT_THROW(free_field_column(IncidentWave::SV, m, soil(), -1.0, 10.0, 0.1), std::runtime_error);
  EXPECT_THROW(free_field_column(IncidentWave::P, m, soil(), 10.5, 10.0, 0.1), std::runtime_error);
  EXPECT_THROW(free_field_column(IncidentWave::P, IncidentMotion{}, soil(), 1.0, 10.0, 0.1), std::runtime_error);
}

namespace {

// 1D shear column of lumped masses (unit area), base on the viscous-spring boundary,
// integrated with velocity Verlet (dashpot on the half-step velocity, as the solver
// does). Returns the peak surface displacement and the column's energy at the end and
// at its maximum.
struct ColumnResult {
  double peak_surface = 0, energy_end = 0, energy_max = 0;
};
ColumnResult run_column(const ElasticMedium& md, double H, int N, double R, const IncidentMotion* input,
                        const std::function<void(std::vector<double>&, std::vector<double>&, double)>& init,
                        double t_end) {
  const double dy = H / N, k = md.G / dy, cs = md.cs();
  std::vector<double> m(N + 1, md.rho * dy), u(N + 1, 0.0), v(N + 1, 0.0), f(N + 1, 0.0);
  m[0] = m[N] = 0.5 * md.rho * dy;
  init(u, v, dy);
  const ViscousSpringCoefficients c = viscous_spring_coefficients(1.0, md, R);
  const Vec2 n(0, -1);
  const double dt = 0.5 * dy / cs;
  auto forces = [&](double t) {
    std::fill(f.begin(), f.end(), 0.0);
    for (int i = 0; i < N; ++i) {
      const double s = k * (u[i + 1] - u[i]);
      f[i] += s;
      f[i + 1] -= s;
    }
    f[0] += viscous_spring_force(c, n, Vec2(u[0], 0), Vec2(v[0], 0)).x();
    if (input) f[0] += free_field_input_force(c, 1.0, n, free_field_column(IncidentWave::SV, *input, md, 0.0, H, t)).x();
  };
  auto energy = [&]() {
    double e = 0;
    for (int i = 0; i <= N; ++i) e += 0.5 * m[i] * v[i] * v[i];
    for (int i = 0; i < N; ++i) e += 0.5 * k * (u[i + 1] - u[i]) * (u[i + 1] - u[i]);
    return e;
  };
  ColumnResult res;
  forces(0.0);
  const int steps = static_cast<int>(t_end / dt);
  for (int s = 1; s <= steps; ++s) {
    for (int i = 0; i <= N; ++i) {
      v[i] += 0.5 * dt * f[i] / m[i];
      u[i] += dt * v[i];
    }
    forces(s * dt);
    for (int i = 0; i <= N; ++i) v[i] += 0.5 * dt * f[i] / m[i];
    res.peak_surface = std::max(res.peak_surface, std::abs(u[N]));
    res.energy_max = std::max(res.energy_max, energy());
  }
  res.energy_end = energy();
  return res;
}

}  // namespace

// docs/theory.md §5 check: a 1D column hit from below doubles the amplitude at the free
// surface and lets the reflected wave out through the base. 80 masses per dominant
// wavelength: dispersion error ~1e-3, so 1% on the doubling and 99% of the energy out.
TEST(FreeField, ColumnHitFromBelowDoublesAtSurfaceAndEmpties) {
  const ElasticMedium md = soil();  // cs = 200 m/s
  const double H = 100.0;
  const Ricker r{0.01, 5.0, 0.3};
  const Accelerogram rec = sampled(r, 1e-4, 2.5);
  const IncidentMotion m{&rec, 1.0};
  const double t_end = 0.3 + 2 * H / md.cs() + 0.5;
  const ColumnResult res = run_column(md, H, 200, H, &m, [](auto&, auto&, double) {}, t_end);
  EXPECT_NEAR(res.peak_surface / 0.01, 2.0, 0.02);
  EXPECT_LT(res.energy_end / res.energy_max, 0.01);
}

// A downgoing pulse started inside the column leaves through the base: at least 99%
// of its energy is absorbed by the dashpot (the spring aT G/R reflects ~1.5% in
// amplitude at 5 Hz with R = H).
TEST(FreeField, BaseAbsorbsDowngoingPulse) {
  const ElasticMedium md = soil();
  const double H = 100.0, cs = md.cs();
  const Ricker g{0.01, 5.0, 0.0};
  // u(y, t) = g(t + (y - y0)/cs): a pulse centred at y0 = 60 m moving down.
  auto init = [&](std::vector<double>& u, std::vector<double>& v, double dy) {
    for (std::size_t i = 0; i < u.size(); ++i) {
      const double tau = (i * dy - 60.0) / cs;
      u[i] = g.d(tau);
      v[i] = g.v(tau);
    }
  };
  const ColumnResult res = run_column(md, H, 200, H, nullptr, init, 60.0 / cs + 0.5);
  EXPECT_LT(res.energy_end / res.energy_max, 0.01);
}
