#include <gtest/gtest.h>

#include <cmath>

#include "boundary/viscous_spring.hpp"

using namespace dsdem;
using namespace dsdem::boundary;

namespace {
ElasticMedium rock() {
  Material m;
  m.E = 20e9;
  m.nu = 0.25;
  m.rho = 2600.0;
  return medium_from_material(m);
}
}  // namespace

TEST(ViscousSpring, CoefficientsAreDesignFormulas) {
  const ElasticMedium md = rock();
  const double G = 20e9 / 2.5, lambda = 20e9 * 0.25 / (1.25 * 0.5);
  EXPECT_DOUBLE_EQ(md.G, G);
  EXPECT_DOUBLE_EQ(md.lambda, lambda);
  EXPECT_NEAR(md.cs(), std::sqrt(G / 2600.0), 1e-9);
  EXPECT_NEAR(md.cp(), std::sqrt((lambda + 2 * G) / 2600.0), 1e-9);
  const double A = 2.5, R = 400.0;
  const ViscousSpringCoefficients c = viscous_spring_coefficients(A, md, R);
  // docs/theory.md §5: kn = A aN G/R, kt = A aT G/R, cn = A rho cp, ct = A rho cs; aN = 1, aT = 0.5.
  EXPECT_NEAR(c.kn, A * 1.0 * G / R, 1e-6 * c.kn);
  EXPECT_NEAR(c.kt, A * 0.5 * G / R, 1e-6 * c.kt);
  EXPECT_NEAR(c.cn, A * 2600.0 * md.cp(), 1e-9 * c.cn);
  EXPECT_NEAR(c.ct, A * 2600.0 * md.cs(), 1e-9 * c.ct);
  // The paper's Kb = G/(2 rb) is the tangential spring per unit area.
  EXPECT_NEAR(c.kt / A, G / (2.0 * R), 1e-6);
}

TEST(ViscousSpring, BadInputThrows) {
  const ElasticMedium md = rock();
  EXPECT_THROW(viscous_spring_coefficients(1.0, md, 0.0), std::runtime_error);
  EXPECT_THROW(viscous_spring_coefficients(-1.0, md, 10.0), std::runtime_error);
  EXPECT_THROW(viscous_spring_coefficients(1.0, ElasticMedium{0.0, 1e9, 1e9}, 10.0), std::runtime_error);
  Material bad;
  EXPECT_THROW(medium_from_material(bad), std::runtime_error);
}

TEST(ViscousSpring, ForceSplitsAlongNormalAndTangent) {
  const ViscousSpringCoefficients c{3.0, 5.0, 7.0, 11.0};
  // Left side (outward normal -x): normal is x, tangent is y.
  const Vec2 f = viscous_spring_force(c, Vec2(-1, 0), Vec2(0.1, 0.2), Vec2(0.3, 0.4));
  EXPECT_NEAR(f.x(), -(3.0 * 0.1 + 7.0 * 0.3), 1e-14);
  EXPECT_NEAR(f.y(), -(5.0 * 0.2 + 11.0 * 0.4), 1e-14);
  // Bottom (outward normal -y): normal is y.
  const Vec2 g = viscous_spring_force(c, Vec2(0, -1), Vec2(0.1, 0.2), Vec2(0.3, 0.4));
  EXPECT_NEAR(g.x(), -(5.0 * 0.1 + 11.0 * 0.3), 1e-14);
  EXPECT_NEAR(g.y(), -(3.0 * 0.2 + 7.0 * 0.4), 1e-14);
  // Rotating the boundary, u and v together rotates the force (objectivity).
  const double th = 0.7;
  Mat2 Q;
  Q << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
  const Vec2 fr = viscous_spring_force(c, Q * Vec2(-1, 0), Q * Vec2(0.1, 0.2), Q * Vec2(0.3, 0.4));
  EXPECT_NEAR((fr - Q * f).norm(), 0.0, 1e-14);
}

// A mass on the boundary's spring and dashpot (tangential direction) set moving at v0
// follows the damped oscillator x = v0/wd exp(-zeta w t) sin(wd t). RK4 with 4000 steps
// per period: time-discretisation error below 1e-10 of the amplitude; 1e-8 asserted.
TEST(ViscousSpring, SpringDashpotMassFollowsDampedOscillator) {
  const ElasticMedium md = rock();
  const ViscousSpringCoefficients c = viscous_spring_coefficients(1.0, md, 50.0);
  const double k = c.kt, cd = c.ct;
  const double zeta = 0.2;
  const double m = (cd / (2.0 * zeta)) * (cd / (2.0 * zeta)) / k;  // so that c = 2 zeta sqrt(k m)
  const double w = std::sqrt(k / m), wd = w * std::sqrt(1 - zeta * zeta);
  const Vec2 n(0, -1);  // bottom node: x is tangential
  auto acc = [&](double x, double v) { return viscous_spring_force(c, n, Vec2(x, 0), Vec2(v, 0)).x() / m; };
  const double v0 = 0.01, T = 2 * kPi / w, h = T / 4000;
  double x = 0, v = v0, worst = 0;
  for (int i = 1; i <= 8000; ++i) {
    const double k1x = v, k1v = acc(x, v);
    const double k2x = v + h / 2 * k1v, k2v = acc(x + h / 2 * k1x, v + h / 2 * k1v);
    const double k3x = v + h / 2 * k2v, k3v = acc(x + h / 2 * k2x, v + h / 2 * k2v);
    const double k4x = v + h * k3v, k4v = acc(x + h * k3x, v + h * k3v);
    x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    const double t = i * h;
    worst = std::max(worst, std::abs(x - v0 / wd * std::exp(-zeta * w * t) * std::sin(wd * t)));
  }
  EXPECT_LT(worst / (v0 / wd), 1e-8);
}
