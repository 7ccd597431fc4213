// The plastic laws at the tetrahedron's point (docs/theory.md §10): Mohr-Coulomb's return
// in principal stresses and Drucker-Prager's cone on the six stress components. Stress
// paths land on and stay on the surface (1e-9 of c + |p|), at its planes, edges and apex;
// the dissipation is never negative; a plane-strain path gives the 2D law's stress (1e-9);
// a rotated path gives the rotated stress (isotropy, 1e-9).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "fem/drucker_prager.hpp"
#include "fem/mohr_coulomb.hpp"
#include "common/materials.hpp"
#include "model/model.hpp"

using namespace dsdem;
using fem::Vec6;

namespace {

constexpr double kDeg = kPi / 180.0;

fem::MohrCoulombModel mohr_coulomb(double c, double phi, double psi, double ft = std::numeric_limits<double>::infinity()) {
  return fem::make_mohr_coulomb({c, phi * kDeg, psi * kDeg, ft}, test::elastic_constants(1e9, 0.3));
}

std::array<double, 3> principal(const Vec6& S) {
  const Eigen::SelfAdjointEigenSolver<Mat3> e(fem::detail::to_tensor(S));
  return {e.eigenvalues()[2], e.eigenvalues()[1], e.eigenvalues()[0]};
}

double mean(const Vec6& S) { return (S[0] + S[1] + S[2]) / 3.0; }

// The strain (engineering shears) R E R^T of a Voigt strain.
Vec6 rotate_strain(const Mat3& R, const Vec6& e) {
  Vec6 t = e;
  t[3] *= 0.5, t[4] *= 0.5, t[5] *= 0.5;
  const Mat3 m = R * fem::detail::to_tensor(t) * R.transpose();
  Vec6 out;
  out << m(0, 0), m(1, 1), m(2, 2), 2 * m(1, 2), 2 * m(0, 2), 2 * m(0, 1);
  return out;
}
Vec6 rotate_stress(const Mat3& R, const Vec6& s) {
  const Mat3 m = R * fem::detail::to_tensor(s) * R.transpose();
  Vec6 out;
  out << m(0, 0), m(1, 1), m(2, 2), m(1, 2), m(0, 2), m(0, 1);
  return out;
}

}  // namespace

TEST(MohrCoulomb3D, RandomPathsStayOnTheSurfaceAtPlanesEdgesAndApex) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::map<fem::MohrCoulombRegion, int> seen;
  struct Case {
    double c, phi, psi, ft;
  };
  const double inf = std::numeric_limits<double>::infinity();
  for (const Case& cs : {Case{1e5, 30, 0, inf}, Case{1e5, 30, 30, inf}, Case{1e5, 35, 10, 5e4}, Case{2e5, 0, 0, inf},
                         Case{5e4, 40, 15, 2e4}}) {
    const fem::MohrCoulombModel mc = mohr_coulomb(cs.c, cs.phi, cs.psi, cs.ft);
    for (int path = 0; path < 60; ++path) {
      fem::PlasticState3D st;
      Vec6 E = Vec6::Zero();
      // Some paths pull apart (tension, the cut-off and the apex), some squeeze, all shear.
      const double bias = path % 3 == 0 ? 3e-6 : (path % 3 == 1 ? -1e-6 : 0.0);
      double work = 0.0;
      for (int step = 0; step < 50; ++step) {
        for (int q = 0; q < 6; ++q) E[q] += 2e-5 * u(rng) + (q < 3 ? bias : 0.0);
        const fem::PlasticState3D before = st;
        const auto r = fem::mohr_coulomb_update_3d(mc, E, Vec6::Zero(), st, st);
        SCOPED_TRACE(testing::Message() << "c " << cs.c << " phi " << cs.phi << " path " << path << " step " << step);
        ASSERT_GE(r.dissipation, 0.0);
        work += r.dissipation;
        EXPECT_DOUBLE_EQ(st.plastic_work, work);
        const double f = fem::yield_function(mc, principal(r.S)) / (cs.c + std::abs(mean(r.S)));
        ++seen[r.region];
        if (r.region == fem::MohrCoulombRegion::Elastic) {
          EXPECT_LE(f, 1e-12);
          EXPECT_EQ(st.ep, before.ep);
        } else {
          EXPECT_NEAR(f, 0.0, 1e-9);
        }
      }
    }
  }
  for (const auto r : {fem::MohrCoulombRegion::ShearPlane, fem::MohrCoulombRegion::ShearEdgeCompression,
                       fem::MohrCoulombRegion::ShearEdgeExtension, fem::MohrCoulombRegion::ShearApex,
                       fem::MohrCoulombRegion::TensionPlane})
    EXPECT_GT(seen[r], 0) << fem::to_string(r);
}

// A plane-strain path (E_zz = E_yz = E_xz = 0) gives the 2D law's stress and plastic strain.
TEST(MohrCoulomb3D, PlaneStrainPathGivesThePlaneStrainLaw) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const fem::MohrCoulombModel mc = mohr_coulomb(1e5, 30, 10, 4e4);
  fem::PlasticState3D st3;
  fem::PlasticState st2;
  Vec3 E2 = Vec3::Zero();
  int yielded = 0;
  for (int step = 0; step < 300; ++step) {
    E2 += 2e-5 * Vec3(u(rng), u(rng), u(rng)) + Vec3(1e-6, -2e-6, 4e-6);  // shear, some tension
    Vec6 E3;
    E3 << E2[0], E2[1], 0, 0, 0, E2[2];
    const auto r2 = fem::mohr_coulomb_update(mc, E2, Vec3::Zero(), 0.0, st2, st2);
    const auto r3 = fem::mohr_coulomb_update_3d(mc, E3, Vec6::Zero(), st3, st3);
    const double scale = 1e-9 * (1e5 + std::abs(mean(r3.S)));
    EXPECT_NEAR(r3.S[0], r2.S[0], scale) << step;
    EXPECT_NEAR(r3.S[1], r2.S[1], scale) << step;
    EXPECT_NEAR(r3.S[2], r2.S_zz, scale) << step;
    EXPECT_NEAR(r3.S[5], r2.S[2], scale) << step;
    EXPECT_NEAR(r3.S[3], 0.0, scale);
    EXPECT_NEAR(r3.S[4], 0.0, scale);
    EXPECT_NEAR(st3.ep[2], st2.ep_zz, 1e-9 * (1e-3 + std::abs(st2.ep_zz)));
    EXPECT_NEAR(st3.plastic_work, st2.plastic_work, 1e-9 * (1.0 + st2.plastic_work));
    yielded += r3.yielded();
  }
  EXPECT_GT(yielded, 50);
}

// Isotropy: the path R E R^T gives R S R^T, whatever the rotation.
TEST(MohrCoulomb3D, ARotatedPathGivesTheRotatedStress) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const fem::MohrCoulombModel mc = mohr_coulomb(1e5, 35, 5, 3e4);
  const Mat3 R = Eigen::AngleAxisd(1.1, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  fem::PlasticState3D a, b;
  Vec6 E = Vec6::Zero();
  int yielded = 0;
  for (int step = 0; step < 200; ++step) {
    for (int q = 0; q < 6; ++q) E[q] += 2e-5 * u(rng) + (q < 3 ? 5e-7 : 0.0);
    const auto ra = fem::mohr_coulomb_update_3d(mc, E, Vec6::Zero(), a, a);
    const auto rb = fem::mohr_coulomb_update_3d(mc, rotate_strain(R, E), Vec6::Zero(), b, b);
    const Vec6 expect = rotate_stress(R, ra.S);
    for (int q = 0; q < 6; ++q) EXPECT_NEAR(rb.S[q], expect[q], 1e-9 * (1e5 + std::abs(mean(ra.S)))) << step << " " << q;
    EXPECT_NEAR(b.plastic_work, a.plastic_work, 1e-9 * (1.0 + a.plastic_work));
    yielded += ra.yielded();
  }
  EXPECT_GT(yielded, 20);  // a quarter of the steps return
}

TEST(DruckerPrager3D, RandomPathsStayOnTheConeAndMatchPlaneStrain) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const fem::ElasticConstants el = test::elastic_constants(1e9, 0.3);
  int cone = 0, apex = 0;
  for (const auto& [phi, psi] : {std::pair{30.0, 0.0}, {30.0, 30.0}, {0.0, 0.0}, {40.0, 15.0}}) {
    const fem::DruckerPragerModel m = fem::make_drucker_prager(1e5, phi * kDeg, psi * kDeg, el);
    for (int path = 0; path < 40; ++path) {
      fem::PlasticState3D st;
      fem::PlasticState st2;
      Vec6 E = Vec6::Zero();
      const bool plane = path % 4 == 0;  // E_zz = E_yz = E_xz = 0: the 2D law alongside
      double work = 0.0;
      for (int step = 0; step < 50; ++step) {
        for (int q = 0; q < 6; ++q)
          if (!plane || q == 0 || q == 1 || q == 5) E[q] += 2e-5 * u(rng) + (q < 3 ? (path % 2 ? 3e-6 : -1e-6) : 0.0);
        const auto r = fem::drucker_prager_update_3d(m, E, Vec6::Zero(), st, st);
        SCOPED_TRACE(testing::Message() << "phi " << phi << " path " << path << " step " << step);
        ASSERT_GE(r.dissipation, 0.0);
        work += r.dissipation;
        EXPECT_DOUBLE_EQ(st.plastic_work, work);
        const double f = fem::drucker_prager_yield(m, r.S) / (m.k + std::abs(m.alpha * 3 * mean(r.S)));
        if (r.region == fem::DruckerPragerRegion::Elastic) {
          EXPECT_LE(f, 1e-12);
        } else {
          EXPECT_NEAR(f, 0.0, 1e-9);
          (r.region == fem::DruckerPragerRegion::Apex ? apex : cone)++;
        }
        if (plane) {
          const auto r2 = fem::drucker_prager_update(m, Vec3(E[0], E[1], E[5]), Vec3::Zero(), 0.0, st2, st2);
          const double scale = 1e-9 * (1e5 + std::abs(mean(r.S)));
          EXPECT_NEAR(r.S[0], r2.S[0], scale);
          EXPECT_NEAR(r.S[1], r2.S[1], scale);
          EXPECT_NEAR(r.S[2], r2.S_zz, scale);
          EXPECT_NEAR(r.S[5], r2.S[2], scale);
          EXPECT_EQ(r.region, r2.region);
        }
      }
    }
  }
  EXPECT_GT(cone, 100);
  EXPECT_GT(apex, 0);
}

// The elastic check from the invariants (a bound on the principal stresses) never decides
// for a trial the principal-stress check finds outside: every trial strictly inside the
// envelope comes back unchanged and every one outside is returned.
TEST(MohrCoulomb3D, TheInvariantsShortcutAgreesWithThePrincipalStressCheck) {
  const fem::MohrCoulombModel mc = mohr_coulomb(1e5, 35.0, 5.0, 5e4);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int inside = 0, outside = 0;
  for (int i = 0; i < 20000; ++i) {
    Vec6 E;
    for (int k = 0; k < 6; ++k) E[k] = 4e-4 * u(rng);
    E.head<3>().array() -= 3e-4 * (1.0 + u(rng));  // mostly compression, around the envelope
    const fem::PlasticState3D start;
    fem::PlasticState3D end;
    const Vec6 S0 = Vec6::Zero();
    const fem::ElasticTrial3D t = fem::elastic_trial(mc.elastic, E, S0, start);
    const auto s = principal(t.S);
    const bool elastic = mc.k * s[0] - s[2] - mc.sc <= 0.0 && s[0] <= mc.ft;
    const auto r = fem::mohr_coulomb_update_3d(mc, E, S0, start, end);
    if (elastic) {
      ++inside;
      EXPECT_FALSE(r.yielded()) << i;
      for (int k = 0; k < 6; ++k) ASSERT_EQ(r.S[k], t.S[k]) << i;
    } else {
      ++outside;
      EXPECT_TRUE(r.yielded()) << i;
    }
  }
  EXPECT_GT(inside, 2000);
  EXPECT_GT(outside, 2000);
}
