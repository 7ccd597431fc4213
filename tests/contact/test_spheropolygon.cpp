// Spheropolygon geometry: incircle, rounding radius, erosion (docs/theory.md §4, paper §1.1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "contact/narrow_phase.hpp"
#include "contact/spheropolygon.hpp"

using namespace dsdem;
using namespace dsdem::contact;

namespace {

// Distance from p to the infinite line through a, b.
double line_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  return std::abs(cross(b - a, p - a)) / (b - a).norm();
}

// A random non-degenerate CCW triangle with vertices within `size` of c.
std::array<Vec2, 3> random_triangle(std::mt19937& rng, const Vec2& c, double size) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (;;) {
    std::array<Vec2, 3> p = {c + size * Vec2(u(rng), u(rng)), c + size * Vec2(u(rng), u(rng)),
                             c + size * Vec2(u(rng), u(rng))};
    const double a2 = cross(p[1] - p[0], p[2] - p[0]);
    const double l2 = std::max({(p[1] - p[0]).squaredNorm(), (p[2] - p[1]).squaredNorm(),
                                (p[0] - p[2]).squaredNorm()});
    if (std::abs(a2) < 0.05 * l2) continue;  // avoid slivers (min angle about 3 degrees)
    if (a2 < 0) std::swap(p[1], p[2]);
    return p;
  }
}

}  // namespace

TEST(Spheropolygon, IncircleOfRightAndEquilateralTriangles) {
  // 3-4-5 right triangle: inradius (3 + 4 - 5)/2 = 1, incentre (1, 1).
  const Incircle ic = incircle(Vec2(0, 0), Vec2(4, 0), Vec2(0, 3));
  EXPECT_NEAR(ic.radius, 1.0, 1e-15);
  EXPECT_NEAR(ic.centre.x(), 1.0, 1e-15);
  EXPECT_NEAR(ic.centre.y(), 1.0, 1e-15);
  // Equilateral, side 2: inradius 2/(2 sqrt 3), incentre = centroid; clockwise too.
  const Incircle eq = incircle(Vec2(0, 0), Vec2(1, std::sqrt(3.0)), Vec2(2, 0));
  EXPECT_NEAR(eq.radius, 1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(eq.centre.x(), 1.0, 1e-15);
  EXPECT_NEAR(eq.centre.y(), 1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(rounding_radius(Vec2(0, 0), Vec2(4, 0), Vec2(0, 3)), 0.05, 1e-16);
  EXPECT_NEAR(rounding_radius(Vec2(0, 0), Vec2(4, 0), Vec2(0, 3), 0.1), 0.1, 1e-16);
}

TEST(Spheropolygon, CoreEdgesMovedInwardByRAndCoreInradiusIsInradiusMinusR) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const auto p = random_triangle(rng, Vec2(3.0, -2.0), 5.0);
    const Incircle ic = incircle(p[0], p[1], p[2]);
    for (double factor : {0.05, 0.2, 0.5}) {
      const double r = factor * ic.radius;
      const Spheropolygon sp = make_spheropolygon(p[0], p[1], p[2], r);
      EXPECT_EQ(sp.r, r);
      const Incircle core_ic = incircle(sp.core[0], sp.core[1], sp.core[2]);
      EXPECT_NEAR(core_ic.radius, ic.radius - r, 1e-12 * ic.radius);
      EXPECT_NEAR((core_ic.centre - ic.centre).norm(), 0.0, 1e-12 * ic.radius);
      for (int k = 0; k < 3; ++k) {
        // Core edge k parallel to edge k, at distance r inside.
        const Vec2& a = sp.core[k];
        const Vec2& b = sp.core[(k + 1) % 3];
        EXPECT_NEAR(line_distance(a, p[k], p[(k + 1) % 3]), r, 1e-12 * ic.radius);
        EXPECT_NEAR(line_distance(b, p[k], p[(k + 1) % 3]), r, 1e-12 * ic.radius);
        EXPECT_GT(cross(p[(k + 1) % 3] - p[k], a - p[k]), 0.0);  // on the inner side
      }
    }
  }
}

TEST(Spheropolygon, TrianglesSharingAnEdgeTouchWithZeroOverlap) {
  // Two triangles on either side of a shared edge P-Q, different sizes so r differs.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.2, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec2 P(0.0, 0.0);
    const Vec2 Q(1.0 + u(rng), 0.3 * (u(rng) - 0.6));
    const Vec2 mid = 0.5 * (P + Q);
    const Vec2 n = Vec2(-(Q - P).y(), (Q - P).x()).normalized();
    const Vec2 R1 = mid + u(rng) * n + (u(rng) - 0.6) * (Q - P);  // left of P->Q
    const Vec2 R2 = mid - 2.0 * u(rng) * n + (u(rng) - 0.6) * (Q - P);
    // Both counter-clockwise: (P, Q, R1) and (Q, P, R2).
    const Spheropolygon a = make_spheropolygon(P, Q, R1, rounding_radius(P, Q, R1));
    const Spheropolygon b = make_spheropolygon(Q, P, R2, rounding_radius(Q, P, R2));
    // The nearest vertex-core distance is exactly r_a + r_b: touching, zero overlap.
    double min_gap = 1e300;
    for (int v = 0; v < 3; ++v) {
      min_gap = std::min(min_gap, closest_on_core(a.core[v], b.core).distance - (a.r + b.r));
      min_gap = std::min(min_gap, closest_on_core(b.core[v], a.core).distance - (a.r + b.r));
    }
    EXPECT_NEAR(min_gap, 0.0, 1e-12);
    std::array<ContactGeometry, kMaxContactsPerPair> out;
    const int n_contacts = narrow_phase(a, b, out);
    for (int k = 0; k < n_contacts; ++k) EXPECT_LE(out[k].overlap, 1e-12);
  }
}

TEST(Spheropolygon, ConformingMeshHasNoOverlapAnywhere) {
  // A jittered structured mesh, every triangle with its own rounding radius: any two
  // triangles (sharing an edge, a vertex, or nothing) overlap by at most round-off.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jit(-0.25, 0.25);
  const int n = 6;
  std::vector<Vec2> X;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const bool interior = i > 0 && i < n && j > 0 && j < n;
      X.emplace_back(i + (interior ? jit(rng) : 0.0), j + (interior ? jit(rng) : 0.0));
    }
  std::vector<Spheropolygon> sps;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Vec2 &p00 = X[j * (n + 1) + i], &p10 = X[j * (n + 1) + i + 1];
      const Vec2 &p01 = X[(j + 1) * (n + 1) + i], &p11 = X[(j + 1) * (n + 1) + i + 1];
      sps.push_back(make_spheropolygon(p00, p10, p11, rounding_radius(p00, p10, p11)));
      sps.push_back(make_spheropolygon(p00, p11, p01, rounding_radius(p00, p11, p01)));
    }
  double max_overlap = -1.0;
  std::array<ContactGeometry, kMaxContactsPerPair> out;
  for (std::size_t a = 0; a < sps.size(); ++a)
    for (std::size_t b = a + 1; b < sps.size(); ++b) {
      const int k = narrow_phase(sps[a], sps[b], out);
      for (int c = 0; c < k; ++c) max_overlap = std::max(max_overlap, out[c].overlap);
    }
  EXPECT_LE(max_overlap, 1e-12);
}

TEST(Spheropolygon, BoundingBoxOfRoundedShapeLiesInTriangleBox) {
  const Vec2 p0(0, 0), p1(4, 0), p2(0, 3);  // inradius 1, incentre (1, 1)
  const Spheropolygon sp = make_spheropolygon(p0, p1, p2, 0.05);
  const Aabb box = bounding_box(sp);
  // Leftmost/lowest core points lie at distance r from the legs: rounded box touches x=0, y=0.
  EXPECT_NEAR(box.lo.x(), 0.0, 1e-15);
  EXPECT_NEAR(box.lo.y(), 0.0, 1e-15);
  // Core = scaling by 0.95 about (1, 1): corner (4, 0) -> (3.85, 0.05); box max x = 3.9.
  EXPECT_NEAR(box.hi.x(), 1.0 + 0.95 * 3.0 + 0.05, 1e-14);
  EXPECT_NEAR(box.hi.y(), 1.0 + 0.95 * 2.0 + 0.05, 1e-14);
  EXPECT_LT(box.hi.x(), 4.0);
  EXPECT_LT(box.hi.y(), 3.0);
}

TEST(Spheropolygon, SquashedTriangleCollapsesCoreToIncentre) {
  // Inradius 1 but r = 1.5: the core is the incentre point.
  const Spheropolygon sp = make_spheropolygon(Vec2(0, 0), Vec2(4, 0), Vec2(0, 3), 1.5);
  for (const Vec2& q : sp.core) {
    EXPECT_NEAR(q.x(), 1.0, 1e-15);
    EXPECT_NEAR(q.y(), 1.0, 1e-15);
  }
}

TEST(Aabb, ContainsIsClosedAndRejectsEachSide) {
  const Aabb b{Vec2(0.0, -1.0), Vec2(2.0, 1.0)};
  EXPECT_TRUE(contains(b, Vec2(1.0, 0.0)));
  EXPECT_TRUE(contains(b, Vec2(0.0, -1.0)));  // corners belong to the box
  EXPECT_TRUE(contains(b, Vec2(2.0, 1.0)));
  EXPECT_FALSE(contains(b, Vec2(-1e-12, 0.0)));
  EXPECT_FALSE(contains(b, Vec2(2.0 + 1e-12, 0.0)));
  EXPECT_FALSE(contains(b, Vec2(1.0, -1.0 - 1e-12)));
  EXPECT_FALSE(contains(b, Vec2(1.0, 1.0 + 1e-12)));
}
