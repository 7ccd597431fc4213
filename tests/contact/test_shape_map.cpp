// Contact force to nodes by the linear shape functions (paper eq. 5, docs/theory.md §4).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "contact/shape_map.hpp"
#include "contact/spheropolygon.hpp"

using namespace dsdem;
using namespace dsdem::contact;

TEST(ShapeMap, BarycentricReproducesThePointInsideAndOutside) {
  const Vec2 x0(1.0, 2.0), x1(4.0, 2.5), x2(2.0, 5.0);
  for (const Vec2& p : {Vec2(2.0, 3.0), Vec2(5.0, -1.0), Vec2(-3.0, 7.0)}) {
    const Vec3 N = barycentric(p, x0, x1, x2);
    EXPECT_NEAR(N.sum(), 1.0, 1e-15);
    const Vec2 q = N[0] * x0 + N[1] * x1 + N[2] * x2;
    EXPECT_NEAR((q - p).norm(), 0.0, 1e-14);
  }
  // Vertices and the centroid.
  EXPECT_EQ(barycentric(x1, x0, x1, x2), Vec3(0.0, 1.0, 0.0));
  const Vec3 Nc = barycentric((x0 + x1 + x2) / 3.0, x0, x1, x2);
  EXPECT_NEAR((Nc - Vec3::Constant(1.0 / 3.0)).norm(), 0.0, 1e-15);
  // Clockwise listing gives the same coordinates.
  const Vec3 a = barycentric(Vec2(2.0, 3.0), x0, x1, x2);
  const Vec3 b = barycentric(Vec2(2.0, 3.0), x0, x2, x1);
  EXPECT_NEAR(a[1], b[2], 1e-15);
  EXPECT_NEAR(a[2], b[1], 1e-15);
}

TEST(ShapeMap, ForceAtAVertexGoesAllToThatVertex) {
  const Vec2 x0(0.3, 0.1), x1(2.0, 0.4), x2(1.1, 1.9);
  const Vec2 F(3.0e6, -1.5e6);
  for (int k = 0; k < 3; ++k) {
    const Vec2& xk = k == 0 ? x0 : (k == 1 ? x1 : x2);
    const auto f = distribute(barycentric(xk, x0, x1, x2), F);
    for (int m = 0; m < 3; ++m) {
      EXPECT_EQ(f[m].x(), m == k ? F.x() : 0.0);
      EXPECT_EQ(f[m].y(), m == k ? F.y() : 0.0);
    }
  }
}

TEST(ShapeMap, EqualAndOppositeContactForcesConserveMomentumAndAngularMomentum) {
  // Two triangles in contact around a point; +F on i, -F on j at that point. Total
  // nodal force and total moment about the origin vanish to round-off.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 500; ++trial) {
    const Vec2 c(100.0 * u(rng), 50.0 * u(rng));  // away from the origin: moments matter
    std::vector<Vec2> x = {c + Vec2(-1, 0), c + Vec2(0, -1), c + Vec2(0.2, 0.1),
                           c + Vec2(1, 0.2), c + Vec2(0.1, 1.2), c + Vec2(-0.1, -0.05)};
    for (auto& p : x) p += 0.1 * Vec2(u(rng), u(rng));
    const std::array<Index, 3> ti = {0, 1, 2}, tj = {3, 4, 5};
    const Vec2 point = c + 0.05 * Vec2(u(rng), u(rng));
    const Vec2 F = 1e7 * Vec2(u(rng), u(rng));
    std::vector<Vec2> f(6, Vec2::Zero());
    add_point_force(barycentric(point, x[0], x[1], x[2]), ti, F, f);
    add_point_force(barycentric(point, x[3], x[4], x[5]), tj, -F, f);
    Vec2 total = Vec2::Zero();
    double moment = 0.0, moment_i = 0.0;
    for (int n = 0; n < 6; ++n) {
      total += f[n];
      moment += cross(x[n], f[n]);
      if (n < 3) moment_i += cross(x[n], f[n]);
    }
    const double scale_f = F.norm();
    const double scale_m = F.norm() * point.norm();
    EXPECT_LE(total.norm(), 1e-12 * scale_f);
    EXPECT_LE(std::abs(moment), 1e-12 * scale_m);
    // Each triangle alone gets the moment of the point force: point x F.
    EXPECT_NEAR(moment_i, cross(point, F), 1e-12 * scale_m);
  }
}

TEST(ShapeMap, PointVelocityOfARigidMotionAndPointMass) {
  // Rigid motion v = V + w x (x - o): the interpolated velocity is exact (linear field).
  const Vec2 V(0.7, -0.2), o(1.0, 1.0);
  const double w = 3.0;
  const std::vector<Vec2> x = {Vec2(0, 0), Vec2(2, 0.5), Vec2(0.5, 1.8)};
  std::vector<Vec2> v;
  for (const auto& p : x) v.push_back(V + w * Vec2(-(p - o).y(), (p - o).x()));
  const std::array<Index, 3> nodes = {0, 1, 2};
  const Vec2 p(0.8, 0.6);
  const Vec2 vp = point_velocity(barycentric(p, x[0], x[1], x[2]), nodes, v);
  const Vec2 want = V + w * Vec2(-(p - o).y(), (p - o).x());
  EXPECT_NEAR((vp - want).norm(), 0.0, 1e-14);
  // Mass driven by a point force: a node's own mass at a vertex, 3m at the centroid.
  const std::vector<double> m = {2.0, 2.0, 2.0};
  EXPECT_NEAR(point_inverse_mass(Vec3(0, 1, 0), nodes, m), 0.5, 1e-16);
  EXPECT_NEAR(point_inverse_mass(Vec3::Constant(1.0 / 3.0), nodes, m), 1.0 / 6.0, 1e-16);
  // A massless (immovable) node adds nothing.
  const std::vector<double> m0 = {0.0, 2.0, 2.0};
  EXPECT_NEAR(point_inverse_mass(Vec3(0.5, 0.5, 0.0), nodes, m0), 0.125, 1e-16);
}

TEST(ShapeMap, BarycentricFrameGivesBarycentricBitForBit) {
  // The per-pair frame (process_pair: one per triangle, reused by its contacts) must give
  // exactly what barycentric() gives, degenerate triangles included.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    const Vec2 x0(100.0 + u(rng), 50.0 + u(rng)), x1(100.0 + u(rng), 50.0 + u(rng));
    const Vec2 x2 = k % 10 == 0 ? Vec2(x0 + 0.5 * (x1 - x0)) : Vec2(100.0 + u(rng), 50.0 + u(rng));
    const Vec2 p(100.0 + u(rng), 50.0 + u(rng));
    const Vec3 a = barycentric(p, x0, x1, x2), b = barycentric(p, barycentric_frame(x0, x1, x2));
    ASSERT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * 3), 0) << k;
  }
}
