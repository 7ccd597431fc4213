// A fluid pair's terms (pair_terms.hpp) and a particle's sums over its partners four pairs
// at a time (pair_lanes.hpp): a pair evaluated from either side gives the same terms
// mirrored exactly (equal and opposite forces); the sums are the pair terms' sums, and the
// AVX2 lanes give the scalar functions' bits, so the water's results do not depend on the CPU.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>
#include <random>

#include "sph/kernels.hpp"
#include "sph/pair_lanes.hpp"
#include "sph/pair_terms.hpp"

using namespace dsdem::sph;

namespace {

constexpr double kH = 0.015, kRho0 = 1000.0, kC0 = 14.0;

DensityPairConstants density_constants() {
  return {1.0 / kH, -5.0 * wendland_normalisation(kH) / (kH * kH), 0.1, 0.1 * kH * kC0, 0.0, -9.81, kRho0, kC0};
}
ForcePairConstants force_constants() {
  return {kH, 0.02 * kC0, 0.1, 1.0 / kH, -5.0 * wendland_normalisation(kH) / (kH * kH)};
}

// n particles scattered around the origin within 2.3 h (some beyond the support), moving
// and a little compressed, in the arrays the lanes read.
struct Cloud {
  std::vector<double> x, y, vx, vy, rho, p, gx, gy, vol;
  explicit Cloud(int n, unsigned seed) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < n; ++i) {
      x.push_back(1.6 * kH * u(g));
      y.push_back(1.6 * kH * u(g));
      vx.push_back(0.3 * u(g));
      vy.push_back(0.3 * u(g));
      rho.push_back(kRho0 * (1.0 + 0.01 * u(g)));
      p.push_back(tait_pressure(rho.back(), kRho0, tait_b(kRho0, kC0)));
      gx.push_back(50.0 * u(g));
      gy.push_back(50.0 * u(g));
      vol.push_back(0.1 / rho.back());
    }
  }
  DensityPoint density_point(int i) const { return {x[i], y[i], vx[i], vy[i], rho[i], gx[i], gy[i]}; }
  ForcePoint force_point(int i) const { return {x[i], y[i], vx[i], vy[i], rho[i], p[i]}; }
  std::vector<DensityRecord> density_records() const {
    std::vector<DensityRecord> r;
    for (std::size_t i = 0; i < x.size(); ++i) r.push_back({x[i], y[i], vx[i], vy[i], rho[i], gx[i], gy[i], vol[i]});
    return r;
  }
  std::vector<ForceRecord> force_records() const {
    std::vector<ForceRecord> r;
    for (std::size_t i = 0; i < x.size(); ++i) r.push_back({x[i], y[i], vx[i], vy[i], rho[i], p[i], vol[i], 0.0});
    return r;
  }
};

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <bool fourtakas>
void expect_density_pair_mirrored(const Cloud& c) {
  int inside = 0;
  for (int a = 0; a < 20; ++a)
    for (int b = 0; b < 20; ++b) {
      if (a == b) continue;
      const DensityPairTerms s = density_pair<fourtakas>(density_constants(), c.density_point(a), c.density_point(b));
      const DensityPairTerms t = density_pair<fourtakas>(density_constants(), c.density_point(b), c.density_point(a));
      // Equal values (==: beyond the support a 0 may come with either sign).
      EXPECT_TRUE(s.f == t.f && s.c == t.c && s.q == -t.q) << a << ", " << b;
      if (s.f != 0.0) {
        EXPECT_TRUE(same_bits(s.q, -t.q)) << a << ", " << b;
      }
      inside += s.f != 0.0 ? 1 : 0;
    }
  EXPECT_GT(inside, 100);
}

}  // namespace

TEST(SphPairTerms, DensityPairFromEitherSideIsMirroredExactly) {
  const Cloud c(20, 1);
  expect_density_pair_mirrored<true>(c);
  expect_density_pair_mirrored<false>(c);
}

TEST(SphPairTerms, ForcePairFromEitherSideIsMirroredExactly) {
  const Cloud c(20, 2);
  for (int a = 0; a < 20; ++a)
    for (int b = 0; b < 20; ++b) {
      if (a == b) continue;
      const double dx = c.x[a] - c.x[b], dy = c.y[a] - c.y[b];
      const double f = wendland_gradient_factor(dx * dx + dy * dy, kH);
      const ForcePairTerms s = force_pair<true>(force_constants(), c.force_point(a), c.force_point(b), f);
      const ForcePairTerms t = force_pair<true>(force_constants(), c.force_point(b), c.force_point(a), f);
      EXPECT_TRUE(same_bits(s.ax, -t.ax) && same_bits(s.ay, -t.ay)) << a << ", " << b;
      EXPECT_TRUE(same_bits(s.xx, t.xx) && same_bits(s.xy, t.xy) && same_bits(s.yy, t.yy));
      EXPECT_TRUE(same_bits(s.sx, t.sx) && same_bits(s.sy, t.sy));
    }
}

TEST(SphPairTerms, PairBeyondTheSupportAddsNothing) {
  const DensityPoint a{0.0, 0.0, 0.1, 0.0, 1001.0, 1.0, 2.0}, b{2.0 * kH, 1e-9, -0.1, 0.0, 999.0, 3.0, 4.0};
  const DensityPairTerms t = density_pair<false>(density_constants(), a, b);
  EXPECT_EQ(t.f, 0.0);
  EXPECT_EQ(t.c, 0.0);
  EXPECT_EQ(t.q, 0.0);
}

// A particle's sums over lists of 0 to 30 partners (some beyond the support, so groups of
// four and a padded last group): the AVX2 lanes give the scalar reference's bits, and both
// are the plain sums of the pair terms (to round-off: the lanes add in another order). The
// density pass hands each pair's F to the force pass: the kernel's, from either.
TEST(SphPairLanes, SumsAreThePairTermsAndTheLanesGiveTheScalarBits) {
  const Cloud c(64, 3);
  const std::vector<DensityRecord> dr = c.density_records();
  const std::vector<ForceRecord> fr = c.force_records();
  std::mt19937 g(4);
  std::uniform_int_distribution<std::int32_t> pick(1, 63);
  const bool avx2 = pair_lanes_avx2();
  int nonzero = 0;
  for (int rep = 0; rep < 200; ++rep) {
    const std::size_t n = static_cast<std::size_t>(rep % 31);
    std::vector<std::int32_t> js(n);
    for (auto& j : js) j = pick(g);
    const DensityPoint di = c.density_point(0);
    const ForcePoint fi = c.force_point(0);
    std::vector<double> fs(n, -1.0), fs2(n, -1.0);
    for (bool fourtakas : {false, true}) {
      const double s1 = fourtakas ? density_sum_scalar<true>(density_constants(), di, dr.data(), js.data(), n, fs.data())
                                  : density_sum_scalar<false>(density_constants(), di, dr.data(), js.data(), n, fs.data());
      for (std::size_t m = 0; m < n; ++m) {
        const double dx = di.x - c.x[js[m]], dy = di.y - c.y[js[m]];
        const double f = wendland_gradient_factor(dx * dx + dy * dy, density_constants().inv_h, density_constants().grad_c);
        EXPECT_TRUE(same_bits(fs[m], f)) << m;
      }
      double plain = 0.0, scale = 0.0;
      for (std::size_t m = 0; m < n; ++m) {
        const DensityPairTerms t = fourtakas ? density_pair<true>(density_constants(), di, c.density_point(js[m]))
                                             : density_pair<false>(density_constants(), di, c.density_point(js[m]));
        plain += t.c + t.q * c.vol[static_cast<std::size_t>(js[m])];
        scale += std::abs(t.c) + std::abs(t.q * c.vol[static_cast<std::size_t>(js[m])]);
      }
      EXPECT_NEAR(s1, plain, 1e-14 * scale) << n << " partners";
      nonzero += s1 != 0.0 ? 1 : 0;
      if (!avx2) continue;
      const double s2 = fourtakas ? density_sum_avx2<true>(density_constants(), di, dr.data(), js.data(), n, fs2.data())
                                  : density_sum_avx2<false>(density_constants(), di, dr.data(), js.data(), n, fs2.data());
      EXPECT_TRUE(same_bits(s1, s2)) << (fourtakas ? "Fourtakas, " : "delta-SPH, ") << n << " partners";
      EXPECT_TRUE(n == 0 || std::memcmp(fs.data(), fs2.data(), n * sizeof(double)) == 0) << n << " partners";
    }
    const ForceSums t1 = force_sum_scalar<true>(force_constants(), fi, fr.data(), js.data(), fs.data(), n);
    double ax = 0.0, mxx = 0.0, sy = 0.0, scale = 0.0;
    for (std::size_t m = 0; m < n; ++m) {
      const double dx = fi.x - c.x[js[m]], dy = fi.y - c.y[js[m]];
      const ForcePairTerms t =
          force_pair<true>(force_constants(), fi, c.force_point(js[m]), wendland_gradient_factor(dx * dx + dy * dy, kH));
      const double v = c.vol[static_cast<std::size_t>(js[m])];
      ax += t.ax;
      mxx -= v * t.xx;
      sy += v * t.sy;
      scale += std::abs(t.ax) + std::abs(v * t.xx) + std::abs(v * t.sy);
    }
    EXPECT_NEAR(t1.ax, ax, 1e-14 * scale);
    EXPECT_NEAR(t1.mxx, mxx, 1e-14 * scale);
    EXPECT_NEAR(t1.sy, sy, 1e-14 * scale);
    if (!avx2) continue;
    for (bool grad : {true, false}) {
      const ForceSums a = grad ? force_sum_scalar<true>(force_constants(), fi, fr.data(), js.data(), fs.data(), n)
                               : force_sum_scalar<false>(force_constants(), fi, fr.data(), js.data(), fs.data(), n);
      const ForceSums b = grad ? force_sum_avx2<true>(force_constants(), fi, fr.data(), js.data(), fs.data(), n)
                               : force_sum_avx2<false>(force_constants(), fi, fr.data(), js.data(), fs.data(), n);
      EXPECT_TRUE(same_bits(a, b)) << (grad ? "with" : "without") << " the gradient, " << n << " partners";
    }
  }
  EXPECT_GT(nonzero, 300);
  if (!avx2) GTEST_SKIP() << "no AVX2 on this CPU: the scalar sums checked alone";
}
