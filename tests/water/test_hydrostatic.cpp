// Water at rest (docs/theory.md §8): the piezometric line, the exact edge tractions and a
// triangle's water forces against closed forms and an independent quadrature.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "joint/cohesive_law.hpp"
#include "water/hydrostatic.hpp"

using namespace dsdem;
using water::PiezometricLine;

namespace {

constexpr double kGamma = 1000.0 * 9.81;  // N/m^3

// int p N_a ds and int p N_b ds along a -> b by the midpoint rule on n pieces: an
// independent check of the exact integration (error O(1/n^2) even across kinks).
std::array<Vec2, 2> edge_forces_by_quadrature(const PiezometricLine& line, Vec2 a, Vec2 b, int n = 200000) {
  double i0 = 0.0, i1 = 0.0;
  for (int k = 0; k < n; ++k) {
    const double s = (k + 0.5) / n;
    const double p = water::pressure(line, kGamma, a + s * (b - a));
    i0 += p * (1.0 - s) / n;
    i1 += p * s / n;
  }
  const Vec2 d = b - a, ln(d.y(), -d.x());
  return {Vec2(-i0 * ln), Vec2(-i1 * ln)};
}

}  // namespace

TEST(PiezometricLine, InterpolatesAndHoldsItsEnds) {
  const PiezometricLine line({Vec2(0, 10), Vec2(10, 20), Vec2(30, 0)});
  EXPECT_DOUBLE_EQ(line.elevation(-5), 10.0);
  EXPECT_DOUBLE_EQ(line.elevation(5), 15.0);
  EXPECT_DOUBLE_EQ(line.elevation(20), 10.0);
  EXPECT_DOUBLE_EQ(line.elevation(40), 0.0);
  EXPECT_DOUBLE_EQ(line.highest(), 20.0);
  EXPECT_DOUBLE_EQ(PiezometricLine::level(3.5).elevation(-1e9), 3.5);
  EXPECT_THROW(PiezometricLine({Vec2(0, 1), Vec2(0, 2)}), std::invalid_argument);
  EXPECT_THROW(PiezometricLine(std::vector<Vec2>{}), std::invalid_argument);
}

TEST(PiezometricLine, PressureIsHydrostaticBelowAndZeroAbove) {
  const auto line = PiezometricLine::level(10.0);
  EXPECT_DOUBLE_EQ(water::pressure(line, kGamma, Vec2(3, 4)), kGamma * 6.0);
  EXPECT_EQ(water::pressure(line, kGamma, Vec2(3, 12)), 0.0);
}

// A bottom face at depth d under a flat pool: uniform p = gamma d, half p L to each node,
// pushing up into the solid above it.
TEST(EdgeForces, UniformPressureOnABottomFace) {
  const auto line = PiezometricLine::level(5.0);
  const auto f = water::edge_forces(line, kGamma, Vec2(0, 2), Vec2(2, 2));  // solid above (on the left)
  for (const Vec2& fk : f) {
    EXPECT_NEAR(fk.x(), 0.0, 1e-12 * kGamma);
    EXPECT_NEAR(fk.y(), 0.5 * kGamma * 3.0 * 2.0, 1e-9 * kGamma);
  }
}

// A vertical face of a solid on its left (x < 0) half under water: the triangular load
// gamma h^2 / 2 pushes in -x, split by the shape functions exactly.
TEST(EdgeForces, TriangularLoadOnAVerticalFace) {
  const double H = 4.0, h = 2.5;
  const auto line = PiezometricLine::level(h);
  const auto f = water::edge_forces(line, kGamma, Vec2(0, 0), Vec2(0, H));
  // int_0^h gamma (h - z) (1 - z/H) dz and int_0^h gamma (h - z) z/H dz.
  const double fb = kGamma * h * h * h / (6.0 * H), fa = 0.5 * kGamma * h * h - fb;
  EXPECT_NEAR(f[0].x(), -fa, 1e-12 * kGamma);
  EXPECT_NEAR(f[1].x(), -fb, 1e-12 * kGamma);
  EXPECT_NEAR(f[0].y(), 0.0, 1e-12 * kGamma);
}

// Across a kinked line and through its zero crossing, in both directions: the exact
// integration agrees with a fine quadrature.
TEST(EdgeForces, ExactAcrossKinksAndTheWaterline) {
  const PiezometricLine line({Vec2(-10, 2), Vec2(0.5, 5), Vec2(1.2, 3), Vec2(10, 1)});
  for (const auto& [a, b] : {std::pair{Vec2(-1, 1), Vec2(3, 6)}, std::pair{Vec2(3, 6), Vec2(-1, 1)},
                             std::pair{Vec2(-2, 4.5), Vec2(2, 2.5)}, std::pair{Vec2(0.7, -1), Vec2(0.7, 8)}}) {
    const auto f = water::edge_forces(line, kGamma, a, b);
    const auto q = edge_forces_by_quadrature(line, a, b);
    const double scale = kGamma * 5.0 * (b - a).norm();
    for (int k = 0; k < 2; ++k) EXPECT_NEAR((f[k] - q[k]).norm(), 0.0, 1e-8 * scale) << a.transpose();
  }
}

TEST(EdgeForces, ToALevelMatchesAFlatLine) {
  const Vec2 a(0.3, -2), b(1.7, 4);
  const auto f = water::edge_forces_to_level(1.5, kGamma, a, b);
  const auto g = water::edge_forces(PiezometricLine::level(1.5), kGamma, a, b);
  for (int k = 0; k < 2; ++k) EXPECT_NEAR((f[k] - g[k]).norm(), 0.0, 1e-12 * kGamma);
}

// The pore pressure alone puts no net force on a triangle (grad N sums to 0).
TEST(ElementPoreForces, SumToZeroAndPushTheCornersOut) {
  const std::array<Vec2, 3> x{Vec2(0, 0), Vec2(2, 0.3), Vec2(0.5, 1.5)};
  const auto f = water::element_pore_forces(x, 1000.0);
  EXPECT_NEAR((f[0] + f[1] + f[2]).norm(), 0.0, 1e-12);
  const Vec2 c = (x[0] + x[1] + x[2]) / 3.0;
  for (int k = 0; k < 3; ++k) EXPECT_GT(f[k].dot(x[k] - c), 0.0);
}

// A submerged triangle whose three edges are loaded: each corner gets its share of the
// buoyancy, gamma A / 3 upward, and no horizontal force (p linear: exact).
TEST(TriangleForces, SubmergedTriangleCarriesItsBuoyancyAtItsCorners) {
  water::TriangleWater in;
  in.x = {Vec2(0, 0), Vec2(2, 0.3), Vec2(0.5, 1.5)};
  in.edge = {water::EdgeWater::line, water::EdgeWater::line, water::EdgeWater::line};
  const double A = 0.5 * ((in.x[1] - in.x[0]).x() * (in.x[2] - in.x[0]).y() - (in.x[1] - in.x[0]).y() * (in.x[2] - in.x[0]).x());
  const auto f = water::triangle_forces(in, PiezometricLine::level(7.0), kGamma);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(f[k].x(), 0.0, 1e-11 * kGamma * A);
    EXPECT_NEAR(f[k].y(), kGamma * A / 3.0, 1e-11 * kGamma * A);
  }
  // Above the water: nothing.
  EXPECT_EQ(water::triangle_forces(in, PiezometricLine::level(-1.0), kGamma)[0], Vec2::Zero());
}

// Archimedes on a partly submerged square of two triangles (their shared diagonal dry):
// the net force is gamma times the submerged area, upward, exactly.
TEST(TriangleForces, FloatingSquareGetsTheWeightOfTheDisplacedWater) {
  const Vec2 p0(0, 0), p1(1, 0), p2(1, 1), p3(0, 1);
  const auto line = PiezometricLine::level(0.37);
  water::TriangleWater t1, t2;
  t1.x = {p0, p1, p2};
  t1.edge = {water::EdgeWater::line, water::EdgeWater::line, water::EdgeWater::dry};
  t2.x = {p0, p2, p3};
  t2.edge = {water::EdgeWater::dry, water::EdgeWater::line, water::EdgeWater::line};
  Vec2 net = Vec2::Zero();
  for (const auto& t : {t1, t2})
    for (const Vec2& f : water::triangle_forces(t, line, kGamma)) net += f;
  EXPECT_NEAR(net.x(), 0.0, 1e-12 * kGamma);
  EXPECT_NEAR(net.y(), kGamma * 0.37, 1e-12 * kGamma);
}

// Terzaghi on a joint (docs/theory.md §8 item 2): a horizontal joint under the total normal
// stress sigma with water at pressure p in it. The water pushes its faces apart by p, so
// in equilibrium the cohesive spring carries sigma + p, and the joint slips at
// tau = c - (sigma + p) tan(phi) (tension positive).
TEST(JointUnderWater, SlipsAtTheEffectiveNormalStress) {
  JointProperties jp;
  jp.kn = 1e10;
  jp.ks = 5e9;
  jp.ft = 1e6;
  jp.c = 3e5;
  jp.phi = 35.0 * M_PI / 180.0;
  jp.GI = 100.0;
  jp.GII = 1000.0;
  const double L = 2.0, sigma = -2.0e6, depth = 40.0;
  const double p = kGamma * depth;
  // Face a: the bottom of the block above (counter-clockwise along it: left to right);
  // face b: the top of the block below (right to left). The crack is full to z = depth.
  const Vec2 left(0.0, 0.0), right(L, 0.0);
  const auto on_a = water::edge_forces_to_level(depth, kGamma, left, right);
  const auto on_b = water::edge_forces_to_level(depth, kGamma, right, left);
  const double push = (on_a[0] + on_a[1]).y();
  EXPECT_NEAR(push, p * L, 1e-12 * p * L);
  EXPECT_NEAR((on_a[0] + on_a[1] + on_b[0] + on_b[1]).norm(), 0.0, 1e-12 * p * L);  // apart, equal and opposite
  // Face a in equilibrium: sigma L (the load from above) + the water + the spring's
  // -sn L (the normal points from a to b, downward) sum to zero.
  const double sn = sigma + push / L;
  const double dn = sn / jp.kn;
  const double tau = jp.c - (sigma + p) * std::tan(jp.phi);
  const CohesiveResponse below = cohesive_law(dn, 0.999 * tau / jp.ks, jp, JointPointState{});
  EXPECT_NEAR(below.sn, sigma + p, 1e-9 * std::abs(sigma));
  EXPECT_NEAR(below.fs, tau, 1e-9 * tau);
  EXPECT_NEAR(below.ss, 0.999 * tau, 1e-9 * tau);  // still elastic, no damage
  EXPECT_EQ(below.state.damage, 0.0);
  const CohesiveResponse beyond = cohesive_law(dn, 1.01 * tau / jp.ks, jp, JointPointState{});
  EXPECT_GT(beyond.state.damage, 0.0);  // slipping: the shear strength is passed
  EXPECT_LE(beyond.ss, tau * (1.0 + 1e-9));
}
