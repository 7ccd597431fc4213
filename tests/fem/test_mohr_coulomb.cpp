// Verification of the Mohr-Coulomb return mapping (docs/theory.md §10) on a single material
// point driven by the Green strain. Tolerances: the returned stress lies on the envelope to
// 1e-9 of (c + |p|); closed forms and flow directions to 1e-9 relative; round-off checks to
// 1e-12 of the stress scale.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "fem/cst.hpp"
#include "fem/mohr_coulomb.hpp"
#include "common/materials.hpp"
#include "model/model.hpp"

using namespace dsdem;
using fem::MohrCoulombRegion;

namespace {

constexpr double kDeg = kPi / 180.0;

fem::MohrCoulombParameters params(double c, double phi_deg, double psi_deg,
                                  double ft = std::numeric_limits<double>::infinity()) {
  fem::MohrCoulombParameters p;
  p.c = c;
  p.phi = phi_deg * kDeg;
  p.psi = psi_deg * kDeg;
  p.ft = ft;
  return p;
}

// One material point: initial stress, state, total strain.
struct Point {
  const fem::MohrCoulombModel& mc;
  Vec3 S0 = Vec3::Zero();
  double S0_zz = 0.0;
  fem::MohrCoulombState state;
  Vec3 E = Vec3::Zero();
  fem::MohrCoulombResult last;

  explicit Point(const fem::MohrCoulombModel& m) : mc(m) {}
  const fem::MohrCoulombResult& go(const Vec3& E_new) {
    E = E_new;
    last = fem::mohr_coulomb_update(mc, E, S0, S0_zz, state, state);
    return last;
  }
};

double mean_stress(const fem::MohrCoulombResult& r) { return (r.S[0] + r.S[1] + r.S_zz) / 3.0; }

// f(S) / (c + |p|): 0 on the envelope, < 0 inside.
double relative_yield(const fem::MohrCoulombModel& mc, double c, const fem::MohrCoulombResult& r) {
  const double f = fem::yield_function(mc, fem::principal_stresses(r.S, r.S_zz));
  const double scale = c + std::abs(mean_stress(r));
  return scale > 0.0 ? f / scale : f;  // c = 0 at the apex: f is 0 there
}

// Principal values (sorted, descending) of a plane-strain Voigt strain (xx, yy, 2xy) and zz.
std::array<double, 3> principal_strains(const Vec3& e, double zz) {
  return fem::principal_stresses(Vec3(e[0], e[1], 0.5 * e[2]), zz);
}

Vec3 ep_of(const fem::MohrCoulombState& s) { return Vec3(s.ep_xx, s.ep_yy, s.ep_xy); }

// S0 + D (E - Ep) in 3D plane strain: (xx, yy, xy) and zz.
std::pair<Vec3, double> elastic_stress(const fem::ElasticConstants& c, const Vec3& E, const Vec3& S0, double S0_zz,
                                       const fem::MohrCoulombState& s) {
  const double exx = E[0] - s.ep_xx, eyy = E[1] - s.ep_yy, gxy = E[2] - s.ep_xy, ezz = -s.ep_zz;
  const double tr = exx + eyy + ezz;
  return {Vec3(S0[0] + c.lambda * tr + 2 * c.mu * exx, S0[1] + c.lambda * tr + 2 * c.mu * eyy, S0[2] + c.mu * gxy),
          S0_zz + c.lambda * tr + 2 * c.mu * ezz};
}

Mat2 tensor(const Vec3& s) {
  Mat2 m;
  m << s[0], s[2], s[2], s[1];
  return m;
}

}  // namespace

// 5. Bad parameters give an error text naming the field.
TEST(MohrCoulomb, BadParametersGiveAnErrorText) {
  EXPECT_EQ(fem::validate(params(1e5, 30, 10)), "");
  EXPECT_EQ(fem::validate(params(1e5, 0, 0, 5e4)), "");
  EXPECT_EQ(fem::validate(params(0, 35, 0)), "");
  EXPECT_EQ(fem::validate(params(1e5, 30, 30, 1e5 / std::tan(30 * kDeg))), "");
  auto has = [](const std::string& s, const char* what) { return s.find(what) != std::string::npos; };
  EXPECT_TRUE(has(fem::validate(params(-1, 30, 0)), "c must be >= 0"));
  EXPECT_TRUE(has(fem::validate(params(1e5, -1, 0)), "phi must be in [0, 90)"));
  EXPECT_TRUE(has(fem::validate(params(1e5, 90, 0)), "phi must be in [0, 90)"));
  EXPECT_TRUE(has(fem::validate(params(1e5, 20, 25)), "psi must be in [0, phi]"));
  EXPECT_TRUE(has(fem::validate(params(1e5, 20, -5)), "psi must be in [0, phi]"));
  EXPECT_TRUE(has(fem::validate(params(1e5, 20, 0, -1)), "ft must be >= 0"));
  EXPECT_TRUE(has(fem::validate(params(1e5, 30, 0, 2e5)), "ft must not exceed c / tan(phi)"));
  EXPECT_TRUE(has(fem::validate(params(0, 0, 0)), "no strength"));
  EXPECT_TRUE(has(fem::validate(params(std::nan(""), 30, 0)), "c must be >= 0"));
  EXPECT_TRUE(has(fem::validate(params(1e5, std::nan(""), 0)), "phi must be"));
  EXPECT_TRUE(has(fem::validate(params(1e5, 30, 0), true), "plane stress is not supported"));
  const std::string two = fem::validate(params(-1, 30, 40));
  EXPECT_TRUE(has(two, "mohr_coulomb: ") && has(two, "c must") && has(two, "psi must")) << two;
}

TEST(MohrCoulomb, StateVariablesAreDeclared) {
  EXPECT_EQ(fem::kMohrCoulombStateVariables.size(), sizeof(fem::MohrCoulombState) / sizeof(double));
  EXPECT_STREQ(fem::kMohrCoulombStateVariables[0].name, "plastic_strain_xx");
  EXPECT_STREQ(fem::kMohrCoulombStateVariables[3].name, "plastic_strain_zz");
  EXPECT_STREQ(fem::kMohrCoulombStateVariables[4].unit, "J/m^3");
}

// Below the envelope the law is the elastic kernel's, bit for bit, stress and energy.
TEST(MohrCoulomb, ElasticPathIsTheElasticKernelsBits) {
  const auto el = test::elastic_constants(20e9, 0.25);
  const auto mc = fem::make_mohr_coulomb(params(1e9, 40, 10), el);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 E(1e-4 * u(rng), 1e-4 * u(rng), 1e-4 * u(rng));
    const Vec3 S0(-1e6 + 1e5 * u(rng), -2e6 + 1e5 * u(rng), 1e5 * u(rng));
    fem::MohrCoulombState st;
    const auto r = fem::mohr_coulomb_update(mc, E, S0, -1e6, st, st);
    ASSERT_FALSE(r.yielded());
    const Vec3 S = S0 + fem::svk_stress(E, el);
    EXPECT_EQ(r.S[0], S[0]);
    EXPECT_EQ(r.S[1], S[1]);
    EXPECT_EQ(r.S[2], S[2]);
    const Vec3 DE = fem::svk_stress(E, el);
    EXPECT_EQ(r.strain_energy, S0.dot(E) + 0.5 * (DE[0] * E[0] + DE[1] * E[1] + DE[2] * E[2]));
    EXPECT_EQ(r.S_zz, -1e6 + el.lambda * (E[0] + E[1]));
    EXPECT_EQ(st.ep_xx, 0.0);
    EXPECT_EQ(st.plastic_work, 0.0);
  }
}

// 4. Plane-strain simple shear of a Tresca material (phi = 0) yields at S_xy = c exactly;
// with psi = 0 the plastic strain is pure shear and the dissipation is c * plastic slip.
TEST(MohrCoulomb, TrescaSimpleShearYieldsAtCohesion) {
  const double c = 1e5;
  const auto el = test::elastic_constants(1.1e8, 0.3);
  const auto mc = fem::make_mohr_coulomb(params(c, 0, 0), el);
  Point pt(mc);
  const double gamma_y = c / el.mu;
  bool yielded = false;
  for (int i = 1; i <= 100; ++i) {
    const double gamma = 1e-4 * i;
    const double gamma_before = pt.E[2];
    const double work_before = pt.state.plastic_work;
    const auto& r = pt.go(Vec3(0, 0, gamma));
    if (gamma <= gamma_y) {
      EXPECT_FALSE(r.yielded()) << i;
      EXPECT_NEAR(r.S[2], el.mu * gamma, 1e-12 * c);
      continue;
    }
    EXPECT_EQ(r.region, MohrCoulombRegion::ShearPlane) << i;
    EXPECT_NEAR(r.S[2], c, 1e-9 * c) << i;
    EXPECT_NEAR(r.S[0], 0.0, 1e-9 * c);
    EXPECT_NEAR(r.S[1], 0.0, 1e-9 * c);
    EXPECT_NEAR(r.S_zz, 0.0, 1e-9 * c);
    EXPECT_NEAR(pt.state.ep_xx, 0.0, 1e-12);
    EXPECT_NEAR(pt.state.ep_yy, 0.0, 1e-12);
    EXPECT_NEAR(pt.state.ep_zz, 0.0, 1e-12);
    EXPECT_NEAR(pt.state.ep_xy, gamma - gamma_y, 1e-9 * gamma);
    const double slip = gamma - std::max(gamma_before, gamma_y);
    EXPECT_NEAR(r.dissipation, c * slip, 1e-9 * c * slip) << i;
    EXPECT_NEAR(pt.state.plastic_work, work_before + r.dissipation, 1e-15 * c);
    yielded = true;
  }
  EXPECT_TRUE(yielded);
  EXPECT_NEAR(pt.state.plastic_work, c * (0.01 - gamma_y), 1e-9 * c * 0.01);
}

namespace {

// Biaxial plane-strain compression under a constant lateral stress -pc: S_xx = -pc held by
// bisection on E_xx, E_yy driven down.
struct Biaxial {
  Point pt;
  double pc;
  Biaxial(const fem::MohrCoulombModel& mc, double p) : pt(mc), pc(p) {
    pt.S0 = Vec3(-pc, -pc, 0);
    pt.S0_zz = -pc;
  }
  const fem::MohrCoulombResult& go(double Eyy) {
    double lo = pt.E[0] - 0.05, hi = pt.E[0] + 0.05;
    fem::MohrCoulombState scratch;
    for (int it = 0; it < 200 && hi - lo > 0.0; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (mid == lo || mid == hi) break;
      const auto r = fem::mohr_coulomb_update(pt.mc, Vec3(mid, Eyy, 0), pt.S0, pt.S0_zz, pt.state, scratch);
      (r.S[0] + pc > 0.0 ? hi : lo) = mid;
    }
    return pt.go(Vec3(0.5 * (lo + hi), Eyy, 0));
  }
};

}  // namespace

// 4. Biaxial compression with phi > 0 reaches the Mohr-Coulomb peak
// s_axial = -(pc tan^2(45 + phi/2) + 2 c tan(45 + phi/2)) and stays there (perfect
// plasticity); unloading leaves the envelope inward; loading along the yield plane stays on
// it without plastic flow.
TEST(MohrCoulomb, BiaxialCompressionReachesTheMohrCoulombPeak) {
  const double c = 50e3, phi = 30, pc = 200e3;
  const auto el = test::elastic_constants(100e6, 0.3);
  const auto mc = fem::make_mohr_coulomb(params(c, phi, 10), el);
  const double t = std::tan((45 + phi / 2) * kDeg);
  const double peak = -(pc * t * t + 2 * c * t);
  Biaxial b(mc, pc);
  bool yielded = false;
  for (int i = 1; i <= 400; ++i) {
    const auto& r = b.go(-5e-5 * i);
    ASSERT_NEAR(r.S[0], -pc, 1e-9 * pc);
    EXPECT_LE(relative_yield(mc, c, r), 1e-9);
    if (!r.yielded()) {
      EXPECT_FALSE(yielded) << "elastic again under monotonic loading at " << i;
      EXPECT_GT(r.S[1], peak);
      continue;
    }
    yielded = true;
    EXPECT_EQ(r.region, MohrCoulombRegion::ShearPlane) << i;
    EXPECT_NEAR(r.S[1], peak, 1e-9 * std::abs(peak)) << i;
    EXPECT_NEAR(relative_yield(mc, c, r), 0.0, 1e-9);
    EXPECT_GT(r.S_zz, r.S[1]);  // intermediate principal stress
    EXPECT_LT(r.S_zz, r.S[0]);
    EXPECT_GT(r.dissipation, 0.0);
  }
  ASSERT_TRUE(yielded);

  // Tangential loading on the yield plane k s1 - s3 = sc with s1 = S_xx, s3 = S_yy:
  // dE = (dx, dy) with k dS_xx - dS_yy = 0.
  const fem::MohrCoulombState on = b.pt.state;
  const double L = el.lambda, M2 = el.lambda + 2 * el.mu, k = mc.k;
  const double dy = -1e-5, dx = dy * (M2 - k * L) / (k * M2 - L);
  Point& pt = b.pt;
  for (int i = 0; i < 50; ++i) {
    const auto& r = pt.go(pt.E + Vec3(dx, dy, 0));
    EXPECT_NEAR(relative_yield(mc, c, r), 0.0, 1e-9) << i;
    EXPECT_LE(r.dissipation, 1e-12 * c) << i;
  }
  EXPECT_NEAR(pt.state.ep_xx, on.ep_xx, 1e-12);
  EXPECT_NEAR(pt.state.ep_yy, on.ep_yy, 1e-12);
  EXPECT_NEAR(pt.state.ep_zz, on.ep_zz, 1e-12);

  // Unloading: the axial strain goes back under the same lateral stress, the point moves
  // inside.
  b.pc = -pt.last.S[0];
  double f_prev = relative_yield(mc, c, pt.last);
  for (int i = 0; i < 10; ++i) {
    const auto& r = b.go(pt.E[1] + 1e-5);
    EXPECT_FALSE(r.yielded());
    const double f = relative_yield(mc, c, r);
    EXPECT_LT(f, f_prev);
    f_prev = f;
  }
  EXPECT_LT(f_prev, -1e-3);
}

// 2. Flow direction on the shear plane (biaxial compression: s1 = S_xx, s2 = S_zz,
// s3 = S_yy): the plastic strain increment is dl (m, 0, -1) in (xx, zz, yy) with
// m = (1 + sin psi) / (1 - sin psi), so dEp_vol = sin(psi) (dEp_1 - dEp_3): psi = 0 keeps
// the plastic volume, psi = phi is the normal of the yield plane (k, 0, -1).
TEST(MohrCoulomb, PlasticFlowFollowsTheDilationAngle) {
  const double c = 50e3, phi = 30, pc = 200e3;
  const auto el = test::elastic_constants(100e6, 0.3);
  for (double psi : {0.0, 10.0, 30.0}) {
    const auto mc = fem::make_mohr_coulomb(params(c, phi, psi), el);
    Biaxial b(mc, pc);
    int checked = 0;
    for (int i = 1; i <= 300; ++i) {
      const fem::MohrCoulombState before = b.pt.state;
      const auto& r = b.go(-5e-5 * i);
      if (!r.yielded()) continue;
      ASSERT_EQ(r.region, MohrCoulombRegion::ShearPlane);
      const double dxx = b.pt.state.ep_xx - before.ep_xx, dyy = b.pt.state.ep_yy - before.ep_yy;
      const double dzz = b.pt.state.ep_zz - before.ep_zz, dxy = b.pt.state.ep_xy - before.ep_xy;
      ASSERT_GT(dxx, 0.0);
      ASSERT_LT(dyy, 0.0);
      const double size = dxx - dyy;
      EXPECT_NEAR(dzz, 0.0, 1e-9 * size);
      EXPECT_NEAR(dxy, 0.0, 1e-9 * size);
      EXPECT_NEAR(dxx + dyy + dzz, std::sin(psi * kDeg) * size, 1e-9 * size) << psi;
      EXPECT_NEAR(dxx / -dyy, mc.m, 1e-9 * mc.m) << psi;
      if (psi == phi) {
        EXPECT_NEAR(dxx / -dyy, mc.k, 1e-9 * mc.k);
      }
      if (psi == 0.0) {
        EXPECT_NEAR(dxx + dyy + dzz, 0.0, 1e-9 * size);
      }
      ++checked;
    }
    EXPECT_GT(checked, 100) << psi;
  }
}

// The in-situ out-of-plane stress of an elastic stage: what the law gives from zero.
TEST(MohrCoulomb, PlaneStrainSigmaZzOfAnElasticState) {
  const auto el = test::elastic_constants(100e6, 0.3);
  const auto mc = fem::make_mohr_coulomb(params(1e9, 30, 0), el);
  fem::MohrCoulombState st;
  const auto r = fem::mohr_coulomb_update(mc, Vec3(-1e-3, -3e-3, 5e-4), Vec3::Zero(), 0.0, st, st);
  ASSERT_FALSE(r.yielded());
  EXPECT_NEAR(fem::plane_strain_sigma_zz(r.S, el), r.S_zz, 1e-12 * std::abs(r.S_zz));
}

// 1. Confined (oedometric) compression: S_xx = S_zz, the point yields on the triaxial
// compression edge and moves along it; unloading goes inside.
TEST(MohrCoulomb, OedometricCompressionFollowsTheCompressionEdge) {
  const double c = 20e3;
  const auto el = test::elastic_constants(50e6, 0.2);
  for (double psi : {0.0, 15.0, 30.0}) {
    const auto mc = fem::make_mohr_coulomb(params(c, 30, psi), el);
    Point pt(mc);
    bool yielded = false;
    for (int i = 1; i <= 300; ++i) {
      const auto& r = pt.go(Vec3(0, -2e-4 * i, 0));
      const double f = relative_yield(mc, c, r);
      EXPECT_LE(f, 1e-9);
      if (!r.yielded()) {
        EXPECT_FALSE(yielded);
        continue;
      }
      if (!yielded) {
        EXPECT_EQ(r.region, MohrCoulombRegion::ShearEdgeCompression) << psi;
      }
      yielded = true;
      EXPECT_NEAR(f, 0.0, 1e-9) << psi << " " << i;
      const auto s = fem::principal_stresses(r.S, r.S_zz);
      EXPECT_NEAR(s[0], s[1], 1e-9 * (c + std::abs(s[2])));
    }
    EXPECT_TRUE(yielded) << psi;
    const auto& r = pt.go(pt.E + Vec3(0, 1e-4, 0));
    EXPECT_FALSE(r.yielded());
    EXPECT_LT(relative_yield(mc, c, r), -1e-4);
  }
}

// 1. Extension from an isotropic state: S_yy = S_zz, the triaxial extension edge.
TEST(MohrCoulomb, ExtensionFromIsotropicStateFollowsTheExtensionEdge) {
  const double c = 20e3, p0 = 300e3;
  const auto el = test::elastic_constants(50e6, 0.3);
  const auto mc = fem::make_mohr_coulomb(params(c, 25, 5), el);
  Point pt(mc);
  pt.S0 = Vec3(-p0, -p0, 0);
  pt.S0_zz = -p0;
  int on_edge = 0;
  for (int i = 1; i <= 300; ++i) {
    const auto& r = pt.go(Vec3(2e-4 * i, 0, 0));
    EXPECT_LE(relative_yield(mc, c, r), 1e-9);
    if (!r.yielded()) continue;
    EXPECT_NEAR(relative_yield(mc, c, r), 0.0, 1e-9);
    const auto s = fem::principal_stresses(r.S, r.S_zz);
    EXPECT_NEAR(s[1], s[2], 1e-9 * (c + std::abs(s[2])));
    on_edge += r.region == MohrCoulombRegion::ShearEdgeExtension;
  }
  EXPECT_GT(on_edge, 0);
}

// 1. In-plane biaxial extension climbs the compression edge to the apex c / tan(phi).
TEST(MohrCoulomb, BiaxialExtensionReachesTheApex) {
  const double c = 50e3;
  const auto el = test::elastic_constants(100e6, 0.3);
  for (double psi : {5.0, 30.0}) {
    const auto mc = fem::make_mohr_coulomb(params(c, 30, psi), el);
    const double apex = c / std::tan(30 * kDeg);
    Point pt(mc);
    bool apex_reached = false;
    for (int i = 1; i <= 400; ++i) {
      const auto& r = pt.go(Vec3(1e-4 * i, 1e-4 * i, 0));
      EXPECT_LE(relative_yield(mc, c, r), 1e-9) << i;
      if (r.yielded()) {
        EXPECT_NEAR(relative_yield(mc, c, r), 0.0, 1e-9) << i;
      }
      if (r.region == MohrCoulombRegion::ShearApex) {
        apex_reached = true;
        EXPECT_NEAR(r.S[0], apex, 1e-9 * apex);
        EXPECT_NEAR(r.S[1], apex, 1e-9 * apex);
        EXPECT_NEAR(r.S[2], 0.0, 1e-9 * apex);
        EXPECT_NEAR(r.S_zz, apex, 1e-9 * apex);
      } else if (apex_reached) {
        ADD_FAILURE() << "left the apex under continued extension at " << i;
      }
    }
    EXPECT_TRUE(apex_reached) << psi;
  }
}

// 1. Tension cut-off: uniaxial extension returns to s1 = ft, biaxial to s1 = s2 = ft (the
// plastic flow in x and y then holds S_zz below ft); a large step with S_zz near ft brings
// all three to ft; in-plane shear with dilation reaches the cut-off, then the line where it
// meets the shear plane, then slides down the shear plane.
TEST(MohrCoulomb, ExtensionIntoTheTensionCutoff) {
  const double c = 50e3, ft = 20e3;
  const auto el = test::elastic_constants(100e6, 0.3);
  const auto mc = fem::make_mohr_coulomb(params(c, 30, 10, ft), el);
  using R = MohrCoulombRegion;
  struct Path {
    Vec3 dE;
    double S0_zz;
    std::vector<R> visits;
  };
  for (const Path& path : {Path{Vec3(1e-5, 0, 0), 0.0, {R::TensionPlane}},
                           Path{Vec3(1e-5, 1e-5, 0), 0.0, {R::TensionEdge}},
                           Path{Vec3(1e-3, 1e-3, 0), 0.95 * ft, {R::TensionApex}},
                           Path{Vec3(1.2e-5, -1.2e-5, 1.6e-5), 0.0,
                                {R::TensionPlane, R::ShearTensionLine, R::ShearPlane}}}) {
    Point pt(mc);
    pt.S0_zz = path.S0_zz;
    std::vector<R> seen;
    for (int i = 1; i <= 200; ++i) {
      const auto& r = pt.go(pt.E + path.dE);
      EXPECT_LE(relative_yield(mc, c, r), 1e-9);
      if (!r.yielded()) continue;
      EXPECT_NEAR(relative_yield(mc, c, r), 0.0, 1e-9);
      if (seen.empty() || seen.back() != r.region) seen.push_back(r.region);
      const auto s = fem::principal_stresses(r.S, r.S_zz);
      if (r.region != R::ShearPlane) {
        EXPECT_NEAR(s[0], ft, 1e-9 * c);
      }
      if (r.region == R::TensionEdge) {
        EXPECT_NEAR(s[1], ft, 1e-9 * c);
      }
      if (path.S0_zz > 0.0) {  // stays at (ft, ft, ft): a later step may name it the edge
        EXPECT_NEAR(s[1], ft, 1e-9 * c);
        EXPECT_NEAR(s[2], ft, 1e-9 * c);
      }
    }
    std::string names;
    for (R r : seen) names += std::string(fem::to_string(r)) + " ";
    if (path.S0_zz > 0.0)
      EXPECT_EQ(seen.front(), R::TensionApex) << names;
    else
      EXPECT_EQ(seen, path.visits) << names;
  }
}

// 1-3. Random paths (seeded) through every region: each update stays admissible, a yielded
// stress lies on the envelope, the state reproduces the stress (S = S0 + D (E - Ep)), the
// plastic strain increment follows the potential with the dilation angle, the dissipation
// is >= 0 and is S : dEp.
TEST(MohrCoulomb, RandomPathsStayOnTheEnvelopeAndDissipate) {
  const auto el = test::elastic_constants(80e6, 0.28);
  struct Case {
    fem::MohrCoulombParameters p;
    std::size_t regions;  // regions (elastic included) the walks visit at least
  };
  const Case cases[] = {
      {params(50e3, 30, 10), 5},       {params(50e3, 30, 30), 5},        {params(50e3, 30, 0), 5},
      {params(50e3, 30, 10, 20e3), 8}, {params(50e3, 35, 35, 0.0), 6},   {params(80e3, 0, 0, 40e3), 8},
      {params(80e3, 0, 0), 4},         {params(0, 35, 5), 5},
  };
  std::set<MohrCoulombRegion> all_seen;
  std::mt19937_64 rng(20261203);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int updates = 0;
  for (const Case& cs : cases) {
    const auto mc = fem::make_mohr_coulomb(cs.p, el);
    const double c = cs.p.c;
    const double sinpsi = std::sin(cs.p.psi);
    std::map<MohrCoulombRegion, int> seen;
    for (int path = 0; path < 40; ++path) {
      Point pt(mc);
      const double p0 = 200e3 * (u(rng) + 1.0);
      pt.S0 = Vec3(-p0 + 50e3 * u(rng), -p0 + 50e3 * u(rng), 30e3 * u(rng));
      pt.S0_zz = -p0 + 50e3 * u(rng);
      // Random direction per leg; step sizes from small to large so that trial stresses land
      // far beyond the lines and corners too.
      for (int leg = 0; leg < 10; ++leg) {
        const Vec3 dir(u(rng), u(rng), u(rng));
        const double h = std::pow(10.0, -5.0 + 3.0 * (u(rng) + 1.0) / 2.0);
        for (int i = 0; i < 20; ++i, ++updates) {
          const fem::MohrCoulombState before = pt.state;
          const auto [S_trial, S_trial_zz] = elastic_stress(el, pt.E + h * dir, pt.S0, pt.S0_zz, before);
          const auto& r = pt.go(pt.E + h * dir);
          const double f = relative_yield(mc, c, r);
          ASSERT_LE(f, 1e-9) << fem::to_string(r.region);
          if (r.yielded()) {
            ASSERT_NEAR(f, 0.0, 1e-9) << fem::to_string(r.region);
          }
          seen[r.region]++;
          // The state reproduces the stress.
          const auto [S, S_zz] = elastic_stress(el, pt.E, pt.S0, pt.S0_zz, pt.state);
          const double big = std::abs(S_trial[0]) + std::abs(S_trial[1]) + std::abs(S_trial[2]) +
                             std::abs(S_trial_zz) + c;
          ASSERT_NEAR(S[0], r.S[0], 1e-12 * big);
          ASSERT_NEAR(S[1], r.S[1], 1e-12 * big);
          ASSERT_NEAR(S[2], r.S[2], 1e-12 * big);
          ASSERT_NEAR(S_zz, r.S_zz, 1e-12 * big);
          if (!r.yielded()) {
            ASSERT_EQ(r.dissipation, 0.0);
            continue;
          }
          // Dissipation >= 0, and it is S : dEp in Voigt form (engineering shear).
          const Vec3 dEp = ep_of(pt.state) - ep_of(before);
          const double dEp_zz = pt.state.ep_zz - before.ep_zz;
          const double sdep = r.S.dot(dEp) + r.S_zz * dEp_zz;
          const double dep_norm = dEp.norm() + std::abs(dEp_zz);
          ASSERT_GE(r.dissipation, 0.0);
          ASSERT_NEAR(r.dissipation, sdep, 1e-10 * big * dep_norm);
          ASSERT_NEAR(pt.state.plastic_work, before.plastic_work + r.dissipation, 1e-15 * pt.state.plastic_work + 1e-300);
          // Coaxial: the in-plane plastic strain increment commutes with the stress.
          const Mat2 St = tensor(r.S), Et = tensor(Vec3(dEp[0], dEp[1], 0.5 * dEp[2]));
          ASSERT_LE((St * Et - Et * St).norm(), 1e-9 * St.norm() * Et.norm() + 1e-12 * big * dep_norm);
          // 2. Flow direction: for the shear plane and edges the plastic potentials
          // m s_max - s_min give dEp_vol = sin(psi) * sum |dEp_i| (principal values).
          if (r.region == MohrCoulombRegion::ShearPlane || r.region == MohrCoulombRegion::ShearEdgeCompression ||
              r.region == MohrCoulombRegion::ShearEdgeExtension) {
            const auto e = principal_strains(dEp, dEp_zz);
            const double sum_abs = std::abs(e[0]) + std::abs(e[1]) + std::abs(e[2]);
            ASSERT_NEAR(e[0] + e[1] + e[2], sinpsi * sum_abs, 1e-9 * sum_abs) << fem::to_string(r.region);
          }
          if (r.region == MohrCoulombRegion::TensionPlane) {
            // Associated with s1 <= ft: only the major principal plastic strain moves.
            const auto e = principal_strains(dEp, dEp_zz);
            ASSERT_GT(e[0], 0.0);
            ASSERT_NEAR(e[1], 0.0, 1e-9 * e[0]);
            ASSERT_NEAR(e[2], 0.0, 1e-9 * e[0]);
          }
        }
      }
    }
    std::string list;
    for (const auto& [region, n] : seen) {
      list += std::string(fem::to_string(region)) + " " + std::to_string(n) + ", ";
      all_seen.insert(region);
    }
    EXPECT_GE(seen.size(), cs.regions) << list;
  }
  EXPECT_EQ(all_seen.size(), 11u);  // every region, the elastic one included
  EXPECT_GE(updates, 50000);
}

// A single return from random trial stresses far outside: every region is reached from
// fresh states, and the returned point is the one the region names (to 1e-9 of c + |p|),
// for friction angles from 0.1 to 60 deg, cut-offs from 0 to the apex.
TEST(MohrCoulomb, RandomTrialStressesReturnToTheNamedFeature) {
  const auto el = test::elastic_constants(80e6, 0.28);
  struct Case {
    fem::MohrCoulombParameters p;
    std::size_t regions;  // regions reached, the elastic one included
  };
  // With a cut-off every region but the cone's apex; a cut-off just below the apex leaves
  // too small a target for the tension plane, edge and the shear-tension line.
  const Case cases[] = {
      {params(50e3, 30, 10, 20e3), 10}, {params(50e3, 30, 10), 5},         {params(80e3, 0, 0, 0.0), 10},
      {params(50e3, 0.1, 0.05), 4},     {params(50e3, 60, 0, 5e3), 10},    {params(20e3, 45, 45, 1e3), 10},
      {params(0, 40, 10), 5},           {params(50e3, 30, 10, 0.999 * 50e3 / std::tan(30 * kDeg)), 7},
  };
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Case& cs : cases) {
    const auto mc = fem::make_mohr_coulomb(cs.p, el);
    const double c = cs.p.c, ft = mc.ft;
    const double apex_line = mc.k * ft - mc.sc;  // s3 where the cut-off meets the shear plane
    std::map<MohrCoulombRegion, int> seen;
    for (int i = 0; i < 20000; ++i) {
      const Vec3 E(2e-3 * u(rng), 2e-3 * u(rng), 2e-3 * u(rng));
      const Vec3 S0(-200e3 * (1 + u(rng)), -200e3 * (1 + u(rng)), 50e3 * u(rng));
      const double S0_zz = 200e3 * u(rng);
      fem::MohrCoulombState st;
      const auto r = fem::mohr_coulomb_update(mc, E, S0, S0_zz, st, st);
      seen[r.region]++;
      const auto s = fem::principal_stresses(r.S, r.S_zz);
      const double tol = 1e-9 * (c + std::abs(mean_stress(r)));
      ASSERT_LE(fem::yield_function(mc, s), tol);
      using R = MohrCoulombRegion;
      const bool s12 = std::abs(s[0] - s[1]) <= tol, s23 = std::abs(s[1] - s[2]) <= tol;
      const bool t1 = std::abs(s[0] - ft) <= tol, shear = std::abs(mc.k * s[0] - s[2] - mc.sc) <= mc.k * tol;
      const bool corner = std::abs(s[2] - apex_line) <= mc.k * tol;
      switch (r.region) {
        case R::Elastic: break;
        case R::ShearPlane: EXPECT_TRUE(shear); break;
        case R::ShearEdgeCompression: EXPECT_TRUE(shear && s12); break;
        case R::ShearEdgeExtension: EXPECT_TRUE(shear && s23); break;
        case R::ShearApex: EXPECT_TRUE(!mc.cutoff && s12 && s23 && std::abs(s[0] - mc.apex) <= tol); break;
        case R::TensionPlane: EXPECT_TRUE(t1); break;
        case R::TensionEdge: EXPECT_TRUE(t1 && s12); break;
        case R::TensionApex: EXPECT_TRUE(t1 && s12 && s23); break;
        case R::ShearTensionLine: EXPECT_TRUE(t1 && shear); break;
        case R::ShearTensionCompression: EXPECT_TRUE(t1 && s12 && corner); break;
        case R::ShearTensionExtension: EXPECT_TRUE(t1 && s23 && corner); break;
      }
      ASSERT_GE(r.dissipation, 0.0);
    }
    std::string list;
    for (const auto& [region, n] : seen) list += std::string(fem::to_string(region)) + " " + std::to_string(n) + ", ";
    EXPECT_EQ(seen.size(), cs.regions) << list;
  }
}

// 3. The energy ledger closes: in each step the work of the midpoint stress on the strain
// increment equals the change of the stored energy plus the booked dissipation, to an
// error 0.5 dS : dEp of second order in the step (the dissipation is booked at the
// returned stress), so the summed error falls tenfold for ten times smaller steps. The
// stored energy is S0 : Ee + Ee : D : Ee / 2 of the state.
TEST(MohrCoulomb, EnergyBalanceClosesAsTheStepShrinks) {
  const auto el = test::elastic_constants(80e6, 0.28);
  const auto mc = fem::make_mohr_coulomb(params(50e3, 30, 10, 20e3), el);
  auto error = [&](int n) {
    Point pt(mc);
    pt.S0 = Vec3(-300e3, -200e3, 20e3);
    pt.S0_zz = -250e3;
    double work = 0.0, error_sum = 0.0, psi_prev = 0.0;
    Vec3 S_prev = pt.S0;
    for (int i = 1; i <= n; ++i) {
      // A curved path through shear, extension and compression.
      const double t = double(i) / n;
      const Vec3 E(4e-3 * std::sin(3 * t), -3e-3 * t + 2e-3 * std::sin(5 * t), 6e-3 * t * t);
      const Vec3 dE = E - pt.E;
      const auto& r = pt.go(E);
      const double w = 0.5 * (S_prev + r.S).dot(dE);  // no work on the zero E_zz
      work += w;
      error_sum += std::abs(w - (r.strain_energy - psi_prev) - r.dissipation);
      S_prev = r.S;
      psi_prev = r.strain_energy;
      // Stored energy of the state, independently.
      const double exx = E[0] - pt.state.ep_xx, eyy = E[1] - pt.state.ep_yy, g = E[2] - pt.state.ep_xy;
      const double ezz = -pt.state.ep_zz, tr = exx + eyy + ezz;
      const double psi = pt.S0.dot(Vec3(exx, eyy, g)) + pt.S0_zz * ezz +
                         0.5 * (el.lambda * tr * tr + 2 * el.mu * (exx * exx + eyy * eyy + ezz * ezz) + el.mu * g * g);
      EXPECT_NEAR(r.strain_energy, psi, 1e-9 * (std::abs(psi) + 1.0));
    }
    EXPECT_GT(pt.state.plastic_work, 0.01 * work);
    EXPECT_NEAR(std::abs(work - pt.last.strain_energy - pt.state.plastic_work), 0.0, error_sum + 1e-12 * work);
    return error_sum / std::abs(work);
  };
  const double e1 = error(200), e2 = error(2000), e3 = error(20000);
  EXPECT_LT(e2, 0.2 * e1) << e1 << " " << e2;
  EXPECT_LT(e3, 0.2 * e2) << e2 << " " << e3;
  EXPECT_LT(e3, 1e-6) << e1 << " " << e2 << " " << e3;
}

// Evaluating again from the end state with the same strain (stress on demand, a repeated
// evaluation) gives the same stress and no further plastic flow, up to round-off.
TEST(MohrCoulomb, ReturnedStateIsAFixedPoint) {
  const auto el = test::elastic_constants(80e6, 0.28);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const auto& p : {params(50e3, 30, 10), params(50e3, 30, 10, 20e3), params(80e3, 0, 0, 40e3)}) {
    const auto mc = fem::make_mohr_coulomb(p, el);
    int plastic = 0;
    for (int i = 0; i < 5000; ++i) {
      const Vec3 E(2e-3 * u(rng), 2e-3 * u(rng), 2e-3 * u(rng));
      const Vec3 S0(-200e3 * (1 + u(rng)), -200e3 * (1 + u(rng)), 50e3 * u(rng));
      const double S0_zz = 200e3 * u(rng);
      fem::MohrCoulombState st, again;
      const auto r = fem::mohr_coulomb_update(mc, E, S0, S0_zz, st, st);
      const auto r2 = fem::mohr_coulomb_update(mc, E, S0, S0_zz, st, again);
      plastic += r.yielded();
      const double scale = 1e-12 * (r.S.norm() + std::abs(r.S_zz) + p.c + 400e3);
      EXPECT_NEAR(r2.S[0], r.S[0], scale);
      EXPECT_NEAR(r2.S[1], r.S[1], scale);
      EXPECT_NEAR(r2.S[2], r.S[2], scale);
      EXPECT_NEAR(r2.S_zz, r.S_zz, scale);
      EXPECT_NEAR(again.ep_xx, st.ep_xx, 1e-15);
      EXPECT_NEAR(again.ep_zz, st.ep_zz, 1e-15);
      EXPECT_LE(r2.dissipation, 1e-12 * p.c * 1e-3);
    }
    EXPECT_GT(plastic, 1000);
  }
}

// The law is objective in the plane: rotating E, S0 and the plastic strain rotates S.
TEST(MohrCoulomb, RotatedInputsGiveTheRotatedStress) {
  const auto el = test::elastic_constants(80e6, 0.28);
  const auto mc = fem::make_mohr_coulomb(params(50e3, 30, 10, 20e3), el);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto rot = [](const Vec3& v, double th, bool strain) {
    Mat2 R;
    R << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
    const double h = strain ? 0.5 : 1.0;
    Mat2 m;
    m << v[0], h * v[2], h * v[2], v[1];
    const Mat2 r = R * m * R.transpose();
    return Vec3(r(0, 0), r(1, 1), r(0, 1) / h);
  };
  for (int i = 0; i < 500; ++i) {
    const Vec3 E(2e-3 * u(rng), 2e-3 * u(rng), 2e-3 * u(rng));
    const Vec3 S0(-200e3 * (1 + u(rng)), -200e3 * (1 + u(rng)), 50e3 * u(rng));
    fem::MohrCoulombState a;
    a.ep_xx = 1e-4 * u(rng), a.ep_yy = 1e-4 * u(rng), a.ep_xy = 1e-4 * u(rng), a.ep_zz = 1e-4 * u(rng);
    const double th = kPi * u(rng);
    fem::MohrCoulombState b = a;
    const Vec3 epr = rot(Vec3(a.ep_xx, a.ep_yy, a.ep_xy), th, true);
    b.ep_xx = epr[0], b.ep_yy = epr[1], b.ep_xy = epr[2];
    fem::MohrCoulombState a1, b1;
    const auto ra = fem::mohr_coulomb_update(mc, E, S0, -100e3, a, a1);
    const auto rb = fem::mohr_coulomb_update(mc, rot(E, th, true), rot(S0, th, false), -100e3, b, b1);
    const Vec3 expect = rot(ra.S, th, false);
    const double scale = 1e-9 * (std::abs(ra.S_zz) + ra.S.norm() + 50e3);
    EXPECT_EQ(ra.region, rb.region);
    EXPECT_NEAR(rb.S[0], expect[0], scale);
    EXPECT_NEAR(rb.S[1], expect[1], scale);
    EXPECT_NEAR(rb.S[2], expect[2], scale);
    EXPECT_NEAR(rb.S_zz, ra.S_zz, scale);
    EXPECT_NEAR(b1.ep_zz, a1.ep_zz, 1e-12);
    EXPECT_NEAR(rb.dissipation, ra.dissipation, 1e-9 * (ra.dissipation + 1.0));
    const Vec3 ep_expect = rot(Vec3(a1.ep_xx, a1.ep_yy, a1.ep_xy), th, true);
    EXPECT_NEAR(b1.ep_xx, ep_expect[0], 1e-12);
    EXPECT_NEAR(b1.ep_yy, ep_expect[1], 1e-12);
    EXPECT_NEAR(b1.ep_xy, ep_expect[2], 1e-12);
  }
}
