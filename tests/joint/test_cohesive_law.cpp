// The joint law at one point against paper eqs. 6-9 / docs/theory.md §3.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <functional>
#include <vector>

#include "joint/cohesive_law.hpp"
#include "joint/joint_test_props.hpp"

using namespace dsdem;

namespace {

// Points from a to b in n equal steps, a excluded (so paths can be chained exactly
// through the kinks of the law).
void append_linspace(std::vector<double>& v, double a, double b, int n) {
  for (int i = 1; i <= n; ++i) v.push_back(a + (b - a) * i / n);
}

// Eq. 6, monotonic loading.
double eq6(double d, const JointProperties& p) {
  const double wt = p.ft / p.kn, wn = 2 * p.GI / p.ft;
  if (d < wt) return p.kn * d;
  if (d < wt + wn) return p.ft * (1 - (d - wt) / wn);
  return 0.0;
}

// Eq. 7, monotonic loading, with strength fs, residual fr and softening length wsII.
double eq7(double ds, double fs, double fr, double wsII, const JointProperties& p) {
  const double s = std::abs(ds), ws = fs / p.ks, sg = ds < 0 ? -1.0 : 1.0;
  if (s < ws) return p.ks * ds;
  if (s < ws + wsII) return sg * (fr + (fs - fr) * (1 - (s - ws) / wsII));
  return sg * fr;
}

struct PathResult {
  std::vector<CohesiveResponse> r;
  double work = 0.0;         // trapezoidal work of the tractions along the path, J/m^2
  double dissipation = 0.0;  // sum of the law's increments, J/m^2
  std::size_t first_failed = 0;  // index of the first failed point (size() if none)
};

PathResult run_path(const std::vector<double>& dn, const std::vector<double>& ds,
                    const JointProperties& p, JointPointState s = {}) {
  PathResult out;
  out.first_failed = dn.size();
  double dn0 = s.dn, ds0 = s.ds, sn0 = last_tractions(s, law_constants(p)).sn, ss0 = s.ss;
  for (std::size_t i = 0; i < dn.size(); ++i) {
    const CohesiveResponse r = cohesive_law(dn[i], ds[i], p, s);
    out.work += 0.5 * (sn0 + r.sn) * (dn[i] - dn0) + 0.5 * (ss0 + r.ss) * (ds[i] - ds0);
    out.dissipation += r.dissipation;
    dn0 = dn[i];
    ds0 = ds[i];
    sn0 = r.sn;
    ss0 = r.ss;
    s = r.state;
    if (r.failed_now) out.first_failed = i;
    out.r.push_back(r);
  }
  return out;
}

}  // namespace

TEST(CohesiveLaw, ValidateAcceptsPaperRockAndRejectsNonPositiveShearStrengthAtCutoff) {
  JointProperties p = test::disc_rock();
  EXPECT_EQ(validate(p), "");
  p.c = 2e6;  // c - ft*tan(45 deg) = -0.5 MPa
  EXPECT_NE(validate(p).find("c - ft*tan(phi)"), std::string::npos) << validate(p);
  p = test::disc_rock();
  p.GII = 0.0;
  EXPECT_NE(validate(p).find("GII"), std::string::npos);
}

TEST(CohesiveLaw, ModeIFollowsEq6PointByPoint) {
  const JointProperties p = test::disc_rock();
  const double wt = p.ft / p.kn, wn = 2 * p.GI / p.ft;
  std::vector<double> dn;
  append_linspace(dn, 0.0, wt, 50);
  append_linspace(dn, wt, wt + wn, 1000);
  append_linspace(dn, wt + wn, 1.5 * (wt + wn), 50);
  const PathResult path = run_path(dn, std::vector<double>(dn.size(), 0.0), p);
  for (std::size_t i = 0; i < dn.size(); ++i) {
    const auto& r = path.r[i];
    ASSERT_NEAR(r.sn, eq6(dn[i], p), 1e-9 * p.ft) << "dn = " << dn[i];
    ASSERT_EQ(r.ss, 0.0);
    const double d_expected = std::clamp((dn[i] - wt) / wn, 0.0, 1.0);
    ASSERT_NEAR(r.state.damage, d_expected, 1e-9);
  }
  // Fails at wt + wn (to round-off: the next point if wt + wn lands 1 ulp short), in tension.
  const std::size_t i_fail = path.first_failed;
  EXPECT_TRUE(i_fail == 1049 || i_fail == 1050) << i_fail;  // dn[1049] = wt + wn
  EXPECT_NEAR(dn[1049], wt + wn, 1e-12 * wn);
  EXPECT_EQ(path.r[i_fail].mode, BreakMode::Tension);
}

TEST(CohesiveLaw, ModeIIFollowsEq7PointByPointBothSigns) {
  const JointProperties p = test::disc_rock();
  // dn = 0: sn = 0, fs = c, no friction, wsII = 2 GII / c.
  const double ws = p.c / p.ks, wsII = 2 * p.GII / p.c;
  for (double sign : {1.0, -1.0}) {
    std::vector<double> ds;
    append_linspace(ds, 0.0, sign * ws, 50);
    append_linspace(ds, sign * ws, sign * (ws + wsII), 1000);
    append_linspace(ds, sign * (ws + wsII), sign * 1.5 * (ws + wsII), 50);
    const PathResult path = run_path(std::vector<double>(ds.size(), 0.0), ds, p);
    for (std::size_t i = 0; i < ds.size(); ++i) {
      ASSERT_NEAR(path.r[i].ss, eq7(ds[i], p.c, 0.0, wsII, p), 1e-9 * p.c) << "ds = " << ds[i];
      ASSERT_EQ(path.r[i].sn, 0.0);
      ASSERT_NEAR(path.r[i].fs, p.c, 1e-9 * p.c);
    }
    const std::size_t i_fail = path.first_failed;
    EXPECT_TRUE(i_fail == 1049 || i_fail == 1050) << i_fail;  // at ws + wsII, to round-off
    EXPECT_EQ(path.r[i_fail].mode, BreakMode::Shear);
  }
}

TEST(CohesiveLaw, ModeIDissipatesGI) {
  const JointProperties p = test::disc_rock();
  const double wt = p.ft / p.kn, wn = 2 * p.GI / p.ft;
  std::vector<double> dn;
  append_linspace(dn, 0.0, wt, 20);
  append_linspace(dn, wt, wt + wn, 200);
  append_linspace(dn, wt + wn, 2 * (wt + wn), 20);
  const PathResult path = run_path(dn, std::vector<double>(dn.size(), 0.0), p);
  // Softening area = GI by construction (docs/theory.md §3); the elastic branch adds
  // ft^2/(2 kn), 0.06 % of GI for this penalty stiffness.
  const double exact = p.GI + p.ft * p.ft / (2 * p.kn);
  EXPECT_NEAR(path.work, exact, 1e-9 * exact);
  EXPECT_NEAR(path.dissipation, exact, 1e-9 * exact);
  EXPECT_NEAR(path.work, p.GI, 0.01 * p.GI);
  EXPECT_EQ(path.r.back().energy, 0.0);
}

TEST(CohesiveLaw, ModeIIDissipatesGII) {
  const JointProperties p = test::disc_rock();
  const double ws = p.c / p.ks, wsII = 2 * p.GII / p.c;
  std::vector<double> ds;
  append_linspace(ds, 0.0, ws, 20);
  append_linspace(ds, ws, ws + wsII, 200);
  append_linspace(ds, ws + wsII, 2 * (ws + wsII), 20);
  const PathResult path = run_path(std::vector<double>(ds.size(), 0.0), ds, p);
  const double exact = p.GII + p.c * p.c / (2 * p.ks);  // elastic part: 0.32 % of GII
  EXPECT_NEAR(path.work, exact, 1e-9 * exact);
  EXPECT_NEAR(path.dissipation, exact, 1e-9 * exact);
  EXPECT_NEAR(path.work, p.GII, 0.01 * p.GII);
}

namespace {
// Largest root of a monotone function on [lo, hi] by bisection.
double bisect(const std::function<double(double)>& f, double lo, double hi) {
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Proportional loading (dn, ds) = lambda*(cos a, sin a): check that the law fails
// exactly where the analytic eq. 9 does, with vanishing tractions just before.
void check_ellipse(const JointProperties& p, double angle_deg) {
  const double a = angle_deg * kPi / 180.0, ca = std::cos(a), sa = std::sin(a);
  const double wt = p.ft / p.kn, wn = 2 * p.GI / p.ft, tphi = std::tan(p.phi);
  auto ellipse = [&](double lam) {
    const double dn = lam * ca, s = lam * sa;
    const double sn = eq6(dn, p);  // monotonic loading: maxima = current values
    const double fs = p.c - sn * tphi, ws = fs / p.ks, wsII = 2 * p.GII / fs;
    return std::pow(std::max(dn - wt, 0.0) / wn, 2) + std::pow(std::max(s - ws, 0.0) / wsII, 2) - 1;
  };
  const double lam_star = bisect(ellipse, 0.0, 10.0 * (wn + 2 * p.GII / p.c));
  std::vector<double> lam;
  append_linspace(lam, 0.0, lam_star * (1 - 1e-9), 2000);
  lam.push_back(lam_star * (1 + 1e-9));
  std::vector<double> dn, ds;
  for (double l : lam) {
    dn.push_back(l * ca);
    ds.push_back(l * sa);
  }
  const PathResult path = run_path(dn, ds, p);
  const auto& before = path.r[path.r.size() - 2];
  const auto& after = path.r.back();
  EXPECT_FALSE(before.failed) << angle_deg;
  EXPECT_GT(before.state.damage, 1 - 1e-6) << angle_deg;
  EXPECT_TRUE(after.failed_now) << angle_deg;
  // No finite traction is dropped at failure.
  EXPECT_LT(std::abs(before.sn), 1e-6 * p.ft) << angle_deg;
  EXPECT_LT(std::abs(before.ss), 1e-6 * p.c) << angle_deg;
  const bool both = lam_star * ca > wt && lam_star * sa > after.ws;
  if (both) EXPECT_EQ(after.mode, BreakMode::Mixed) << angle_deg;
}
}  // namespace

TEST(CohesiveLaw, MixedModeBreaksOnTheEllipseWithoutFriction) {
  JointProperties p = test::disc_rock();
  p.phi = 0.0;  // fs = c: the ellipse is a fixed curve in (dn, |ds|)
  for (double angle : {10.0, 30.0, 45.0, 60.0, 80.0}) check_ellipse(p, angle);
}

TEST(CohesiveLaw, MixedModeBreaksOnTheEllipseWithTensionWeakenedShearStrength) {
  JointProperties p = test::disc_rock();
  p.phi = 30.0 * kPi / 180.0;  // fs = c - sn tan(phi) moves ws and wsII with sn
  for (double angle : {20.0, 45.0, 70.0}) check_ellipse(p, angle);
}

TEST(CohesiveLaw, CompressionRaisesShearStrengthByMohrCoulomb) {
  const JointProperties p = test::disc_rock();
  const double tphi = std::tan(p.phi);
  for (double d0 : {0.0, 1e-7, 3e-7, 1e-6}) {
    const double sn = -p.kn * d0;  // up to -42 MPa
    const double fs = p.c - sn * tphi;
    const double ws = fs / p.ks;
    std::vector<double> ds;
    append_linspace(ds, 0.0, ws, 100);
    append_linspace(ds, ws, 1.5 * ws, 50);
    const PathResult path = run_path(std::vector<double>(ds.size(), -d0), ds, p);
    double peak = 0.0;
    for (const auto& r : path.r) {
      ASSERT_NEAR(r.sn, sn, 1e-12 * p.c);
      peak = std::max(peak, r.ss);
    }
    EXPECT_NEAR(peak, fs, 1e-9 * fs) << "d0 = " << d0;
    EXPECT_NEAR(path.r[99].ss, fs, 1e-9 * fs);  // reached at ws = fs/ks
    EXPECT_NEAR(path.r[49].ss, 0.5 * fs, 1e-9 * fs);  // slope ks before
  }
  // Tension cut-off: at sn = ft the strength is c - ft tan(phi) (eq. 8).
  const double wt = p.ft / p.kn, fs_cut = p.c - p.ft * tphi;
  std::vector<double> ds;
  append_linspace(ds, 0.0, fs_cut / p.ks, 100);
  const PathResult path = run_path(std::vector<double>(ds.size(), wt), ds, p);
  EXPECT_NEAR(path.r.back().ss, fs_cut, 1e-9 * p.c);
  EXPECT_NEAR(path.r.back().fs, fs_cut, 1e-9 * p.c);
}

TEST(CohesiveLaw, ResidualFrictionAfterShearSofteningOnlyInCompression) {
  const JointProperties p = test::disc_rock();
  const double tphi = std::tan(p.phi);
  const double d0 = 2e-7, sn = -p.kn * d0;  // -8.4 MPa
  const double fr = -sn * tphi, fs = p.c + fr, ws = fs / p.ks;
  const double wsII = 2 * p.GII / p.c;  // softening of the cohesion only: area GII
  std::vector<double> ds;
  append_linspace(ds, 0.0, ws, 20);
  append_linspace(ds, ws, ws + wsII, 500);
  append_linspace(ds, ws + wsII, 2 * (ws + wsII), 20);
  const PathResult path = run_path(std::vector<double>(ds.size(), -d0), ds, p);
  double area_above_friction = 0.0;
  for (std::size_t i = 0; i < ds.size(); ++i) {
    ASSERT_NEAR(path.r[i].ss, eq7(ds[i], fs, fr, wsII, p), 1e-9 * fs) << ds[i];
    if (i >= 20 && i <= 519)  // intervals from ws (index 19) to ws + wsII (519)
      area_above_friction += 0.5 * (path.r[i].ss + path.r[i - 1].ss - 2 * fr) * (ds[i] - ds[i - 1]);
  }
  EXPECT_NEAR(area_above_friction, p.GII, 1e-9 * p.GII);
  EXPECT_TRUE(path.first_failed == 519 || path.first_failed == 520) << path.first_failed;
  EXPECT_EQ(path.r[path.first_failed].mode, BreakMode::Shear);
  EXPECT_NEAR(path.r.back().ss, fr, 1e-9 * fr);  // residual -sn tan(phi) ...
  EXPECT_NEAR(path.r.back().sn, sn, 1e-9 * p.c);  // ... and compression still carried

  // Same slip history in tension (dn = wt/2): nothing is left once failed.
  const double wt = p.ft / p.kn;
  const PathResult tens = run_path(std::vector<double>(ds.size(), 0.5 * wt), ds, p);
  EXPECT_TRUE(tens.r.back().failed);
  EXPECT_EQ(tens.r.back().ss, 0.0);
  EXPECT_EQ(tens.r.back().sn, 0.0);
}

TEST(CohesiveLaw, UnloadAndReloadFollowTheSecantAndKeepTheDamage) {
  const JointProperties p = test::disc_rock();
  const double wt = p.ft / p.kn, wn = 2 * p.GI / p.ft;
  // Mode I: load to 40 % softening, unload through zero into compression, reload.
  const double d1 = wt + 0.4 * wn, s1 = 0.6 * p.ft;
  std::vector<double> dn;
  append_linspace(dn, 0.0, d1, 400);
  const std::size_t n_load = dn.size();
  append_linspace(dn, d1, -wt, 300);
  append_linspace(dn, -wt, d1, 300);
  const std::size_t n_reload = dn.size();
  append_linspace(dn, d1, wt + 0.5 * wn, 100);
  const PathResult path = run_path(dn, std::vector<double>(dn.size(), 0.0), p);
  double dissipated_cycle = 0.0;
  for (std::size_t i = n_load; i < n_reload; ++i) {
    const auto& r = path.r[i];
    const double expected = dn[i] > 0 ? s1 * dn[i] / d1 : p.kn * dn[i];
    ASSERT_NEAR(r.sn, expected, 1e-9 * p.ft) << dn[i];
    ASSERT_NEAR(r.state.damage, 0.4, 1e-12);
    dissipated_cycle += r.dissipation;
  }
  EXPECT_NEAR(dissipated_cycle, 0.0, 1e-12 * p.GI);
  EXPECT_NEAR(path.r.back().sn, 0.5 * p.ft, 1e-9 * p.ft);  // back on the envelope
  EXPECT_NEAR(path.r.back().state.damage, 0.5, 1e-9);

  // Mode II: load to 25 % softening, reverse the slip to the same magnitude.
  const double ws = p.c / p.ks, wsII = 2 * p.GII / p.c, s_1 = ws + 0.25 * wsII;
  std::vector<double> ds;
  append_linspace(ds, 0.0, s_1, 200);
  append_linspace(ds, s_1, -s_1, 400);
  const PathResult sh = run_path(std::vector<double>(ds.size(), 0.0), ds, p);
  for (std::size_t i = 200; i < ds.size(); ++i) {
    ASSERT_NEAR(sh.r[i].ss, 0.75 * p.c * ds[i] / s_1, 1e-9 * p.c) << ds[i];
    ASSERT_NEAR(sh.r[i].state.damage, 0.25, 1e-12);
  }
}

namespace {
using Corners = std::vector<std::array<double, 2>>;
// Largest traction change between consecutive points of the polygonal path through
// corners (dn, ds), walked with per_segment steps per side.
double max_traction_jump(const Corners& corners, int per_segment, const JointProperties& p) {
  std::vector<double> dn, ds;
  for (std::size_t k = 1; k < corners.size(); ++k)
    for (int i = 1; i <= per_segment; ++i) {
      const double f = double(i) / per_segment;
      dn.push_back(corners[k - 1][0] + f * (corners[k][0] - corners[k - 1][0]));
      ds.push_back(corners[k - 1][1] + f * (corners[k][1] - corners[k - 1][1]));
    }
  const PathResult path = run_path(dn, ds, p);
  EXPECT_TRUE(path.r.back().failed);  // the path goes through failure
  double jump = 0.0;
  for (std::size_t i = 1; i < path.r.size(); ++i)
    jump = std::max({jump, std::abs(path.r[i].sn - path.r[i - 1].sn),
                     std::abs(path.r[i].ss - path.r[i - 1].ss)});
  return jump;
}
}  // namespace

TEST(CohesiveLaw, TractionsAreContinuousAlongPathsThroughAllBranches) {
  // A Lipschitz-continuous law's largest traction jump per step shrinks in proportion
  // to the step; a jump (a traction dropped or switched on at failure) would not.
  const JointProperties p = test::disc_rock();
  const double wt = p.ft / p.kn, wn = 2 * p.GI / p.ft, ws = p.c / p.ks, wsII = 2 * p.GII / p.c;
  // Elastic, mixed softening, unloading into compression with reversed slip,
  // reloading, failure in tension-shear, closing.
  const Corners mixed = {{0, 0},
                         {2 * wt, 0.5 * ws},
                         {wt + 0.3 * wn, 2 * ws},
                         {-3 * wt, 2 * ws},
                         {-3 * wt, -(ws + 0.5 * wsII)},
                         {wt + 0.6 * wn, -(ws + 0.6 * wsII)},
                         {wt + 0.9 * wn, -(ws + 0.8 * wsII)},
                         {-wt, 0}};
  // Shear failure under compression (residual friction switches on), slip reversal,
  // opening.
  const Corners confined = {{0, 0}, {-2 * wt, 0}, {-2 * wt, 3 * (ws + wsII)},
                            {-2 * wt, -0.5 * ws}, {wt, 0}};
  for (const Corners* c : {&mixed, &confined}) {
    const double coarse = max_traction_jump(*c, 1000, p);
    const double fine = max_traction_jump(*c, 10000, p);
    EXPECT_LT(fine, 0.15 * coarse) << "coarse " << coarse << " Pa, fine " << fine << " Pa";
  }
}

TEST(CohesiveLaw, FrozenHistoryIsElasticAndDissipatesNothing) {
  const JointProperties p = test::disc_rock();
  const double wt = p.ft / p.kn, ws = p.c / p.ks;
  JointPointState s;
  const CohesiveResponse r = cohesive_law(3 * wt, 2 * ws, p, s, /*damage_enabled=*/false);
  EXPECT_NEAR(r.sn, 3 * p.ft, 1e-9 * p.ft);  // beyond the strength: stage-1 joints hold
  EXPECT_NEAR(r.ss, 2 * p.c, 1e-9 * p.c);
  EXPECT_EQ(r.state.damage, 0.0);
  EXPECT_EQ(r.state.dn_max, 0.0);
  EXPECT_EQ(r.state.s_max, 0.0);
  EXPECT_FALSE(r.failed);
  EXPECT_NEAR(r.energy, 0.5 * (3 * p.ft * 3 * wt + 2 * p.c * 2 * ws), 1e-9 * p.c * ws);
  EXPECT_NEAR(r.dissipation, 0.0, 1e-12 * p.c * ws);
}

TEST(CohesiveLaw, ClosedCyclesOfCompressionAndSlipAfterShearDamageCreateNoEnergy) {
  // After shear damage the secant stiffness depends on the compression (fs and fr grow
  // with -sn). Slip released under high compression and re-applied under low
  // compression is a closed loop in (dn, ds): a passive joint must absorb work over it.
  // A law that re-evaluates the secant at the current sn hands back more energy than
  // it took (0.5 * (k_high - k_low) * ds^2 per loop) and blew up the Brazilian disc
  // next to the loading plates (energy pumped by the normal oscillations).
  const JointProperties p = test::disc_rock();
  const double wt = p.ft / p.kn, ws = p.c / p.ks, wsII = 2 * p.GII / p.c;
  const double s1 = ws + 0.2 * wsII;    // 20 % into shear softening at sn = 0
  const double d0 = 40 * wt;            // compression of 100 MPa: fs and fr both up by 100 MPa
  std::vector<double> dn, ds;
  auto leg = [&](double dn_a, double ds_a, double dn_b, double ds_b, int n) {
    append_linspace(dn, dn_a, dn_b, n);
    append_linspace(ds, ds_a, ds_b, n);
  };
  leg(0, 0, 0, s1, 400);                 // shear damage at sn = 0
  leg(0, s1, 0, 0.5 * s1, 100);          // partial unloading
  const std::size_t loop_start = dn.size();
  for (int cycle = 0; cycle < 10; ++cycle) {
    leg(0, 0.5 * s1, -d0, 0.5 * s1, 50);        // compress at fixed slip
    leg(-d0, 0.5 * s1, -d0, 0.2 * s1, 50);      // release slip under compression
    leg(-d0, 0.2 * s1, 0, 0.2 * s1, 50);        // decompress at fixed slip
    leg(0, 0.2 * s1, 0, 0.5 * s1, 50);          // re-apply slip without compression
  }
  const PathResult path = run_path(dn, ds, p);
  double work = 0.0, dissipation = 0.0;
  for (std::size_t i = loop_start; i < dn.size(); ++i) {
    const auto& a = path.r[i - 1];
    const auto& b = path.r[i];
    work += 0.5 * (a.sn + b.sn) * (dn[i] - dn[i - 1]) + 0.5 * (a.ss + b.ss) * (ds[i] - ds[i - 1]);
    dissipation += b.dissipation;
    ASSERT_GE(b.dissipation, -1e-9 * p.c * ws) << "step " << i;
    ASSERT_NEAR(b.state.damage, path.r[loop_start - 1].state.damage, 1e-12);  // below s_max: no new damage
  }
  EXPECT_GE(work, 0.0);  // the loops absorb energy (here: friction), never release it
  // Work = dissipation + change of stored energy (the law integrates the kinks where
  // the traction is held at zero exactly, this sum by plain trapezoids: 1e-3).
  const double stored0 = path.r[loop_start - 1].energy, stored1 = path.r.back().energy;
  EXPECT_GT(dissipation, 0.0);
  EXPECT_NEAR(work, dissipation + stored1 - stored0, 1e-3 * std::abs(work));
  // The traction never exceeds the shear strength at the current compression.
  for (std::size_t i = loop_start; i < dn.size(); ++i) EXPECT_LE(std::abs(path.r[i].ss), path.r[i].fs * (1 + 1e-12));
}

// The elastic fast path (undamaged point inside wt and ws = fs/ks): exactly linear,
// nothing dissipated, and continuous with the general branch at the elastic limit in
// tension, in shear under compression and in shear with the gravity stage's frozen
// history (a separate branch).
TEST(CohesiveLaw, ElasticRangeIsExactlyLinearAndMeetsTheGeneralBranchAtTheLimit) {
  const JointProperties p = test::disc_rock();
  const double wt = p.ft / p.kn, ws = p.c / p.ks;
  for (double dn : {-2 * wt, -0.3 * wt, 0.0, 0.4 * wt, 0.999 * wt})
    for (double ds : {-0.9 * ws, -0.01 * ws, 0.0, 0.3 * ws}) {
      const JointPointState fresh;
      const CohesiveResponse r = cohesive_law(dn, ds, p, fresh);
      const double fs = p.c - std::min(p.kn * dn, p.ft) * std::tan(p.phi);
      if (std::abs(ds) * p.ks > fs) continue;  // tension lowered fs below this slip
      EXPECT_EQ(r.sn, p.kn * dn);
      EXPECT_EQ(r.ss, p.ks * ds);
      EXPECT_EQ(r.dissipation, 0.0);
      EXPECT_EQ(r.state.damage, 0.0);
      EXPECT_NEAR(r.energy, 0.5 * (p.kn * dn * dn + p.ks * ds * ds), 1e-15 * (p.ft * wt + p.c * ws));
    }
  // Across the limit: the traction just inside (fast path) and just outside (general
  // branch) differ by the slope times the step, not by a jump.
  const double eps = 1e-9;
  for (auto [dn_in, ds_in, dn_out, ds_out] :
       {std::array<double, 4>{(1 - eps) * wt, 0, (1 + eps) * wt, 0},
        std::array<double, 4>{-wt, (1 - eps) * (ws + wt * std::tan(p.phi) * p.kn / p.ks), -wt,
                              (1 + eps) * (ws + wt * std::tan(p.phi) * p.kn / p.ks)}}) {
    const CohesiveResponse in = cohesive_law(dn_in, ds_in, p, JointPointState{});
    const CohesiveResponse out = cohesive_law(dn_out, ds_out, p, in.state);
    EXPECT_EQ(in.state.damage, 0.0);
    EXPECT_GT(out.state.damage, 0.0);
    EXPECT_NEAR(out.sn, in.sn, 1e-6 * p.ft);
    EXPECT_NEAR(out.ss, in.ss, 1e-6 * p.c);
  }
  // Frozen history (gravity stage): linear beyond wt without damage, as before.
  const CohesiveResponse frozen = cohesive_law(3 * wt, 0.0, p, JointPointState{}, false);
  EXPECT_EQ(frozen.state.damage, 0.0);
  EXPECT_NEAR(frozen.sn, 3 * p.ft, 1e-12 * p.ft);
}

// The history keeps no tractions but the shear one (memory per element):
// last_tractions() recomputes the normal traction and the shear secant of the
// evaluation that left it. They must be that evaluation's bits, in every regime
// (elastic fast path, softening, unloading, compression with friction, failed,
// frozen history), or the next increment's dissipation and a restart would drift.
TEST(CohesiveLaw, LastTractionsAreThoseOfTheEvaluationThatLeftTheHistory) {
  JointProperties p = test::disc_rock();
  for (double scale : {1.0, 2.5}) {
    const JointLawConstants k = scaled(law_constants(p), scale);
    const double wt = k.ft / k.kn, ws = k.c / k.ks, wn = 2 * p.GI / p.ft, wsII = 2 * p.GII / p.c;
    std::vector<double> dn, ds;
    auto leg = [&](double dn_a, double ds_a, double dn_b, double ds_b, int n) {
      append_linspace(dn, dn_a, dn_b, n);
      append_linspace(ds, ds_a, ds_b, n);
    };
    leg(0, 0, 0.5 * wt, 0.3 * ws, 20);                  // elastic
    leg(0.5 * wt, 0.3 * ws, -3 * wt, 0.9 * ws, 20);     // compression, still elastic
    leg(-3 * wt, 0.9 * ws, -3 * wt, ws + 0.3 * wsII, 50);  // shear softening under compression
    leg(-3 * wt, ws + 0.3 * wsII, 0.0, 0.2 * ws, 30);   // unloading, slip back through zero traction
    leg(0.0, 0.2 * ws, wt + 0.4 * wn, -0.5 * ws, 40);   // opening: mixed-mode softening
    leg(wt + 0.4 * wn, -0.5 * ws, -wt, -ws, 20);        // closing again
    leg(-wt, -ws, wt + 2 * wn, 3 * (ws + wsII), 60);    // to failure and past it
    for (bool enabled : {true, false}) {
      // Frozen history (gravity stage) for the last steps, or from half-way on.
      auto damage_on = [&](std::size_t i) { return enabled ? i + 10 < dn.size() : 2 * i < dn.size(); };
      JointPointState st;
      int checked = 0, general = 0;
      for (std::size_t i = 0; i < dn.size(); ++i) {
        const CohesiveResponse r = cohesive_law(dn[i], ds[i], k, st, damage_on(i));
        st = r.state;
        const LastTractions t = last_tractions(st, k);
        ASSERT_EQ(t.sn, r.sn) << "step " << i;
        ASSERT_EQ(st.ss, r.ss) << "step " << i;
        if (r.ws == 0.0) {  // elastic fast path: the secant is ks
          ASSERT_EQ(t.ks_sec, k.ks) << "step " << i;
        } else {  // general branch: its energy from the recomputed secant, bit for bit
          const double shear = t.ks_sec > 0.0 ? 0.5 * st.ss * st.ss / t.ks_sec : 0.0;
          ASSERT_EQ(0.5 * t.sn * st.dn + shear, r.energy) << "step " << i;
          ++general;
        }
        ++checked;
      }
      EXPECT_EQ(checked, static_cast<int>(dn.size()));
      EXPECT_GT(general, 100);
      EXPECT_LT(general, checked);
      if (enabled) EXPECT_EQ(st.damage, 1.0);
    }
  }
}

// Eq. 9's damage update with the libm call skipped below the damage reached: the same
// bits as max(d, min(1, hypot(en, es))) everywhere, including at and near d.
TEST(CohesiveLaw, MixedModeDamageSkipsHypotOnlyWhereTheMaxKeepsTheOldDamage) {
  auto reference = [](double en, double es, double d) {
    const double e = en == 0.0 ? es : (es == 0.0 ? en : std::hypot(en, es));
    return std::max(d, std::min(1.0, e));
  };
  auto same_bits = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0), angle(0.0, 1.5707963267948966);
  long skipped = 0, raised = 0;
  for (int k = 0; k < 200000; ++k) {
    const double d = k % 50 == 0 ? 0.0 : u(rng);
    // Points around the circle of radius d (some exactly on it, as far as rounding allows),
    // and anywhere in the unit square.
    double en, es;
    if (k % 2 == 0) {
      const double r = d * (1.0 + (u(rng) - 0.5) * (k % 4 == 0 ? 1e-8 : 0.2)), a = angle(rng);
      en = r * std::cos(a);
      es = r * std::sin(a);
    } else {
      en = u(rng);
      es = u(rng);
    }
    if (k % 7 == 0) en = 0.0;
    const double got = std::max(d, std::min(1.0, mixed_mode_damage(en, es, d)));
    ASSERT_TRUE(same_bits(got, reference(en, es, d))) << en << " " << es << " " << d;
    if (en != 0.0 && es != 0.0) (got == d ? skipped : raised) += 1;
  }
  EXPECT_GT(skipped, 30000);
  EXPECT_GT(raised, 30000);
  // Within the margin of the old damage the libm call decides.
  const double d = 0.6;
  for (const double f : {1.0 - 1e-12, 1.0, 1.0 + 1e-12}) {
    const double en = d * f * 0.6, es = d * f * 0.8;
    EXPECT_EQ(mixed_mode_damage(en, es, d), std::hypot(en, es)) << f;
  }
  EXPECT_EQ(mixed_mode_damage(0.3, 0.4, 0.6), 0.6);  // 0.5 < 0.6: no call
  EXPECT_TRUE(std::isnan(mixed_mode_damage(std::nan(""), 0.4, 0.6)));
  EXPECT_EQ(mixed_mode_damage(1e-170, 1e-170, 1e-200), std::hypot(1e-170, 1e-170));  // no underflowed test
}
