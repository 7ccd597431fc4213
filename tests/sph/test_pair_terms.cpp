// A fluid pair's terms (pair_terms.hpp) and four of them at once (pair_lanes.hpp): a pair
// evaluated from either side gives the same terms mirrored exactly, which is what lets
// sph::Fluid evaluate each pair once and add it to both particles; the AVX2 lanes give the
// scalar functions' bits, so the water's results do not depend on the CPU.
#include <gtest/gtest.h>

#include <cstring>
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
ForcePairConstants force_constants() { return {kH, 0.02 * kC0, 0.1}; }

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
  DensityArrays density_arrays() const {
    return {x.data(), y.data(), vx.data(), vy.data(), rho.data(), gx.data(), gy.data(), vol.data()};
  }
  ForceArrays force_arrays() const { return {x.data(), y.data(), vx.data(), vy.data(), rho.data(), p.data(), vol.data()}; }
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
      if (s.f != 0.0) EXPECT_TRUE(same_bits(s.q, -t.q)) << a << ", " << b;
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

// Many groups of four partners of one particle (some beyond the support, a padded group
// repeating a partner), both density variants and both force variants: every output of the
// AVX2 lanes equals the scalar reference's bit for bit.
TEST(SphPairLanes, Avx2LanesGiveTheScalarBits) {
  if (!pair_lanes_avx2()) GTEST_SKIP() << "no AVX2 on this CPU";
  const Cloud c(64, 3);
  std::mt19937 g(4);
  std::uniform_int_distribution<std::int32_t> pick(1, 63);
  int groups = 0;
  for (int rep = 0; rep < 200; ++rep) {
    const int i = rep % 64;
    std::int32_t js[4] = {pick(g), pick(g), pick(g), pick(g)};
    if (rep % 7 == 0) js[3] = js[2] = js[0];  // a padded last group
    const double vi = c.vol[static_cast<std::size_t>(i)];
    DensityLanes d1{}, d2{};
    density_lanes_scalar<false>(density_constants(), c.density_point(i), vi, c.density_arrays(), js, d1);
    density_lanes_avx2<false>(density_constants(), c.density_point(i), vi, c.density_arrays(), js, d2);
    EXPECT_TRUE(same_bits(d1, d2)) << "delta-SPH, group " << rep;
    density_lanes_scalar<true>(density_constants(), c.density_point(i), vi, c.density_arrays(), js, d1);
    density_lanes_avx2<true>(density_constants(), c.density_point(i), vi, c.density_arrays(), js, d2);
    EXPECT_TRUE(same_bits(d1, d2)) << "Fourtakas, group " << rep;
    ForceLanes f1{}, f2{};
    force_lanes_scalar<true>(force_constants(), c.force_point(i), vi, c.force_arrays(), js, d1.f, f1);
    force_lanes_avx2<true>(force_constants(), c.force_point(i), vi, c.force_arrays(), js, d1.f, f2);
    EXPECT_TRUE(same_bits(f1, f2)) << "forces with the gradient, group " << rep;
    force_lanes_scalar<false>(force_constants(), c.force_point(i), vi, c.force_arrays(), js, d1.f, f1);
    force_lanes_avx2<false>(force_constants(), c.force_point(i), vi, c.force_arrays(), js, d1.f, f2);
    EXPECT_TRUE(same_bits(f1, f2)) << "forces, group " << rep;
    groups += d1.f[0] != 0.0 && d1.f[1] != 0.0 ? 1 : 0;
  }
  EXPECT_GT(groups, 20);  // most groups hold pairs within the support
}
