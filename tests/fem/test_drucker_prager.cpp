// Verification of the Drucker-Prager return mapping (docs/theory.md §10) on one material
// point driven by the Green strain. Tolerances: the returned stress lies on the cone to 1e-9
// of (k + |alpha I1|); closed forms and flow directions to 1e-9 relative.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fem/cst.hpp"
#include "fem/drucker_prager.hpp"
#include "common/materials.hpp"
#include "model/model.hpp"

using namespace dsdem;
using fem::DruckerPragerRegion;

namespace {

constexpr double kDeg = kPi / 180.0;

double first_invariant(const fem::DruckerPragerResult& r) { return r.S[0] + r.S[1] + r.S_zz; }

// f(S) / (k + |alpha I1|): 0 on the cone, < 0 inside.
double relative_yield(const fem::DruckerPragerModel& m, const fem::DruckerPragerResult& r) {
  return fem::drucker_prager_yield(m, r.S, r.S_zz) / (m.k + std::abs(m.alpha * first_invariant(r)));
}

// The plastic strain increment as a symmetric tensor of the plane-strain point (xx, yy, zz,
// xy with the tensor's xy, half the engineering shear).
std::array<double, 4> increment(const fem::PlasticState& a, const fem::PlasticState& b) {
  return {b.ep_xx - a.ep_xx, b.ep_yy - a.ep_yy, b.ep_zz - a.ep_zz, 0.5 * (b.ep_xy - a.ep_xy)};
}

}  // namespace

TEST(DruckerPrager, ConstantsMatchMohrCoulombInPlaneStrain) {
  const auto el = test::elastic_constants(1e9, 0.25);
  const double c = 1e5, phi = 30 * kDeg;
  const fem::DruckerPragerModel m = fem::make_drucker_prager(c, phi, 10 * kDeg, el);
  const double t = std::tan(phi);
  EXPECT_NEAR(m.alpha, t / std::sqrt(9 + 12 * t * t), 1e-15);
  EXPECT_NEAR(m.k, 3 * c / std::sqrt(9 + 12 * t * t), 1e-9);
  const double tp = std::tan(10 * kDeg);
  EXPECT_NEAR(m.beta, tp / std::sqrt(9 + 12 * tp * tp), 1e-15);
  // phi = 0: von Mises with k = c (Tresca's c in plane strain).
  const fem::DruckerPragerModel vm = fem::make_drucker_prager(c, 0, 0, el);
  EXPECT_EQ(vm.alpha, 0.0);
  EXPECT_DOUBLE_EQ(vm.k, c);
  // A stress on the cone whose flow has no out-of-plane component (associated: s_zz = -2 J
  // alpha, the plane-strain state of steady flow) meets Mohr-Coulomb's envelope in plane:
  // R = c cos(phi) - p sin(phi), R and p the in-plane Mohr circle's radius and centre.
  const fem::DruckerPragerModel a = fem::make_drucker_prager(c, phi, phi, el);
  for (const double p : {-3e5, -1e5, 0.0, 5e4}) {
    // Unknowns R and z = S_zz; Newton on (yield, flow) from a start inside.
    double R = c, z = p;
    for (int it = 0; it < 50; ++it) {
      auto res = [&](double RR, double zz) {
        const Vec3 S(p + RR, p - RR, 0.0);
        const double I1 = 2 * p + zz, mean = I1 / 3;
        const double J = fem::detail::sqrt_j2(S, zz, mean);
        return std::array<double, 2>{J + a.alpha * I1 - a.k, (zz - mean) + 2 * J * a.alpha};
      };
      const auto f = res(R, z);
      const double h = 1e-3;
      const auto fR = res(R + h, z), fz = res(R, z + h);
      const double j11 = (fR[0] - f[0]) / h, j12 = (fz[0] - f[0]) / h, j21 = (fR[1] - f[1]) / h,
                   j22 = (fz[1] - f[1]) / h, det = j11 * j22 - j12 * j21;
      R -= (f[0] * j22 - f[1] * j12) / det;
      z -= (j11 * f[1] - j21 * f[0]) / det;
    }
    EXPECT_NEAR(R, c * std::cos(phi) - p * std::sin(phi), 1e-9 * c) << p;
  }
}

// Below the cone, with no plastic strain: the elastic kernel's stress bits.
TEST(DruckerPrager, BelowTheConeTheStressIsTheElasticKernels) {
  const auto el = test::elastic_constants(2e9, 0.3);
  const fem::DruckerPragerModel m = fem::make_drucker_prager(1e6, 35 * kDeg, 0, el);
  const Vec3 E(1.3e-5, -2.1e-5, 0.7e-5), S0(-2e5, -4e5, 3e4);
  fem::PlasticState start, end;
  const auto r = fem::drucker_prager_update(m, E, S0, 0.0, start, end);
  EXPECT_EQ(r.region, DruckerPragerRegion::Elastic);
  const Vec3 S = S0 + fem::svk_stress(E, el);
  EXPECT_EQ(r.S[0], S[0]);
  EXPECT_EQ(r.S[1], S[1]);
  EXPECT_EQ(r.S[2], S[2]);
  EXPECT_EQ(r.dissipation, 0.0);
  EXPECT_EQ(end.plastic_work, 0.0);
}

// Random strain paths: every update lands inside or on the cone (1e-9), yielded ones on it,
// apex returns at I1 = k / alpha with no deviator; the dissipation is never negative and the
// accumulated plastic work is its sum; the flow follows the potential's gradient
// s / (2 J) + beta 1 (volume over deviator 3 sqrt(2) beta, 1e-9).
TEST(DruckerPrager, RandomStrainPathsStayOnTheConeAndDissipate) {
  const auto el = test::elastic_constants(1e9, 0.3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int cone = 0, apex = 0;
  for (const auto& [phi, psi] : {std::pair{30.0, 0.0}, {30.0, 10.0}, {30.0, 30.0}, {0.0, 0.0}, {45.0, 20.0}}) {
    const double c = 1e5;
    const fem::DruckerPragerModel m = fem::make_drucker_prager(c, phi * kDeg, psi * kDeg, el);
    for (int path = 0; path < 40; ++path) {
      fem::PlasticState st;
      Vec3 E = Vec3::Zero();
      double work = 0.0;
      for (int step = 0; step < 60; ++step) {
        E += 2e-5 * Vec3(u(rng), u(rng), u(rng)) + Vec3(1e-6, 1e-6, 0) * (path % 3 == 0 ? 3.0 : -1.0);
        const fem::PlasticState before = st;
        const auto r = fem::drucker_prager_update(m, E, Vec3::Zero(), 0.0, st, st);
        SCOPED_TRACE(testing::Message() << "phi " << phi << " psi " << psi << " path " << path << " step " << step);
        ASSERT_GE(r.dissipation, 0.0);
        work += r.dissipation;
        EXPECT_DOUBLE_EQ(st.plastic_work, work);
        if (r.region == DruckerPragerRegion::Elastic) {
          EXPECT_LE(relative_yield(m, r), 1e-12);
          continue;
        }
        EXPECT_NEAR(relative_yield(m, r), 0.0, 1e-9);
        const auto d = increment(before, st);
        const double vol = d[0] + d[1] + d[2];
        const double dm = vol / 3;
        const double dev = std::sqrt((d[0] - dm) * (d[0] - dm) + (d[1] - dm) * (d[1] - dm) + (d[2] - dm) * (d[2] - dm) +
                                     2 * d[3] * d[3]);
        if (r.region == DruckerPragerRegion::Apex) {
          ++apex;
          const double I1 = m.k / m.alpha;
          EXPECT_NEAR(first_invariant(r), I1, 1e-9 * std::abs(I1));
          EXPECT_NEAR(r.S[0], I1 / 3, 1e-9 * std::abs(I1));
          EXPECT_NEAR(r.S[2], 0.0, 1e-9 * std::abs(I1));
        } else {
          ++cone;
          EXPECT_NEAR(vol, 3 * std::sqrt(2.0) * m.beta * dev, 1e-9 * dev);
        }
      }
    }
  }
  EXPECT_GT(cone, 100);
  EXPECT_GT(apex, 0);
}

// phi = 0 in plane strain: simple shear from rest flows at the in-plane radius c (Tresca).
TEST(DruckerPrager, SimpleShearAtZeroFrictionFlowsAtTheCohesion) {
  const auto el = test::elastic_constants(1e9, 0.3);
  const double c = 2e5;
  const fem::DruckerPragerModel m = fem::make_drucker_prager(c, 0, 0, el);
  fem::PlasticState st;
  fem::DruckerPragerResult r;
  for (int k = 1; k <= 100; ++k) r = fem::drucker_prager_update(m, Vec3(0, 0, 1e-5 * k), Vec3::Zero(), 0.0, st, st);
  EXPECT_EQ(r.region, DruckerPragerRegion::Cone);
  const double radius = std::hypot(0.5 * (r.S[0] - r.S[1]), r.S[2]);
  EXPECT_NEAR(radius, c, 1e-9 * c);
  // The flow is isochoric and in plane.
  EXPECT_NEAR(st.ep_xx + st.ep_yy + st.ep_zz, 0.0, 1e-15);
  EXPECT_NEAR(st.ep_zz, 0.0, 1e-15);
  // Plastic work: c times the plastic engineering shear.
  EXPECT_NEAR(st.plastic_work, c * st.ep_xy, 1e-9 * c * st.ep_xy);
}

TEST(DruckerPrager, BadParametersGiveAnErrorText) {
  EXPECT_EQ(fem::validate_drucker_prager(1e5, 30 * kDeg, 10 * kDeg, false), "");
  auto has = [](const std::string& s, const char* what) { return s.find(what) != std::string::npos; };
  const std::string two = fem::validate_drucker_prager(-1, 30 * kDeg, 40 * kDeg, false);
  EXPECT_TRUE(has(two, "drucker_prager: ") && has(two, "c must") && has(two, "psi must")) << two;
  EXPECT_TRUE(has(fem::validate_drucker_prager(1e5, 30 * kDeg, 0, true), "plane stress is not supported"));
  EXPECT_TRUE(has(fem::validate_drucker_prager(0, 0, 0, false), "no strength"));
}
