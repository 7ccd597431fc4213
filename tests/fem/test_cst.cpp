#include <algorithm>
// Unit tests of the CST kernel (docs/theory.md §2).
#include <gtest/gtest.h>

#include <cmath>

#include <random>

#include "common/same_bits.hpp"
#include "fem/cst.hpp"
#include "mesh/model_builder.hpp"
#include "common/materials.hpp"
#include "model/model.hpp"

using namespace dsdem;

namespace {

Mat2 rotation(double angle) {
  Mat2 R;
  R << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return R;
}

fem::TriangleInput reference_triangle() {
  fem::TriangleInput in;
  const Vec2 X0(0.1, 0.2), X1(1.3, 0.1), X2(0.4, 0.9);
  const auto g = fem::reference_geometry(X0, X1, X2);
  in.Dm_inv = g.Dm_inv;
  in.area0 = g.area;
  in.x = {X0, X1, X2};
  in.v = {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  return in;
}

}  // namespace

TEST(Cst, RigidRotationOfUnstressedElementGivesZeroStress) {
  const auto c = test::elastic_constants(30e9, 0.25);
  for (double deg : {1.0, 45.0, 90.0, 180.0, 270.0}) {
    fem::TriangleInput in = reference_triangle();
    const Mat2 R = rotation(deg * kPi / 180.0);
    const Vec2 shift(5.0, -3.0);
    for (auto& x : in.x) x = R * x + shift;
    fem::TriangleResponse r;
    std::array<Vec2, 3> fd;
    fem::triangle_internal_force(in, c, r, fd);
    // Round-off relative to the stress a unit strain would give.
    EXPECT_LT(r.cauchy.cwiseAbs().maxCoeff(), 1e-9 * 30e9 * 1e-3) << deg;
    for (const auto& f : r.force) EXPECT_LT(f.norm(), 1e-9 * 30e9 * 1e-3) << deg;
  }
}

TEST(Cst, PrestressedElementRotatedBy90DegreesCarriesRotatedStress) {
  const auto c = test::elastic_constants(30e9, 0.25);
  fem::TriangleInput in = reference_triangle();
  in.S0 = Vec3(-2.0e6, -5.0e6, 1.5e6);
  const double angle = kPi / 2.0;
  const Mat2 R = rotation(angle);
  for (auto& x : in.x) x = R * x;
  fem::TriangleResponse r;
  std::array<Vec2, 3> fd;
  fem::triangle_internal_force(in, c, r, fd);
  Mat2 s0;
  s0 << in.S0[0], in.S0[2], in.S0[2], in.S0[1];
  const Mat2 expected = R * s0 * R.transpose();
  const double scale = 5.0e6;
  EXPECT_NEAR(r.cauchy[0], expected(0, 0), 1e-9 * scale);
  EXPECT_NEAR(r.cauchy[1], expected(1, 1), 1e-9 * scale);
  EXPECT_NEAR(r.cauchy[2], expected(0, 1), 1e-9 * scale);
  // Rotated 90 deg: sigma_xx takes the old sigma_yy.
  EXPECT_NEAR(r.cauchy[0], -5.0e6, 1e-9 * scale);
}

TEST(Cst, UniaxialSmallStrainMatchesHooke) {
  const double E = 10e9, nu = 0.3;
  const auto c = test::elastic_constants(E, nu);
  fem::TriangleInput in = reference_triangle();
  const double eps = 1e-7;  // small: Green strain = linear strain to 1e-7 relative
  for (auto& x : in.x) x = Vec2(x.x() * (1 + eps), x.y());
  fem::TriangleResponse r;
  std::array<Vec2, 3> fd;
  fem::triangle_internal_force(in, c, r, fd);
  const double M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  EXPECT_NEAR(r.cauchy[0], M * eps, 1e-6 * M * eps);
  EXPECT_NEAR(r.cauchy[1], nu / (1 - nu) * M * eps, 1e-6 * M * eps);
  // Forces balance.
  EXPECT_LT((r.force[0] + r.force[1] + r.force[2]).norm(), 1e-12 * M * eps);
}

TEST(Cst, StiffnessDampingForceOpposesStrainRateAndVanishesForRigidMotion) {
  const auto c = test::elastic_constants(10e9, 0.2);
  fem::TriangleInput in = reference_triangle();
  in.beta = 1e-3;
  // Rigid spin about the centroid: no strain rate, no damping force.
  const Vec2 ctr = (in.x[0] + in.x[1] + in.x[2]) / 3.0;
  for (int k = 0; k < 3; ++k) in.v[k] = 2.0 * Vec2(-(in.x[k] - ctr).y(), (in.x[k] - ctr).x());
  fem::TriangleResponse r;
  std::array<Vec2, 3> fd;
  fem::triangle_internal_force(in, c, r, fd);
  for (const auto& f : fd) EXPECT_LT(f.norm(), 1e-6);
  // Stretching: the damping power is negative.
  for (int k = 0; k < 3; ++k) in.v[k] = Vec2(in.x[k].x(), 0.0);
  fem::triangle_internal_force(in, c, r, fd);
  double power = 0;
  for (int k = 0; k < 3; ++k) power += fd[k].dot(in.v[k]);
  EXPECT_LT(power, 0.0);
}

// strain_rate() in scalars is the Green strain rate of the matrix form sym(F^T Fdot) that
// it replaced (a store-forwarding stall), bit for bit, over random gradients
// of several scales and signs.
TEST(Cst, StrainRateInScalarsEqualsTheMatrixFormBitForBit) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-12.0, 12.0);
  auto value = [&] { return u(rng) * std::pow(10.0, e(rng)); };
  for (int n = 0; n < 20000; ++n) {
    Mat2 F, Fdot;
    F << 1.0 + 1e-3 * value(), value(), value(), 1.0 + 1e-3 * value();
    if (n % 2) F << value(), value(), value(), value();
    Fdot << value(), value(), value(), value();
    const Mat2 Ed = 0.5 * (F.transpose() * Fdot + Fdot.transpose() * F);
    const Vec3 expected(Ed(0, 0), Ed(1, 1), 2.0 * Ed(0, 1));
    const Vec3 got = fem::strain_rate(F, Fdot);
    for (int k = 0; k < 3; ++k) ASSERT_TRUE(test::same_bits(got[k], expected[k])) << n << " " << k;
  }
}

TEST(Cst, CriticalTimeStep) {
  EXPECT_DOUBLE_EQ(fem::critical_time_step(0.1, 1000.0, 0.0), 1e-4);
  // With stiffness damping the step shrinks: omega = 2e4, xi = 0.5*1e-5*2e4 = 0.1.
  EXPECT_NEAR(fem::critical_time_step(0.1, 1000.0, 1e-5), 1e-4 * (std::sqrt(1.01) - 0.1), 1e-15);
  EXPECT_NEAR(fem::characteristic_length(Vec2(0, 0), Vec2(2, 0), Vec2(0, 1)), 2.0 / std::sqrt(5.0), 1e-15);
}

// Patch test: any linear displacement field, imposed on an irregular patch, gives the
// same constant strain in every element and zero net force on the interior node.
TEST(Cst, PatchTestConstantStrainIsExact) {
  Material mat;
  mat.name = "m";
  mat.E = 20e9;
  mat.nu = 0.25;
  mat.rho = 2000;
  RawMesh raw;
  raw.source = "patch";
  raw.nodes = {Vec2(0, 0), Vec2(2, 0), Vec2(2, 3), Vec2(0, 3), Vec2(0.7, 1.2)};  // interior node off-centre
  raw.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  RawPhysicalGroup g;
  g.name = "domain";
  g.dim = 2;
  g.triangles = {0, 1, 2, 3};
  raw.groups = {g};
  raw.triangle_surface_group = {0, 0, 0, 0};
  Model model = mesh::build_model(raw, mat);
  const double a = 1e-4, b = -2e-4, cc = 3e-4, d = 0.5e-4;  // u = [a b; c d] X
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    const Vec2 X = model.nodes.X[i];
    model.nodes.u[i] = Vec2(a * X.x() + b * X.y(), cc * X.x() + d * X.y());
  }
  const auto c = test::elastic_constants(mat.E, mat.nu);
  std::array<Vec2, 5> f;
  f.fill(Vec2::Zero());
  Vec3 first = Vec3::Zero();
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    fem::TriangleInput in;
    for (int k = 0; k < 3; ++k) in.x[k] = model.nodes.x(model.triangles.conn[t][k]);
    in.Dm_inv = model.triangles.Dm_inv[t];
    in.area0 = model.triangles.area0[t];
    fem::TriangleResponse r;
    std::array<Vec2, 3> fd;
    fem::triangle_internal_force(in, c, r, fd);
    if (t == 0) first = r.cauchy;
    EXPECT_LT((r.cauchy - first).norm(), 1e-9 * first.norm());
    for (int k = 0; k < 3; ++k) f[model.triangles.conn[t][k]] += r.force[k];
    // Green strain of the exact linear field.
    Mat2 F;
    F << 1 + a, b, cc, 1 + d;
    const Vec3 E = fem::green_strain(F);
    EXPECT_LT((r.green - E).norm(), 1e-14);
  }
  // The interior node: mesh node 4 (the model numbers nodes in the order its triangles use them).
  const auto interior = std::find(model.nodes.origin.begin(), model.nodes.origin.end(), 4) - model.nodes.origin.begin();
  ASSERT_LT(interior, 5);
  EXPECT_EQ(model.nodes.X[static_cast<std::size_t>(interior)], Vec2(0.7, 1.2));
  EXPECT_LT(f[static_cast<std::size_t>(interior)].norm(), 1e-9 * first.norm());
}
