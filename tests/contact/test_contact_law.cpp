// Contact law: normal spring-dashpot without tension, incremental tangential spring
// with the Coulomb cap, frame rotation, restitution (paper eqs. 2-4, docs/theory.md §4).
#include <gtest/gtest.h>

#include <cmath>

#include "contact/contact_law.hpp"

using namespace dsdem;
using namespace dsdem::contact;

namespace {

ContactLawParams params(double kn, double ks, double mu, double zeta = 0.0) {
  return {kn, ks, mu, zeta};
}

Vec2 rotated(const Vec2& a, double th) {
  return Vec2(std::cos(th) * a.x() - std::sin(th) * a.y(), std::sin(th) * a.x() + std::cos(th) * a.y());
}

// Head-on bounce of two masses under the law (velocity Verlet, 4000 steps per contact
// period): returns the final separation speed over the approach speed.
double bounce(double m1, double m2, double kn, double zeta, double v0) {
  const ContactLawParams p = params(kn, kn, 0.5, zeta);
  const double m_eff = m1 * m2 / (m1 + m2);
  const double dt = 2.0 * kPi * std::sqrt(m_eff / kn) / 4000.0;
  // Mass 2 at x2 > x1; overlap = x1 - x2 (radii folded in); normal from 2 to 1 = -x.
  double x1 = 0.0, x2 = 0.0, v1 = v0, v2 = 0.0;
  const Vec2 n(-1.0, 0.0);
  auto force_on_1 = [&]() {
    const Vec2 v_rel(v1 - v2, 0.0);
    return contact_law(x1 - x2, n, v_rel, dt, Vec2::Zero(), m_eff, p).force.x();
  };
  double f = 0.0;
  const double p0 = m1 * v1 + m2 * v2;
  for (int step = 0; step < 100000; ++step) {
    v1 += 0.5 * dt * f / m1;
    v2 -= 0.5 * dt * f / m2;
    x1 += dt * v1;
    x2 += dt * v2;
    f = force_on_1();
    v1 += 0.5 * dt * f / m1;
    v2 -= 0.5 * dt * f / m2;
    if (x1 - x2 < 0.0 && v1 < v2) break;  // apart and separating
  }
  EXPECT_NEAR(m1 * v1 + m2 * v2, p0, 1e-12 * std::abs(p0));  // momentum conserved
  return (v2 - v1) / v0;
}

}  // namespace

TEST(ContactLaw, NormalSpringAndNoTension) {
  const ContactLawParams p = params(1e9, 5e8, 0.6, 0.3);
  const Vec2 n(0.6, 0.8);
  // At rest: Fn = kn * delta exactly, along n.
  ContactLawResult r = contact_law(1e-4, n, Vec2::Zero(), 1e-5, Vec2::Zero(), 10.0, p);
  EXPECT_DOUBLE_EQ(r.fn, 1e5);
  EXPECT_NEAR((r.force - 1e5 * n).norm(), 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(r.elastic_energy, 0.5 * 1e9 * 1e-8);
  // Approaching at 1 m/s: the dashpot adds c*1, c = 2 zeta sqrt(m kn).
  const double c = 2.0 * 0.3 * std::sqrt(10.0 * 1e9);
  r = contact_law(1e-4, n, -1.0 * n, 1e-5, Vec2::Zero(), 10.0, p);
  EXPECT_NEAR(r.fn, 1e5 + c, 1e-9 * (1e5 + c));
  // Separating fast: the dashpot would pull; the force is zero, never tensile.
  r = contact_law(1e-4, n, 10.0 * n, 1e-5, Vec2::Zero(), 10.0, p);
  EXPECT_EQ(r.fn, 0.0);
  EXPECT_EQ(r.force, Vec2::Zero());
  // The dashpot dissipated what the spring would have pushed: kn*delta*vn*dt.
  EXPECT_NEAR(r.damping_dissipation, 1e5 * 10.0 * 1e-5, 1e-12);
  // No overlap, no force.
  r = contact_law(-1e-6, n, -1.0 * n, 1e-5, Vec2(3.0, 0.0), 10.0, p);
  EXPECT_EQ(r.fn, 0.0);
  EXPECT_EQ(r.ft, Vec2::Zero());
}

TEST(ContactLaw, TangentialSpringSticksThenCoulombCapHolds) {
  const double kn = 1e9, ks = 4e8, mu = 0.5, delta = 1e-4, dt = 1e-5;
  const ContactLawParams p = params(kn, ks, mu);
  const Vec2 n(0.0, 1.0);  // tangent t = (-1, 0)
  // Stick: slip 1e-6 along +x gives Ft = -ks * slip = -400 N/m along x, below mu*Fn = 5e4.
  ContactLawResult r = contact_law(delta, n, Vec2(0.1, 0.0), dt, Vec2::Zero(), 0.0, p);
  EXPECT_FALSE(r.sliding);
  EXPECT_NEAR(r.ft.x(), -ks * 0.1 * dt, 1e-9);
  EXPECT_NEAR(r.ft.y(), 0.0, 1e-12);
  EXPECT_NEAR(r.elastic_energy, 0.5 * kn * delta * delta + 0.5 * 400.0 * 400.0 / ks, 1e-12);
  // Continue from that history: increments add.
  r = contact_law(delta, n, Vec2(0.1, 0.0), dt, r.ft, 0.0, p);
  EXPECT_NEAR(r.ft.x(), -800.0, 1e-9);
  // Large slip: capped at mu*Fn, opposite to the slip.
  r = contact_law(delta, n, Vec2(-100.0, 0.0), dt, r.ft, 0.0, p);
  EXPECT_TRUE(r.sliding);
  EXPECT_NEAR(r.ft.norm(), mu * kn * delta, 1e-12 * mu * kn * delta);
  EXPECT_GT(r.ft.x(), 0.0);
  EXPECT_NEAR(r.ft.y(), 0.0, 1e-9);
  // Trial force -800 + 4e8*1e-3 = 399200 is capped: heat = work of the applied force
  // (trapezoidal, from -800 to +cap over the slip of 1e-3 m) minus the change of the
  // stored spring energy.
  const double prev = -800.0, slip = 100.0 * dt, cap = mu * kn * delta;
  const double work = 0.5 * (prev + cap) * slip;  // force along +x, the spring stretched by +slip
  const double d_el = 0.5 * (cap * cap - prev * prev) / ks;
  EXPECT_NEAR(r.friction_dissipation, work - d_el, 1e-9 * cap * slip);
}

TEST(ContactLaw, SteadySlidingDissipatesMuFnTimesSlip) {
  // 1000 steps sliding at 0.2 m/s: dissipated energy = mu*Fn*(slip - stick-up slip).
  const double kn = 1e9, ks = 1e9, mu = 0.4, delta = 1e-4, dt = 1e-5, vs = 0.2;
  const ContactLawParams p = params(kn, ks, mu);
  const Vec2 n(0.0, 1.0);
  Vec2 ft = Vec2::Zero();
  double diss = 0.0;
  for (int s = 0; s < 1000; ++s) {
    const ContactLawResult r = contact_law(delta, n, Vec2(vs, 0.0), dt, ft, 0.0, p);
    ft = r.ft;
    diss += r.friction_dissipation;
  }
  const double cap = mu * kn * delta, ds = vs * dt;
  const double slip = 1000 * ds;
  const double elastic = 0.5 * cap * cap / ks;
  // Work of the applied tangential force (trapezoidal per step) = elastic energy + heat.
  double work = 0.0, f = 0.0;
  for (int s = 0; s < 1000; ++s) {
    const double f_new = std::min(cap, f + ks * ds);
    work += ds * 0.5 * (f + f_new);
    f = f_new;
  }
  EXPECT_NEAR(diss + elastic, work, 1e-9 * work);
  EXPECT_NEAR(diss, cap * (slip - cap / ks), 0.5 * ks * ds * ds + 1e-9);
}

TEST(ContactLaw, FastSlidingHeatIsMuFnTimesSlipEvenForLargeSteps) {
  // A run-out step: 40 m/s, dt = 6.7e-4 s, ks = 2e9 Pa (Dr2 slope). Slip per step 0.027 m
  // is 50 times the elastic slip cap/ks: the heat per step must still be mu*Fn*slip,
  // not mu*Fn*slip + ks*slip^2/2 (the trial-state formula gave 56 x too much heat).
  const double kn = 2e9, ks = 2e9, mu = 0.3, delta = 8e-4, dt = 6.7e-4, vs = 40.0;
  const ContactLawParams p = params(kn, ks, mu);
  const Vec2 n(0.0, 1.0);
  const double cap = mu * kn * delta, ds = vs * dt;
  Vec2 ft(-cap, 0.0);  // already sliding along +x
  for (int s = 0; s < 10; ++s) {
    const ContactLawResult r = contact_law(delta, n, Vec2(vs, 0.0), dt, ft, 0.0, p);
    EXPECT_TRUE(r.sliding);
    EXPECT_NEAR(r.friction_dissipation, cap * ds, 1e-9 * cap * ds);
    ft = r.ft;
  }
}

TEST(ContactLaw, StoredTangentialForceRotatesWithTheContactFrame) {
  const ContactLawParams p = params(1e9, 1e9, 0.5);
  const Vec2 n0(0.0, 1.0);
  // Build a stored force of 3e4 N/m (cap 5e4) along the tangent of n0.
  const Vec2 ft0 = contact_law(1e-4, n0, Vec2(0.3, 0.0), 1e-4, Vec2::Zero(), 0.0, p).ft;
  ASSERT_NEAR(ft0.norm(), 3e4, 1e-6);
  for (double th : {0.01, 0.3, 1.0, -0.7, 1.5}) {
    // The whole contact turned rigidly by th, no relative motion: same force, turned.
    const Vec2 n = rotated(n0, th);
    const ContactLawResult r = contact_law(1e-4, n, Vec2::Zero(), 1e-4, ft0, 0.0, p);
    EXPECT_NEAR(r.ft.norm(), ft0.norm(), 1e-10 * ft0.norm());
    EXPECT_NEAR((r.ft - rotated(ft0, th)).norm(), 0.0, 1e-10 * ft0.norm());
    EXPECT_NEAR(r.ft.dot(n), 0.0, 1e-10 * ft0.norm());
  }
  // A full turn in 1000 small steps brings the force back to where it started.
  Vec2 ft = ft0;
  for (int s = 1; s <= 1000; ++s) {
    ft = contact_law(1e-4, rotated(n0, 2.0 * kPi * s / 1000.0), Vec2::Zero(), 1e-4, ft, 0.0, p).ft;
  }
  EXPECT_NEAR((ft - ft0).norm(), 0.0, 1e-8 * ft0.norm());
}

TEST(ContactLaw, NoTensionRestitutionClosedFormMatchesSimulatedBounce) {
  // The closed form (both damping regimes) against a direct integration of the law.
  for (double zeta : {0.05, 0.2, 0.5, 0.9, 1.5, 3.0}) {
    const double sim = bounce(2.0, 3.0, 1e6, zeta, 1.0);
    EXPECT_NEAR(restitution_no_tension(zeta), sim, 2e-3 * sim) << "zeta " << zeta;
  }
  // With the cut-off, the textbook zeta(e) bounces livelier: e = 0.5 gives 0.550.
  EXPECT_NEAR(restitution_no_tension(damping_ratio_linear(0.5)), 0.5503, 1e-3);
}

TEST(ContactLaw, BounceOfTwoMassesGivesTheSetRestitution) {
  for (double e : {0.1, 0.3, 0.5, 0.8, 0.95, 1.0}) {
    const ContactLawParams p = law_params({1e7, 1e7, 0.5, e});
    EXPECT_NEAR(restitution_no_tension(p.damping_ratio), e, 1e-12);
    const double measured = bounce(5.0, 20.0, 1e7, p.damping_ratio, 2.0);
    EXPECT_NEAR(measured, e, 0.02 * e) << "e " << e;
  }
  EXPECT_THROW(damping_ratio_from_restitution(0.0), std::invalid_argument);
  EXPECT_THROW(damping_ratio_from_restitution(1.2), std::invalid_argument);
  EXPECT_NEAR(damping_ratio_linear(std::exp(-kPi)), 1.0 / std::sqrt(2.0), 1e-15);
}
