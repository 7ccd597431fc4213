// One 4-node joint: kinematics in the rotating frame, nodal forces, energy, dt helper.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "joint/joint_force.hpp"
#include "joint/joint_test_props.hpp"

using namespace dsdem;

namespace {

Mat2 rotation(double a) {
  Mat2 R;
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return R;
}

// Reference joint of length L along direction angle alpha, starting at o: a0 = b0 = o,
// a1 = b1 = o + L t. tri_a lies on the left of a0 -> a1.
JointNodePositions bonded(double alpha, double L, const Vec2& o = Vec2(3.0, -2.0)) {
  const Vec2 t(std::cos(alpha), std::sin(alpha));
  return {o, o + L * t, o, o + L * t};
}

Vec2 tangent(double alpha) { return Vec2(std::cos(alpha), std::sin(alpha)); }
Vec2 normal(double alpha) { return Vec2(std::sin(alpha), -std::cos(alpha)); }  // t turned clockwise

double eq6(double d, const JointProperties& p) {
  const double wt = p.ft / p.kn, wn = 2 * p.GI / p.ft;
  if (d < wt) return p.kn * d;
  if (d < wt + wn) return p.ft * (1 - (d - wt) / wn);
  return 0.0;
}

}  // namespace

TEST(JointKinematics, SeparationsInTheMidLineFrame) {
  const double alpha = 0.3, L = 2.0;
  JointNodePositions x = bonded(alpha, L);
  const Vec2 t = tangent(alpha), n = normal(alpha);
  // Same separation at both ends: the mid-line stays along t.
  const double dn = 1e-4, ds = -3e-4;
  x[2] += dn * n + ds * t;
  x[3] += dn * n + ds * t;
  const JointKinematics k = joint_kinematics(x);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(k.dn[i], dn, 1e-15);
    EXPECT_NEAR(k.ds[i], ds, 1e-15);
  }
  EXPECT_NEAR((k.t - t).norm(), 0.0, 1e-15);
  EXPECT_NEAR((k.n - n).norm(), 0.0, 1e-15);
  EXPECT_NEAR(k.length, L, 1e-14);
  // Opening only at end 1 (a hinge): the mid-line tilts by atan(h/2 / L).
  JointNodePositions y = bonded(0.0, L, Vec2::Zero());
  const double h = 0.01;
  y[3] = Vec2(L, -h);  // b1 moved along the normal (0, -1)
  const JointKinematics kh = joint_kinematics(y);
  const double tilt = std::atan2(0.5 * h, L);
  EXPECT_NEAR(kh.t.x(), std::cos(tilt), 1e-15);
  EXPECT_NEAR(kh.t.y(), -std::sin(tilt), 1e-15);
  EXPECT_NEAR(kh.dn[0], 0.0, 1e-15);
  EXPECT_NEAR(kh.dn[1], h * std::cos(tilt), 1e-15);
  EXPECT_NEAR(kh.ds[1], h * std::sin(tilt), 1e-15);
}

TEST(JointForce, RigidRotationOfABondedPairGivesNoForce) {
  const JointProperties p = test::disc_rock();
  const double L = 0.5;
  const JointNodePositions X = bonded(0.7, L);
  const Vec2 centre(10.0, 4.0), shift(-1.5, 2.5);
  for (double deg : {0.0, 1e-4, 30.0, 90.0, 180.0, 270.0, -135.0, 359.0}) {
    const Mat2 R = rotation(deg * kPi / 180.0);
    JointNodePositions x;
    for (int k = 0; k < 4; ++k) x[k] = centre + R * (X[k] - centre) + shift;
    const JointForceResult r = joint_force(x, L, p, {});
    for (int k = 0; k < 4; ++k) EXPECT_LE(r.f[k].norm(), 1e-12 * p.ft * L) << deg;
    for (int i = 0; i < 2; ++i) {
      EXPECT_LE(std::abs(r.kin.dn[i]), 1e-12 * p.ft / p.kn) << deg;
      EXPECT_EQ(r.state[i].damage, 0.0);
    }
    EXPECT_EQ(r.energy, 0.0);
  }
}

TEST(JointForce, RigidRotationOfALoadedJointRotatesItsForces) {
  // Objectivity: an opened and slid joint, spun rigidly, keeps its separations and
  // tractions; its nodal forces turn with it. Separations are passed as rotated
  // displacement differences, as the solver does (see joint_kinematics).
  const JointProperties p = test::disc_rock();
  const double L = 0.5, alpha = -0.4;
  const JointNodePositions X = bonded(alpha, L);
  const double wt = p.ft / p.kn, ws = p.c / p.ks;
  const JointSeparations delta0{0.6 * wt * normal(alpha) + 0.3 * ws * tangent(alpha),
                                0.2 * wt * normal(alpha) - 0.5 * ws * tangent(alpha)};
  JointNodePositions x0 = X;
  x0[2] += delta0[0];
  x0[3] += delta0[1];
  const JointForceResult r0 = joint_force(x0, delta0, L, p, {});
  const double fscale = p.c * L;
  ASSERT_GT(r0.f[0].norm(), 0.01 * fscale);
  for (double deg : {30.0, 90.0, 180.0, 243.0}) {
    const Mat2 R = rotation(deg * kPi / 180.0);
    const Vec2 shift(7.0, 1.0);
    JointNodePositions x;
    for (int k = 0; k < 4; ++k) x[k] = R * x0[k] + shift;
    const JointSeparations delta{R * delta0[0], R * delta0[1]};
    const JointForceResult r = joint_force(x, delta, L, p, {});
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(r.kin.dn[i], r0.kin.dn[i], 1e-12 * wt) << deg;
      EXPECT_NEAR(r.kin.ds[i], r0.kin.ds[i], 1e-12 * ws) << deg;
    }
    for (int k = 0; k < 4; ++k) EXPECT_LE((r.f[k] - R * r0.f[k]).norm(), 1e-12 * fscale) << deg;
    EXPECT_NEAR(r.energy, r0.energy, 1e-12 * r0.energy);
  }
}

namespace {
// Move face b of a joint along direction dir by the amounts in path; return the
// agent's work (trapezoid of the pulling force, equal and opposite to the joint's
// force on b) and check the force against the expected traction at every point.
struct PullResult {
  double work = 0.0, dissipation = 0.0, final_energy = 0.0;
  std::size_t failed_at = 0;
  BreakMode mode = BreakMode::None;
};
template <class Traction>
PullResult pull(const JointProperties& p, double alpha, double L, const Vec2& dir,
                const Vec2& traction_dir, const std::vector<double>& path, Traction expected) {
  PullResult out;
  out.failed_at = path.size();
  std::array<JointPointState, 2> st{};
  JointEndModes modes{};
  const JointNodePositions X = bonded(alpha, L);
  double d_old = 0.0, f_old = 0.0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    JointNodePositions x = X;
    x[2] += path[i] * dir;
    x[3] += path[i] * dir;
    const JointSeparations delta{path[i] * dir, path[i] * dir};
    const JointForceResult r = joint_force(x, delta, L, p, st, true, modes);
    st = r.state;
    modes = r.end_mode;
    const Vec2 fb = r.f[2] + r.f[3];
    const double traction = -fb.dot(traction_dir) / L;  // joint pulls b back
    EXPECT_NEAR(traction, expected(path[i]), 1e-9 * p.c) << "d = " << path[i];
    for (int k = 0; k < 2; ++k) EXPECT_EQ((r.f[k] + r.f[k + 2]).norm(), 0.0);  // action = reaction
    EXPECT_NEAR((r.f[2] - r.f[3]).norm(), 0.0, 1e-12 * p.c * L);  // uniform: L/2 each
    const double f = -fb.dot(dir);  // agent's force along dir
    out.work += 0.5 * (f + f_old) * (path[i] - d_old);
    d_old = path[i];
    f_old = f;
    out.dissipation += r.dissipation;
    out.final_energy = r.energy;
    if (r.failed_now) {
      out.failed_at = i;
      out.mode = r.mode;
    }
  }
  return out;
}
void append_linspace(std::vector<double>& v, double a, double b, int n) {
  for (int i = 1; i <= n; ++i) v.push_back(a + (b - a) * i / n);
}
}  // namespace

TEST(JointForce, PulledApartPairFollowsModeILawAndDissipatesGI) {
  const JointProperties p = test::disc_rock();
  const double L = 0.25, alpha = 37.0 * kPi / 180.0;
  const double wt = p.ft / p.kn, wn = 2 * p.GI / p.ft;
  std::vector<double> d;
  append_linspace(d, 0.0, wt, 20);
  append_linspace(d, wt, wt + wn, 400);
  append_linspace(d, wt + wn, 1.5 * (wt + wn), 20);
  const PullResult r = pull(p, alpha, L, normal(alpha), normal(alpha), d,
                            [&](double x) { return eq6(x, p); });
  const double exact = L * (p.GI + p.ft * p.ft / (2 * p.kn));  // J/m
  EXPECT_NEAR(r.work, exact, 1e-9 * exact);
  EXPECT_NEAR(r.dissipation, exact, 1e-9 * exact);
  EXPECT_NEAR(r.work, L * p.GI, 0.01 * L * p.GI);
  EXPECT_EQ(r.final_energy, 0.0);
  EXPECT_TRUE(r.failed_at == 419 || r.failed_at == 420) << r.failed_at;  // at wt + wn
  EXPECT_EQ(r.mode, BreakMode::Tension);
}

TEST(JointForce, SlidPairFollowsModeIILawAndDissipatesGII) {
  const JointProperties p = test::disc_rock();
  const double L = 0.25, alpha = -2.0;
  const double ws = p.c / p.ks, wsII = 2 * p.GII / p.c;
  std::vector<double> d;
  append_linspace(d, 0.0, ws, 20);
  append_linspace(d, ws, ws + wsII, 400);
  append_linspace(d, ws + wsII, 1.5 * (ws + wsII), 20);
  auto eq7 = [&](double s) {
    if (s < ws) return p.ks * s;
    if (s < ws + wsII) return p.c * (1 - (s - ws) / wsII);
    return 0.0;
  };
  const PullResult r = pull(p, alpha, L, tangent(alpha), tangent(alpha), d, eq7);
  const double exact = L * (p.GII + p.c * p.c / (2 * p.ks));
  EXPECT_NEAR(r.work, exact, 1e-9 * exact);
  EXPECT_NEAR(r.dissipation, exact, 1e-9 * exact);
  EXPECT_NEAR(r.work, L * p.GII, 0.01 * L * p.GII);
  EXPECT_TRUE(r.failed_at == 419 || r.failed_at == 420) << r.failed_at;
  EXPECT_EQ(r.mode, BreakMode::Shear);
}

TEST(JointForce, JointBreaksOnlyWhenBothEndsHaveFailed) {
  // Hinge: face b turns about end 1, opening end 0 past wt + wn while end 1 stays
  // closed. End 0 then carries nothing, end 1 still holds; the joint is intact until
  // end 1 also fails.
  JointProperties p = test::disc_rock();
  const double L = 1.0, wt = p.ft / p.kn, wn = 2 * p.GI / p.ft;
  const JointNodePositions X = bonded(0.0, L, Vec2::Zero());  // n = (0, -1)
  std::array<JointPointState, 2> st{};
  JointEndModes modes{};
  JointForceResult r;
  const int n = 400;
  for (int i = 1; i <= n; ++i) {  // b0 down to 1.2 (wt + wn), b1 fixed
    JointNodePositions x = X;
    x[2].y() -= 1.2 * (wt + wn) * i / n;
    r = joint_force(x, L, p, st, true, modes);
    st = r.state;
    modes = r.end_mode;
    EXPECT_FALSE(r.failed_now);
  }
  EXPECT_EQ(st[0].damage, 1.0);
  EXPECT_EQ(st[1].damage, 0.0);
  EXPECT_EQ(modes[0], BreakMode::Tension);  // end 0 failed, and keeps how
  EXPECT_EQ(modes[1], BreakMode::None);
  EXPECT_EQ(r.f[0].norm(), 0.0);   // failed end: no traction
  EXPECT_EQ(r.f[1].norm(), 0.0);   // end 1 is exactly at zero separation
  // Now open end 1 too, end 0 kept where it is.
  bool broke = false;
  for (int i = 1; i <= n && !broke; ++i) {
    JointNodePositions x = X;
    x[2].y() -= 1.2 * (wt + wn);
    x[3].y() -= 1.2 * (wt + wn) * i / n;
    r = joint_force(x, L, p, st, true, modes);
    st = r.state;
    modes = r.end_mode;
    broke = r.failed_now;
  }
  EXPECT_TRUE(broke);
  EXPECT_EQ(r.mode, BreakMode::Tension);
  EXPECT_NEAR(r.f[1].norm(), 0.0, 1e-9 * p.ft * L);
}

TEST(JointForce, DuctileJointBreaksOnceSlidFartherThanItsLength) {
  // A plane made ductile (GII so large that 2 GII / c is metres) still holds after its
  // peak; once face b has slid past the joint's own length its ends face other edges
  // and the end forces, that far apart, would form a couple no potential gives: it breaks.
  JointProperties p = test::disc_rock();
  p.GII = 1e9;  // wsII = 2 GII / c = 100 m
  const double L = 0.5, alpha = 0.3;
  const JointNodePositions X = bonded(alpha, L);
  const Vec2 t = tangent(alpha), n = normal(alpha);
  std::array<JointPointState, 2> st{};
  JointEndModes modes{};
  const double squeeze = -1e-3 * p.c / p.kn;  // a little compression: residual friction stays
  const int steps = 600;
  int broke_at = -1;
  double slip_at_break = 0.0;
  for (int i = 1; i <= steps && broke_at < 0; ++i) {
    const double slip = 1.5 * L * i / steps;
    JointNodePositions x = X;
    x[2] += slip * t + squeeze * n;
    x[3] += slip * t + squeeze * n;
    const JointForceResult r = joint_force(x, L, p, st, true, modes);
    st = r.state;
    modes = r.end_mode;
    if (r.failed_now) {
      broke_at = i;
      slip_at_break = slip;
      EXPECT_EQ(r.mode, BreakMode::Shear);
    } else {
      EXPECT_LT(st[0].damage, 1.0);  // the law alone would hold on for metres
    }
  }
  ASSERT_GT(broke_at, 0) << "a joint slid 1.5 times its length still holds";
  EXPECT_GT(slip_at_break, L);
  EXPECT_LT(slip_at_break, L * (1.0 + 2.0 / steps));
  EXPECT_EQ(st[0].damage, 1.0);
  EXPECT_EQ(st[1].damage, 1.0);
}

TEST(JointForce, UndamagedJointIsNotBrokenByTheLengthRule) {
  // The length rule is for damaged joints only: an intact bond far inside its limits (a
  // long, very stiff-strength joint) is left to the law.
  JointProperties p = test::disc_rock();
  p.c = 1e30;
  p.ft = 1e29;
  const double L = 1e-9;  // shorter than the elastic slip below
  const JointNodePositions X = bonded(0.0, L, Vec2::Zero());
  JointNodePositions x = X;
  x[2].x() += 2e-9;
  x[3].x() += 2e-9;
  const JointForceResult r = joint_force(x, L, p, {}, true, {});
  EXPECT_FALSE(r.failed_now);
  EXPECT_EQ(r.state[0].damage, 0.0);
}

TEST(JointForce, StableTimeStepIsTheTwoMassSpringLimitOfVelocityVerlet) {
  const JointProperties p = test::disc_rock();
  const double L = 0.01;
  const double k = joint_end_stiffness(p, L);
  EXPECT_DOUBLE_EQ(k, p.kn * 0.5 * L);
  const double ma = 0.2, mb = 0.05;
  const double omega = std::sqrt(k * (1 / ma + 1 / mb));
  const double dt_crit = joint_stable_dt(ma, mb, k);
  EXPECT_NEAR(dt_crit, 2.0 / omega, 1e-14 * dt_crit);
  // Velocity Verlet on the two-mass spring: bounded just below dt_crit, blows up above.
  auto amplitude_after = [&](double dt) {
    double xa = 0, xb = 1e-6, va = 0, vb = 0;
    double fa = k * (xb - xa), fb = -fa;
    double amax = 0;
    for (int i = 0; i < 300; ++i) {
      va += 0.5 * dt * fa / ma;
      vb += 0.5 * dt * fb / mb;
      xa += dt * va;
      xb += dt * vb;
      fa = k * (xb - xa);
      fb = -fa;
      va += 0.5 * dt * fa / ma;
      vb += 0.5 * dt * fb / mb;
      amax = std::max(amax, std::abs(xb - xa));
    }
    return amax;
  };
  EXPECT_LT(amplitude_after(0.98 * dt_crit), 1e-6 * 20);
  EXPECT_GT(amplitude_after(1.02 * dt_crit), 1e-6 * 1e3);
}
