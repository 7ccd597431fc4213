// Narrow phase: vertex-edge, vertex-vertex and edge-edge contacts against analytic
// overlap, normal and contact point (docs/theory.md §4, paper eq. 1 and Fig. 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "contact/narrow_phase.hpp"
#include "contact/vertex_queries_x6.hpp"
#include "common/same_bits.hpp"

using namespace dsdem;
using namespace dsdem::contact;

namespace {

Spheropolygon sp(Vec2 a, Vec2 b, Vec2 c, double r) { return Spheropolygon{{a, b, c}, r}; }

using Out = std::array<ContactGeometry, kMaxContactsPerPair>;

// Two contact geometries equal in every field, bit for bit.
bool same_geometry(const ContactGeometry& p, const ContactGeometry& q) {
  return p.feature == q.feature && p.kind == q.kind && p.other == q.other && p.t == q.t && p.distance == q.distance &&
         p.overlap == q.overlap && p.normal == q.normal && p.point == q.point;
}

void expect_vec(const Vec2& got, const Vec2& want, double tol) {
  EXPECT_NEAR(got.x(), want.x(), tol);
  EXPECT_NEAR(got.y(), want.y(), tol);
}

// Core B: CCW, top edge (edge 2) from (4,0) to (0,0), apex below.
const Spheropolygon kBelow = sp(Vec2(0, 0), Vec2(2, -3), Vec2(4, 0), 0.1);

}  // namespace

TEST(ClosestOnCore, EdgeVertexAndInsideRegions) {
  const std::array<Vec2, 3> core = kBelow.core;
  // Above the top edge: edge interior, t measured from (4,0).
  CoreClosest c = closest_on_core(Vec2(1.5, 0.3), core);
  EXPECT_FALSE(c.at_vertex);
  EXPECT_EQ(c.edge, 2);
  EXPECT_NEAR(c.t, 0.625, 1e-14);
  EXPECT_NEAR(c.distance, 0.3, 1e-14);
  expect_vec(c.point, Vec2(1.5, 0.0), 1e-14);
  expect_vec(c.normal, Vec2(0, 1), 1e-14);
  // Beyond the corner (4,0): vertex 2.
  c = closest_on_core(Vec2(5, 1), core);
  EXPECT_TRUE(c.at_vertex);
  EXPECT_EQ(c.vertex, 2);
  EXPECT_NEAR(c.distance, std::sqrt(2.0), 1e-14);
  expect_vec(c.normal, Vec2(1, 1) / std::sqrt(2.0), 1e-14);
  // Inside, 0.2 below the top edge and far from the others: depth -0.2, outward normal.
  c = closest_on_core(Vec2(2, -0.2), core);
  EXPECT_FALSE(c.at_vertex);
  EXPECT_EQ(c.edge, 2);
  EXPECT_NEAR(c.distance, -0.2, 1e-14);
  expect_vec(c.point, Vec2(2, 0), 1e-14);
  expect_vec(c.normal, Vec2(0, 1), 1e-14);
  // Same core listed clockwise: same answer.
  c = closest_on_core(Vec2(2, -0.2), {core[0], core[2], core[1]});
  EXPECT_NEAR(c.distance, -0.2, 1e-14);
  expect_vec(c.normal, Vec2(0, 1), 1e-14);
}

TEST(NarrowPhase, VertexOnEdgeGivesAnalyticOverlapNormalAndPoint) {
  // A's core vertex 0 at (1.5, 0.15) above B's top edge y = 0; radii 0.1 + 0.1.
  const Spheropolygon a = sp(Vec2(1.5, 0.15), Vec2(2.5, 2), Vec2(0.5, 2), 0.1);
  Out out;
  ASSERT_EQ(narrow_phase(a, kBelow, out), 1);
  const ContactGeometry& g = out[0];
  EXPECT_EQ(g.kind, ContactKind::VertexEdge);
  EXPECT_EQ(g.feature, 0);  // vertex 0 of i
  EXPECT_EQ(g.other, 2);    // edge 2 of j
  EXPECT_NEAR(g.t, 0.625, 1e-14);
  EXPECT_NEAR(g.overlap, 0.05, 1e-14);
  expect_vec(g.normal, Vec2(0, 1), 1e-14);  // from j (below) to i
  // B's surface at y = 0.1, A's at 0.15 - 0.1 = 0.05: midway 0.075.
  expect_vec(g.point, Vec2(1.5, 0.075), 1e-14);

  // Same pair listed the other way round: side 1, normal reversed, same point.
  ASSERT_EQ(narrow_phase(kBelow, a, out), 1);
  EXPECT_EQ(out[0].feature, 3);
  EXPECT_NEAR(out[0].overlap, 0.05, 1e-14);
  expect_vec(out[0].normal, Vec2(0, -1), 1e-14);
  expect_vec(out[0].point, Vec2(1.5, 0.075), 1e-14);

  // Unequal radii: r_i = 0.04, r_j = 0.2 -> overlap 0.09; surfaces at 0.2 and 0.11.
  Spheropolygon a2 = a, b2 = kBelow;
  a2.r = 0.04;
  b2.r = 0.2;
  ASSERT_EQ(narrow_phase(a2, b2, out), 1);
  EXPECT_NEAR(out[0].overlap, 0.09, 1e-14);
  expect_vec(out[0].point, Vec2(1.5, 0.155), 1e-14);
}

TEST(NarrowPhase, VertexVertexCountedOnceInEveryOrder) {
  // Tips on the diagonal, 0.15 apart, both in each other's vertex region.
  const double d = 0.15;
  const Vec2 tip = Vec2(1, 1) * (d / std::sqrt(2.0));
  const std::array<Vec2, 3> ta = {tip, tip + Vec2(2, 1), tip + Vec2(1, 2)};
  const std::array<Vec2, 3> tb = {Vec2(0, 0), Vec2(-1, -2), Vec2(-2, -1)};
  const Vec2 n = Vec2(1, 1) / std::sqrt(2.0);
  for (int rot_a = 0; rot_a < 3; ++rot_a) {
    for (int rot_b = 0; rot_b < 3; ++rot_b) {
      const Spheropolygon a = sp(ta[rot_a], ta[(rot_a + 1) % 3], ta[(rot_a + 2) % 3], 0.05);
      const Spheropolygon b = sp(tb[rot_b], tb[(rot_b + 1) % 3], tb[(rot_b + 2) % 3], 0.15);
      const int tip_a = (3 - rot_a) % 3, tip_b = (3 - rot_b) % 3;  // where the tips went
      Out out;
      ASSERT_EQ(narrow_phase(a, b, out), 1);
      EXPECT_EQ(out[0].kind, ContactKind::VertexVertex);
      EXPECT_EQ(out[0].feature, tip_a);
      EXPECT_EQ(out[0].other, tip_b);
      EXPECT_NEAR(out[0].overlap, 0.2 - d, 1e-14);
      expect_vec(out[0].normal, n, 1e-14);
      // B's surface 0.15 from its tip, A's at d - 0.05 = 0.10: midway 0.125 along n.
      expect_vec(out[0].point, 0.125 * n, 1e-14);
      ASSERT_EQ(narrow_phase(b, a, out), 1);
      EXPECT_EQ(out[0].feature, tip_b);
      EXPECT_NEAR(out[0].overlap, 0.2 - d, 1e-14);
      expect_vec(out[0].normal, -n, 1e-14);
      expect_vec(out[0].point, 0.125 * n, 1e-14);
    }
  }
}

TEST(NarrowPhase, EdgeEdgeIsTwoVertexEdgeContactsAtTheEndsOfTheOverlap) {
  // A's bottom edge y = 0.15 from x = 0.05 to 4.05 over B's top edge y = 0, x in [0, 4].
  // The ends are offset by only 0.05, so A's corner (4.05, 0.15) is within reach of B's
  // corner (4, 0) (distance 0.158 < 0.2) but not mutually closest: not counted.
  const Spheropolygon a = sp(Vec2(0.05, 0.15), Vec2(4.05, 0.15), Vec2(2.05, 3), 0.1);
  Out out;
  ASSERT_EQ(narrow_phase(a, kBelow, out), 2);
  // A's vertex 0 on B's top edge, then B's vertex 2 (4, 0) on A's bottom edge 0.
  EXPECT_EQ(out[0].feature, 0);
  EXPECT_EQ(out[0].kind, ContactKind::VertexEdge);
  EXPECT_EQ(out[0].other, 2);
  EXPECT_NEAR(out[0].overlap, 0.05, 1e-14);
  expect_vec(out[0].normal, Vec2(0, 1), 1e-14);
  expect_vec(out[0].point, Vec2(0.05, 0.075), 1e-14);
  EXPECT_EQ(out[1].feature, 3 + 2);
  EXPECT_EQ(out[1].kind, ContactKind::VertexEdge);
  EXPECT_EQ(out[1].other, 0);
  EXPECT_NEAR(out[1].overlap, 0.05, 1e-14);
  expect_vec(out[1].normal, Vec2(0, 1), 1e-14);
  expect_vec(out[1].point, Vec2(4.0, 0.075), 1e-14);

  // Edges exactly aligned end to end: two (mutual) vertex-vertex contacts, one per end.
  const Spheropolygon c = sp(Vec2(0, 0.15), Vec2(4, 0.15), Vec2(2, 3), 0.1);
  ASSERT_EQ(narrow_phase(c, kBelow, out), 2);
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(out[k].kind, ContactKind::VertexVertex);
    EXPECT_NEAR(out[k].overlap, 0.05, 1e-14);
    expect_vec(out[k].normal, Vec2(0, 1), 1e-14);
  }
  expect_vec(out[0].point, Vec2(0, 0.075), 1e-14);
  expect_vec(out[1].point, Vec2(4, 0.075), 1e-14);
}

TEST(NarrowPhase, VertexNearAcuteCornerCountsOnlyItsNearestEdge) {
  // B has a 20-degree corner at the origin between edge 0 (along -x) and edge 2 (at 200
  // degrees). A's vertex (-0.15, 0.05) is 0.05 outside edge 0 and also within
  // r_a + r_b = 0.2 of edge 2's interior (from the inner side): summing every
  // vertex-edge pair would count it twice; it has one contact, on edge 0.
  const double th = 20.0 * kPi / 180.0;
  const Spheropolygon b = sp(Vec2(0, 0), Vec2(-5, 0), Vec2(-5 * std::cos(th), -5 * std::sin(th)), 0.1);
  const Vec2 p(-0.15, 0.05);
  const Vec2 dir2(-std::cos(th), -std::sin(th));  // edge 2 from the origin outward
  ASSERT_GT(p.dot(dir2), 0.0);                            // projects inside edge 2
  ASSERT_LT(std::abs(cross(dir2, p)), 0.2);              // and within reach of it
  const Spheropolygon a = sp(p, Vec2(-0.15, 3), Vec2(-2, 3), 0.1);
  Out out;
  ASSERT_EQ(narrow_phase(a, b, out), 1);
  EXPECT_EQ(out[0].feature, 0);
  EXPECT_EQ(out[0].other, 0);
  EXPECT_NEAR(out[0].overlap, 0.2 - 0.05, 1e-14);
  expect_vec(out[0].normal, Vec2(0, 1), 1e-14);
}

TEST(NarrowPhase, VertexInsideTheOtherCoreIsPushedOut) {
  // A's vertex 0.05 below B's top edge, i.e. inside B's core: overlap 0.2 + 0.05, and the
  // normal is still B's outward normal (so the force pushes it back, not through).
  const Spheropolygon a = sp(Vec2(2, -0.05), Vec2(3, 2), Vec2(1, 2), 0.1);
  Out out;
  const int n = narrow_phase(a, kBelow, out);
  ASSERT_GE(n, 1);
  EXPECT_EQ(out[0].feature, 0);
  EXPECT_NEAR(out[0].overlap, 0.25, 1e-14);
  EXPECT_NEAR(out[0].distance, -0.05, 1e-14);
  expect_vec(out[0].normal, Vec2(0, 1), 1e-14);
}

TEST(NarrowPhase, SwappingTheBodiesGivesTheSameContactsReversed) {
  // Random overlapping pairs: contact set (point, overlap) is the same in both orders,
  // normals are opposite; every overlap matches the vertex's brute-force distance to
  // the other core's three edges.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto seg_dist = [](const Vec2& p, const Vec2& a, const Vec2& b) {
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    return (p - (a + t * (b - a))).norm();
  };
  int total = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    auto tri = [&](const Vec2& c) {
      std::array<Vec2, 3> p;
      do {
        for (auto& q : p) q = c + Vec2(u(rng), u(rng));
      } while (std::abs(cross(p[1] - p[0], p[2] - p[0])) < 0.3);
      return sp(p[0], p[1], p[2], 0.05 + 0.1 * std::abs(u(rng)));
    };
    const Spheropolygon a = tri(Vec2(0, 0));
    const Spheropolygon b = tri(Vec2(1.3 + 0.3 * u(rng), 0.3 * u(rng)));
    Out ab, ba;
    const int nab = narrow_phase(a, b, ab);
    const int nba = narrow_phase(b, a, ba);
    ASSERT_EQ(nab, nba);
    total += nab;
    for (int k = 0; k < nab; ++k) {
      const ContactGeometry& g = ab[k];
      EXPECT_NEAR(g.normal.norm(), 1.0, 1e-14);
      // The same contact in the other order: same point and overlap, opposite normal.
      int match = -1;
      for (int m = 0; m < nba; ++m)
        if ((ba[m].point - g.point).norm() < 1e-12) match = m;
      ASSERT_GE(match, 0);
      EXPECT_NEAR(ba[match].overlap, g.overlap, 1e-14);
      EXPECT_NEAR((ba[match].normal + g.normal).norm(), 0.0, 1e-14);
      // Overlap against brute force (vertices outside the other core).
      const bool side0 = g.feature < 3;
      const Spheropolygon& owner = side0 ? a : b;
      const Spheropolygon& other = side0 ? b : a;
      const Vec2& v = owner.core[g.feature % 3];
      if (g.distance > 0.0) {
        double dmin = 1e300;
        for (int e = 0; e < 3; ++e) dmin = std::min(dmin, seg_dist(v, other.core[e], other.core[(e + 1) % 3]));
        EXPECT_NEAR(g.overlap, a.r + b.r - dmin, 1e-14);
      }
    }
  }
  EXPECT_GT(total, 500);  // the trials did produce contacts
}

TEST(CoreEdgeScales, ExpandGivesTheDirectEdgeDataBitForBit) {
  // The per-triangle cache keeps only inv_len2, the normal scales and the proper flag;
  // expand() must rebuild exactly what the direct formulas give (the contact results
  // depend on every bit). Random cores of both orientations, plus degenerate ones.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-2.0, 2.0);
  std::vector<std::array<Vec2, 3>> cores;
  for (int k = 0; k < 2000; ++k) cores.push_back({Vec2(d(rng), d(rng)), Vec2(d(rng), d(rng)), Vec2(d(rng), d(rng))});
  cores.push_back({Vec2(1, 1), Vec2(1, 1), Vec2(1, 1)});  // collapsed to a point
  cores.push_back({Vec2(0, 0), Vec2(1, 0), Vec2(1, 0)});  // a zero-length edge
  cores.push_back({Vec2(0, 0), Vec2(1, 1), Vec2(2, 2)});  // collinear
  auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  for (const auto& c : cores) {
    const CoreEdges ce = expand(c, core_edge_scales(c));
    const double area2 = cross(c[1] - c[0], c[2] - c[0]);
    const double orient = area2 >= 0.0 ? 1.0 : -1.0;
    double max_len2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const Vec2 e = c[(k + 1) % 3] - c[k];
      const double len2 = e.squaredNorm();
      max_len2 = std::max(max_len2, len2);
      const Vec2 n = len2 > 0.0 ? Vec2((orient / std::sqrt(len2)) * Vec2(e.y(), -e.x())) : Vec2::Zero();
      EXPECT_TRUE(same(ce.e[k].x(), e.x()) && same(ce.e[k].y(), e.y()));
      EXPECT_TRUE(same(ce.inv_len2[k], len2 > 0.0 ? 1.0 / len2 : 0.0));
      EXPECT_TRUE(same(ce.n_out[k].x(), n.x()) && same(ce.n_out[k].y(), n.y()));
    }
    EXPECT_EQ(ce.proper, std::abs(area2) > 1e-14 * max_len2);
    const Vec2 lo = c[0].cwiseMin(c[1]).cwiseMin(c[2]), hi = c[0].cwiseMax(c[1]).cwiseMax(c[2]);
    EXPECT_TRUE(same(ce.lo.x(), lo.x()) && same(ce.lo.y(), lo.y()) && same(ce.hi.x(), hi.x()) && same(ce.hi.y(), hi.y()));
  }
}

TEST(CoresApart, RejectsOnlyPairsWithoutContactAndFindsVertexNeighbours) {
  // Random pairs around a shared point (as the vertex neighbours of a discrete mesh) and
  // random overlapping pairs: a rejected pair has every vertex-to-core distance above
  // r_a + r_b, and the scales overload gives exactly the CoreEdges overload's contacts.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ang(0.0, 2.0 * kPi), len(0.5, 2.0), off(-0.3, 0.3);
  int apart = 0, touching = 0;
  for (int k = 0; k < 4000; ++k) {
    const Vec2 P(1000.0 + off(rng), 500.0 + off(rng));  // away from the origin, as real coordinates
    auto tri = [&](double a0, double span) {
      const double a1 = a0 + span;
      const Vec2 p1 = P + len(rng) * Vec2(std::cos(a0), std::sin(a0)), p2 = P + len(rng) * Vec2(std::cos(a1), std::sin(a1));
      return make_spheropolygon(P, p1, p2, rounding_radius(P, p1, p2));
    };
    const double a0 = ang(rng);
    Spheropolygon a = tri(a0, 0.3 + 0.9 * len(rng) / 2.0);
    Spheropolygon b = tri(a0 + 0.2 + 4.0 * len(rng) / 2.0, 0.3 + 0.9 * len(rng) / 2.0);
    if (k % 4 == 0) b = tri(a0 + 0.2 * off(rng), 0.8);  // overlapping the first
    const CoreEdges ea = core_edges(a.core), eb = core_edges(b.core);
    if (cores_apart(a, ea, b, eb)) {
      ++apart;
      for (int v = 0; v < 3; ++v) {
        EXPECT_GT(closest_on_core(a.core[v], b.core, eb).distance, a.r + b.r);
        EXPECT_GT(closest_on_core(b.core[v], a.core, ea).distance, a.r + b.r);
      }
    }
    Out o1, o2;
    const int n1 = narrow_phase(a, ea, b, eb, o1);
    const int n2 = narrow_phase(a, core_edge_scales(a.core), b, core_edge_scales(b.core), o2);
    ASSERT_EQ(n1, n2);
    for (int c = 0; c < n1; ++c) EXPECT_TRUE(same_geometry(o1[c], o2[c]));
    touching += n1 > 0 ? 1 : 0;
  }
  EXPECT_GT(apart, 1000);    // most vertex neighbours are rejected cheaply
  EXPECT_GT(touching, 500);  // and the overlapping ones still give contacts
}

TEST(NarrowPhase, ClearanceWithoutContactBoundsTheCoreDistanceAndCheckApartChangesNoContact) {
  // Vertex neighbours and overlapping pairs as above. Whenever the scales overload finds
  // no contact and reports a clearance c > 0, the cores are at least r_a + r_b + c apart
  // (every vertex-to-core distance), whether cores_clearance() or the nearest vertex
  // query's axis gave it; skipping cores_clearance() (check_apart = false) gives the same
  // contacts. The nearest-query axis finds clearances cores_clearance() misses.
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> ang(0.0, 2.0 * kPi), len(0.5, 2.0), off(-0.3, 0.3);
  int from_sat = 0, from_query = 0, touching = 0;
  for (int k = 0; k < 4000; ++k) {
    const Vec2 P(1000.0 + off(rng), 500.0 + off(rng));
    auto tri = [&](const Vec2& apex, double a0, double span) {
      const double a1 = a0 + span;
      const Vec2 p1 = apex + len(rng) * Vec2(std::cos(a0), std::sin(a0)), p2 = apex + len(rng) * Vec2(std::cos(a1), std::sin(a1));
      return make_spheropolygon(apex, p1, p2, rounding_radius(apex, p1, p2));
    };
    const double a0 = ang(rng), sa_ = 0.3 + 0.9 * len(rng) / 2.0, sb_ = 0.3 + 0.9 * len(rng) / 2.0;
    Spheropolygon a = tri(P, a0, sa_);
    // Around the same apex, moved by up to a few rounding radii (gaps, touches, overlaps);
    // every other one opposite a (corner facing corner across the apex).
    const Vec2 Q = P + 0.02 * off(rng) * Vec2(std::cos(a0 + 1.0), std::sin(a0 + 1.0));
    Spheropolygon b = k % 4 == 0 ? tri(Q, a0 + 0.2 * off(rng), 0.8) : tri(Q, a0 + 0.2 + 4.0 * len(rng) / 2.0, sb_);
    if (k % 2 == 1) {  // two non-adjacent triangles of a fan of six around P (a mesh vertex):
      // opposite ones are corner to corner, at exactly r_a + r_b along the edge normals
      std::array<double, 6> ray;
      for (int q = 0; q < 6; ++q) ray[q] = a0 + q * kPi / 3.0;  // equal angles, as structured meshes have
      auto fan = [&](int q) {
        const Vec2 p1 = P + (0.8 + 0.2 * len(rng)) * Vec2(std::cos(ray[q]), std::sin(ray[q]));
        const Vec2 p2 = P + (0.8 + 0.2 * len(rng)) * Vec2(std::cos(ray[(q + 1) % 6]),
                                            std::sin(ray[(q + 1) % 6]));
        return make_spheropolygon(P, p1, p2, rounding_radius(P, p1, p2));
      };
      a = fan(0);
      b = fan(2 + k / 2 % 3);
    }
    const CoreEdgeScales sa = core_edge_scales(a.core), sb = core_edge_scales(b.core);
    const CoreEdges ea = core_edges(a.core), eb = core_edges(b.core);
    Out o1, o2;
    double c1 = -1.0, c2 = -1.0;
    const int n1 = narrow_phase(a, sa, b, sb, o1, &c1, true);
    const int n2 = narrow_phase(a, sa, b, sb, o2, &c2, false);
    ASSERT_EQ(n1, n2);
    for (int c = 0; c < n1; ++c) EXPECT_TRUE(same_geometry(o1[c], o2[c]));
    if (n1 > 0) {
      ++touching;
      EXPECT_EQ(c1, 0.0);
      EXPECT_EQ(c2, 0.0);
      continue;
    }
    for (const double c : {c1, c2}) {
      EXPECT_GE(c, 0.0);
      for (int v = 0; v < 3; ++v) {
        EXPECT_GE(closest_on_core(a.core[v], b.core, eb).distance, a.r + b.r + c);
        EXPECT_GE(closest_on_core(b.core[v], a.core, ea).distance, a.r + b.r + c);
      }
    }
    const bool sat = cores_apart(a, ea, b, eb);
    from_sat += sat ? 1 : 0;
    from_query += !sat && c1 > 0.0 ? 1 : 0;
  }
  EXPECT_GT(touching, 300);
  EXPECT_GT(from_sat, 300);
  EXPECT_GT(from_query, 100);  // corner-to-corner neighbours no edge normal separates
}

namespace {

using dsdem::test::same_bits;

// Every field of two query results equal, bit for bit.
::testing::AssertionResult same_closest(const CoreClosest& got, const CoreClosest& want) {
  if (same_bits(got.distance, want.distance) && same_bits(got.point.x(), want.point.x()) &&
      same_bits(got.point.y(), want.point.y()) && same_bits(got.normal.x(), want.normal.x()) &&
      same_bits(got.normal.y(), want.normal.y()) && got.edge == want.edge && same_bits(got.t, want.t) &&
      got.at_vertex == want.at_vertex && got.vertex == want.vertex)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "got d " << got.distance << " edge " << got.edge << " t " << got.t
                                       << " vertex " << got.vertex << " at " << got.at_vertex << ", want d "
                                       << want.distance << " edge " << want.edge << " t " << want.t << " vertex "
                                       << want.vertex << " at " << want.at_vertex;
}

// A random core near the origin: proper of either orientation, or degenerate.
std::array<Vec2, 3> random_core(std::mt19937& rng, int kind) {
  std::uniform_real_distribution<double> d(-2.0, 2.0);
  std::array<Vec2, 3> c{Vec2(d(rng), d(rng)), Vec2(d(rng), d(rng)), Vec2(d(rng), d(rng))};
  if (kind == 1) c[2] = c[1];                        // a zero-length edge
  if (kind == 2) c[1] = c[2] = c[0];                 // collapsed to a point
  if (kind == 3) c[2] = c[0] + 0.25 * (c[1] - c[0]);  // three points on a line
  return c;
}

// Three query points for `trial` around `core`, in turn anywhere, on an edge, on a vertex,
// inside and near a vertex.
std::array<Vec2, 3> points_around(const std::array<Vec2, 3>& core, int trial, std::mt19937& rng) {
  std::uniform_real_distribution<double> d(-3.0, 3.0), unit(0.0, 1.0);
  std::array<Vec2, 3> p;
  for (int v = 0; v < 3; ++v) {
    const int k = (trial + v) % 3;
    switch ((trial / 3 + v) % 5) {
      case 0: p[v] = Vec2(d(rng), d(rng)); break;                                      // anywhere
      case 1: p[v] = core[k] + unit(rng) * (core[(k + 1) % 3] - core[k]); break;       // on an edge
      case 2: p[v] = core[k]; break;                                                   // on a vertex
      case 3: p[v] = (core[0] + core[1] + core[2]) / 3.0 + 0.1 * Vec2(d(rng), d(rng)); break;  // inside
      default: p[v] = core[k] + 0.05 * Vec2(d(rng), d(rng)); break;                    // near a vertex
    }
  }
  return p;
}

}  // namespace

TEST(VertexQueries, ThreeAtOnceEqualTheScalarQueryBitForBit) {
  // closest_within_x3 (vector lanes where the CPU has AVX2) against closest_within, for
  // points far off, beyond an edge line, near, inside, on an edge and on a vertex.
  RecordProperty("vectorised", closest_within_x3_vectorised() ? "yes" : "no");
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int inside = 0, at_vertex = 0, far = 0, on_edge = 0;
  for (int trial = 0; trial < 30000; ++trial) {
    const std::array<Vec2, 3> core = random_core(rng, trial % 9 < 6 ? 0 : trial % 9 - 5);
    const CoreEdges ce = core_edges(core);
    const std::array<Vec2, 3> p = points_around(core, trial, rng);
    const double reach = trial % 4 == 0 ? 0.0 : 0.5 * unit(rng);
    std::array<CoreClosest, 3> got;
    closest_within_x3(p, core, ce, reach, got);
    for (int v = 0; v < 3; ++v) {
      const CoreClosest want = closest_within(p[v], core, ce, reach);
      ASSERT_TRUE(same_closest(got[v], want)) << "trial " << trial << " vertex " << v;
      far += std::isinf(want.distance) ? 1 : 0;
      inside += want.distance < 0.0 ? 1 : 0;
      at_vertex += want.at_vertex ? 1 : 0;
      on_edge += std::isfinite(want.distance) && !want.at_vertex && want.distance >= 0.0 ? 1 : 0;
    }
  }
  // Every branch of the scalar query was taken many times.
  EXPECT_GT(far, 1000);
  EXPECT_GT(inside, 1000);
  EXPECT_GT(at_vertex, 1000);
  EXPECT_GT(on_edge, 1000);
}

TEST(VertexQueries, SixAtOnceEqualTheScalarQueriesBitForBit) {
  // vertex_queries_x6 (both sides of a pair in the eight AVX-512 lanes) against
  // closest_within: one core's vertices placed far off, beyond an edge line, near, inside,
  // on an edge and on a vertex of the other core (each side in turn), degenerate cores,
  // and pairs with one side or both sides far.
  if (!set_vertex_queries_x6(true)) GTEST_SKIP() << "this CPU has no AVX-512F: narrow_phase() uses closest_within_x3()";
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int inside = 0, at_vertex = 0, far = 0, on_edge = 0, one_side_far = 0;
  for (int trial = 0; trial < 30000; ++trial) {
    const std::array<Vec2, 3> target = random_core(rng, trial % 9 < 6 ? 0 : trial % 9 - 5);
    std::array<Vec2, 3> placed = points_around(target, trial, rng);
    if (trial % 17 == 0)  // one side far from the other core, or (every third time) both
      for (Vec2& v : placed) v += Vec2(trial % 3 == 0 ? 50.0 : 5.0, 0.0);
    // Side 0 queries a's vertices on b's core, side 1 b's on a's: the placed vertices
    // take each side in turn.
    const bool placed_is_a = trial % 2 == 0;
    const std::array<Vec2, 3>& a = placed_is_a ? placed : target;
    const std::array<Vec2, 3>& b = placed_is_a ? target : placed;
    const CoreEdges ea = core_edges(a), eb = core_edges(b);
    const double reach = trial % 4 == 0 ? 0.0 : 0.5 * unit(rng);
    std::array<CoreClosest, 3> got_a, got_b;
    vertex_queries_x6(a, ea, b, eb, reach, got_a, got_b);
    int far_a = 0, far_b = 0;
    for (int v = 0; v < 3; ++v) {
      const CoreClosest want_a = closest_within(a[v], b, eb, reach);
      const CoreClosest want_b = closest_within(b[v], a, ea, reach);
      ASSERT_TRUE(same_closest(got_a[v], want_a)) << "trial " << trial << " a's vertex " << v;
      ASSERT_TRUE(same_closest(got_b[v], want_b)) << "trial " << trial << " b's vertex " << v;
      for (const CoreClosest* want : {&want_a, &want_b}) {
        far += std::isinf(want->distance) ? 1 : 0;
        inside += want->distance < 0.0 ? 1 : 0;
        at_vertex += want->at_vertex ? 1 : 0;
        on_edge += std::isfinite(want->distance) && !want->at_vertex && want->distance >= 0.0 ? 1 : 0;
      }
      far_a += std::isinf(want_a.distance) ? 1 : 0;
      far_b += std::isinf(want_b.distance) ? 1 : 0;
    }
    one_side_far += (far_a == 3) != (far_b == 3) ? 1 : 0;
  }
  // Every branch of the scalar query was taken many times, and the pass with one side's
  // lanes all far.
  EXPECT_GT(far, 1000);
  EXPECT_GT(inside, 1000);
  EXPECT_GT(at_vertex, 1000);
  EXPECT_GT(on_edge, 1000);
  EXPECT_GT(one_side_far, 500);
}

TEST(VertexQueries, NarrowPhaseGivesTheSameContactsWithAndWithoutTheVectorLanes) {
  // Three ways: both sides in one AVX-512 pass (where the CPU has it), each side in AVX2
  // lanes, and the scalar queries.
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> d(-1.0, 1.0), unit(0.0, 1.0);
  const bool vectorised = closest_within_x3_vectorised();
  const bool x6 = vertex_queries_x6_enabled();
  int contacts = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    const std::array<Vec2, 3> ca = random_core(rng, trial % 11 == 0 ? 3 : 0);
    std::array<Vec2, 3> cb = random_core(rng, trial % 13 == 0 ? 1 : 0);
    for (Vec2& v : cb) v = 0.5 * v + Vec2(d(rng), d(rng));
    const Spheropolygon a{ca, 0.2 * unit(rng)}, b{cb, 0.2 * unit(rng)};
    const CoreEdgeScales sa = core_edge_scales(a.core), sb = core_edge_scales(b.core);
    Out x8, x4, x1;
    double clear_x8 = 0.0, clear_x4 = 0.0, clear_x1 = 0.0;
    set_vertex_queries_x6(true);
    const int n8 = narrow_phase(a, sa, b, sb, x8, &clear_x8, trial % 2 == 0);
    set_vertex_queries_x6(false);
    set_closest_within_x3_vectorised(true);
    const int n4 = narrow_phase(a, sa, b, sb, x4, &clear_x4, trial % 2 == 0);
    set_closest_within_x3_vectorised(false);
    const int n1 = narrow_phase(a, sa, b, sb, x1, &clear_x1, trial % 2 == 0);
    set_closest_within_x3_vectorised(vectorised);
    set_vertex_queries_x6(x6);
    ASSERT_EQ(n8, n1) << "trial " << trial;
    ASSERT_EQ(n4, n1) << "trial " << trial;
    EXPECT_TRUE(same_bits(clear_x8, clear_x1)) << "trial " << trial;
    EXPECT_TRUE(same_bits(clear_x4, clear_x1)) << "trial " << trial;
    for (int k = 0; k < n1; ++k) {
      EXPECT_TRUE(same_geometry(x8[k], x1[k])) << "trial " << trial << " contact " << k;
      EXPECT_TRUE(same_geometry(x4[k], x1[k])) << "trial " << trial << " contact " << k;
    }
    contacts += n1;
  }
  EXPECT_GT(contacts, 2000);
}
