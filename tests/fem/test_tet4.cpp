// Unit and verification tests of the linear tetrahedron kernel (docs/theory.md §2).
// Voigt order (xx, yy, zz, yz, xz, xy), engineering shears in strains, as in fem/tet4.hpp.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "fem/tet4.hpp"
#include "common/materials.hpp"
#include "model/model.hpp"

using namespace dsdem;
using fem::Vec6;

namespace {

// Rotation by angle about a unit axis (Rodrigues).
Mat3 rotation(Vec3 axis, double angle) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

Mat3 tensor(const Vec6& s) {
  Mat3 m;
  m << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
  return m;
}

// A general, positively oriented tetrahedron away from the origin.
fem::TetInput reference_tet() {
  const Vec3 X0(0.1, 0.2, -0.1), X1(1.3, 0.1, 0.2), X2(0.4, 0.9, 0.05), X3(0.3, 0.35, 1.1);
  const auto g = fem::tet_reference_geometry(X0, X1, X2, X3);
  fem::TetInput in;
  in.Dm_inv = g.Dm_inv;
  in.volume0 = g.volume;
  in.x = {X0, X1, X2, X3};
  return in;
}

fem::TetResponse evaluate(const fem::TetInput& in, const fem::ElasticConstants& c) {
  fem::TetResponse r;
  std::array<Vec3, 4> fd;
  fem::tet_internal_force(in, c, r, fd);
  return r;
}

double max_force(const std::array<Vec3, 4>& f) {
  double m = 0.0;
  for (const auto& v : f) m = std::max(m, v.norm());
  return m;
}

// A unit cube split into 12 tetrahedra: each face's two triangles joined to one interior node
// placed off-centre. Nodes 0..7 the corners, node 8 the interior node.
struct Mesh {
  std::vector<Vec3> X;
  std::vector<std::array<int, 4>> tets;
};
Mesh cube_with_interior_node(const Vec3& interior) {
  Mesh m;
  for (int k = 0; k < 8; ++k) m.X.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
  m.X.push_back(interior);
  // The six faces as corner quadruples in cyclic order.
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (const auto& f : faces)
    for (const auto& tri : {std::array<int, 3>{f[0], f[1], f[2]}, std::array<int, 3>{f[0], f[2], f[3]}}) {
      std::array<int, 4> t{tri[0], tri[1], tri[2], 8};
      if (fem::tet_reference_geometry(m.X[t[0]], m.X[t[1]], m.X[t[2]], m.X[t[3]]).volume < 0) std::swap(t[1], t[2]);
      m.tets.push_back(t);
    }
  return m;
}

// The same cube split into 5 tetrahedra (a central one and four corner ones).
Mesh cube_in_five(double a, double b, double c) {
  Mesh m;
  for (int k = 0; k < 8; ++k) m.X.emplace_back(a * (k & 1), b * ((k >> 1) & 1), c * ((k >> 2) & 1));
  m.tets = {{0, 1, 2, 4}, {3, 2, 1, 7}, {5, 4, 7, 1}, {6, 7, 4, 2}, {1, 2, 4, 7}};
  for (auto& t : m.tets)
    if (fem::tet_reference_geometry(m.X[t[0]], m.X[t[1]], m.X[t[2]], m.X[t[3]]).volume < 0) std::swap(t[1], t[2]);
  return m;
}

}  // namespace

TEST(Tet4, ReferenceGeometrySignedVolume) {
  const Vec3 O(0, 0, 0), ex(1, 0, 0), ey(0, 1, 0), ez(0, 0, 1);
  const auto g = fem::tet_reference_geometry(O, ex, ey, ez);
  EXPECT_DOUBLE_EQ(g.volume, 1.0 / 6.0);
  EXPECT_LT((g.Dm_inv - Mat3::Identity()).norm(), 1e-15);
  // Two nodes swapped: the same volume, negative.
  EXPECT_DOUBLE_EQ(fem::tet_reference_geometry(O, ey, ex, ez).volume, -1.0 / 6.0);
  // A general tetrahedron: Dm_inv inverts the edge matrix and the volume is det / 6.
  const fem::TetInput in = reference_tet();
  Mat3 Dm;
  Dm << in.x[1] - in.x[0], in.x[2] - in.x[0], in.x[3] - in.x[0];
  EXPECT_NEAR(in.volume0, Dm.determinant() / 6.0, 1e-15);
  EXPECT_GT(in.volume0, 0.0);
  EXPECT_LT((in.Dm_inv * Dm - Mat3::Identity()).norm(), 1e-14);
  // Degenerate (flat): zero volume, zero Dm_inv.
  const auto flat = fem::tet_reference_geometry(O, ex, ey, Vec3(0.3, 0.3, 0.0));
  EXPECT_EQ(flat.volume, 0.0);
  EXPECT_EQ(flat.Dm_inv, Mat3::Zero());
}

TEST(Tet4, InvertedTetrahedronHasNonPositiveDetF) {
  const auto c = test::elastic_constants(30e9, 0.25);
  fem::TetInput in = reference_tet();
  EXPECT_NEAR(evaluate(in, c).detF, 1.0, 1e-14);
  // Node 3 moved through the plane of nodes 0, 1, 2 to its mirror image: det F = -1.
  const Vec3 n = (in.x[1] - in.x[0]).cross(in.x[2] - in.x[0]).normalized();
  const Vec3 x3 = in.x[3];
  in.x[3] = x3 - 2.0 * n.dot(x3 - in.x[0]) * n;
  const auto r = evaluate(in, c);
  EXPECT_NEAR(r.detF, -1.0, 1e-12);
  EXPECT_LE(r.detF, 0.0);
  // Flattened onto that plane: det F = 0, the current signed volume over the reference one.
  in.x[3] = x3 - n.dot(x3 - in.x[0]) * n;
  EXPECT_LE(evaluate(in, c).detF, 0.0);
  EXPECT_NEAR(evaluate(in, c).detF, 0.0, 1e-14);
  // Half the height: det F = 1/2.
  in.x[3] = x3 - 0.5 * n.dot(x3 - in.x[0]) * n;
  EXPECT_NEAR(evaluate(in, c).detF, 0.5, 1e-14);
}

TEST(Tet4, RigidRotationOfUnstressedTetrahedronGivesZeroStressAndForces) {
  const double E = 30e9;
  const auto c = test::elastic_constants(E, 0.25);
  const double ref_stress = 1e-3 * E;  // the stress of a strain of 1e-3
  const fem::TetInput base = reference_tet();
  const double ref_force = ref_stress * std::cbrt(base.volume0 * base.volume0);
  for (const Vec3& axis : {Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(1, 2, 3), Vec3(-0.3, 0.8, -0.5)})
    for (double deg : {1.0, 45.0, 90.0, 137.0, 180.0, 270.0}) {
      fem::TetInput in = base;
      const Mat3 R = rotation(axis, deg * kPi / 180.0);
      const Vec3 shift(5.0, -3.0, 2.0);
      for (auto& x : in.x) x = R * x + shift;
      const auto r = evaluate(in, c);
      EXPECT_LT(r.cauchy.cwiseAbs().maxCoeff(), 1e-9 * ref_stress) << deg;
      EXPECT_LT(r.green.cwiseAbs().maxCoeff(), 1e-14) << deg;
      EXPECT_LT(max_force(r.force), 1e-9 * ref_force) << deg;
      EXPECT_NEAR(r.detF, 1.0, 1e-14) << deg;
    }
}

TEST(Tet4, PrestressedTetrahedronRotatedBy90DegreesAboutASkewAxisCarriesRotatedStress) {
  const auto c = test::elastic_constants(30e9, 0.25);
  fem::TetInput in = reference_tet();
  Vec6 S0;
  S0 << -2.0e6, -5.0e6, -3.5e6, 0.8e6, -1.1e6, 1.5e6;
  in.S0 = S0;
  const auto r0 = evaluate(in, c);  // unrotated: sigma = S0, forces of S0 alone
  const Mat3 R = rotation(Vec3(1.0, 2.0, 3.0), kPi / 2.0);
  const Vec3 shift(-4.0, 7.0, 1.5);
  for (auto& x : in.x) x = R * x + shift;
  const auto r = evaluate(in, c);
  const Mat3 expected = R * tensor(S0) * R.transpose();
  const double scale = tensor(S0).norm();
  EXPECT_LT((tensor(r.cauchy) - expected).norm(), 1e-9 * scale);
  EXPECT_LT((tensor(r0.cauchy) - tensor(S0)).norm(), 1e-9 * scale);
  // The stress really turned.
  EXPECT_GT((tensor(r.cauchy) - tensor(S0)).norm(), 0.1 * scale);
  // Each nodal force is the unrotated one rotated.
  for (int a = 0; a < 4; ++a) EXPECT_LT((r.force[a] - R * r0.force[a]).norm(), 1e-9 * max_force(r0.force)) << a;
  EXPECT_GT(max_force(r0.force), 1e5);
}

TEST(Tet4, NodalForcesAreMinusTheGradientOfTheStrainEnergy) {
  const auto c = test::elastic_constants(20e9, 0.3);
  fem::TetInput in = reference_tet();
  Vec6 S0;
  S0 << -1.0e6, 0.5e6, -2.0e6, 0.3e6, -0.4e6, 0.7e6;
  in.S0 = S0;
  // A distorted state: a finite deformation (a few per cent strain plus a rotation) and a shift.
  Mat3 A;
  A << 1.04, 0.03, -0.02, -0.05, 0.97, 0.04, 0.01, -0.03, 1.06;
  const Mat3 Fimp = rotation(Vec3(0.2, -1.0, 0.4), 0.7) * A;
  for (auto& x : in.x) x = Fimp * x + Vec3(3.0, -2.0, 5.0);
  const auto r = evaluate(in, c);
  ASSERT_LT((r.green - fem::green_strain(A)).norm(), 1e-14);  // the rotation leaves E alone
  const double fmax = max_force(r.force);
  ASSERT_GT(fmax, 1e6);
  const double h = 1e-6;  // m, on edges of about 1 m
  for (int a = 0; a < 4; ++a)
    for (int d = 0; d < 3; ++d) {
      fem::TetInput p = in, m = in;
      p.x[a][d] += h;
      m.x[a][d] -= h;
      const double dW = (evaluate(p, c).strain_energy - evaluate(m, c).strain_energy) / (2.0 * h);
      EXPECT_NEAR(r.force[a][d], -dW, 1e-6 * fmax) << a << " " << d;
    }
  // Balance: the forces sum to zero, and so do their moments about the origin (the tet is
  // some 6 m from it, so a missing term would show).
  Vec3 sum = Vec3::Zero(), moment = Vec3::Zero();
  double xmax = 0.0;
  for (int a = 0; a < 4; ++a) {
    sum += r.force[a];
    moment += in.x[a].cross(r.force[a]);
    xmax = std::max(xmax, in.x[a].norm());
  }
  EXPECT_LT(sum.norm(), 1e-14 * fmax);
  EXPECT_LT(moment.norm(), 1e-13 * fmax * xmax);
}

// Patch test: a linear displacement field on a cube of 12 tetrahedra around an off-centre interior
// node gives every element the same Green strain and stress, and the interior node no net force.
TEST(Tet4, PatchTestConstantStrainIsExact) {
  const auto c = test::elastic_constants(20e9, 0.25);
  const Mesh mesh = cube_with_interior_node(Vec3(0.43, 0.58, 0.37));
  ASSERT_EQ(mesh.tets.size(), 12u);
  double total = 0.0;
  for (const auto& t : mesh.tets) {
    const double v = fem::tet_reference_geometry(mesh.X[t[0]], mesh.X[t[1]], mesh.X[t[2]], mesh.X[t[3]]).volume;
    EXPECT_GT(v, 0.0);
    total += v;
  }
  EXPECT_NEAR(total, 1.0, 1e-15);
  Mat3 small, large;  // u = A X + b: a small and a finite gradient
  small << 1e-4, -2e-4, 0.5e-4, 3e-4, 0.5e-4, -1e-4, -0.7e-4, 2e-4, -1.5e-4;
  large = 1e3 * small;
  Vec6 S0;
  S0 << -1e6, -2e6, -3e6, 0.2e6, 0.1e6, -0.3e6;
  for (const Mat3& A : {small, large})
    for (const Vec6& s0 : {Vec6(Vec6::Zero()), S0}) {
      const Mat3 F = Mat3::Identity() + A;
      const Vec3 b(0.3, -0.2, 0.1);
      const Vec6 E = fem::green_strain(F);
      const Vec6 sigma = fem::cauchy_from_pk2(F, s0 + fem::svk_stress(E, c));
      std::vector<Vec3> f(mesh.X.size(), Vec3::Zero());
      double fmax = 0.0;
      for (const auto& t : mesh.tets) {
        const auto g = fem::tet_reference_geometry(mesh.X[t[0]], mesh.X[t[1]], mesh.X[t[2]], mesh.X[t[3]]);
        fem::TetInput in;
        for (int k = 0; k < 4; ++k) in.x[k] = mesh.X[t[k]] + A * mesh.X[t[k]] + b;
        in.Dm_inv = g.Dm_inv;
        in.volume0 = g.volume;
        in.S0 = s0;
        const auto r = evaluate(in, c);
        EXPECT_LT((r.green - E).norm(), 1e-14);
        // Round-off: the stress of a strain of 1e-14, the strain's own bound.
        EXPECT_LT((r.cauchy - sigma).norm(), 1e-14 * (c.lambda + 2.0 * c.mu));
        for (int k = 0; k < 4; ++k) f[t[k]] += r.force[k];
        fmax = std::max(fmax, max_force(r.force));
      }
      ASSERT_GT(fmax, 1e3);
      EXPECT_LT(f[8].norm(), 1e-9 * fmax);
      // The boundary nodes carry the traction sigma n of the current faces: sum f = 0.
      Vec3 sum = Vec3::Zero();
      for (const auto& v : f) sum += v;
      EXPECT_LT(sum.norm(), 1e-12 * fmax);
    }
}

// Uniaxial and hydrostatic strain and simple shear in each plane against the closed form of S.
TEST(Tet4, HomogeneousStrainsMatchTheClosedFormSecondPiolaKirchhoffStress) {
  const double Y = 10e9, nu = 0.3;
  const auto c = test::elastic_constants(Y, nu);
  const double lambda = Y * nu / ((1 + nu) * (1 - 2 * nu)), mu = Y / (2 * (1 + nu));
  EXPECT_DOUBLE_EQ(c.lambda, lambda);  // the 3D Lame constants, no plane reduction
  EXPECT_DOUBLE_EQ(c.mu, mu);
  const fem::TetInput base = reference_tet();
  auto run = [&](const Mat3& F) {
    fem::TetInput in = base;
    for (auto& x : in.x) x = F * x;
    return evaluate(in, c);
  };
  const double e = 0.01;
  const double Exx = 0.5 * ((1 + e) * (1 + e) - 1.0);
  {  // uniaxial strain along x
    const auto r = run(Mat3(Vec3(1 + e, 1, 1).asDiagonal()));
    Vec6 Eexp, Sexp;
    Eexp << Exx, 0, 0, 0, 0, 0;
    Sexp << (lambda + 2 * mu) * Exx, lambda * Exx, lambda * Exx, 0, 0, 0;
    EXPECT_LT((r.green - Eexp).norm(), 1e-14);
    // sigma = F S F^T / J with F = diag(1+e, 1, 1), J = 1 + e.
    Vec6 sig;
    sig << (1 + e) * Sexp[0], Sexp[1] / (1 + e), Sexp[2] / (1 + e), 0, 0, 0;
    EXPECT_LT((r.cauchy - sig).norm(), 1e-12 * sig.norm());
    EXPECT_NEAR(r.strain_energy, base.volume0 * 0.5 * (lambda + 2 * mu) * Exx * Exx, 1e-12 * r.strain_energy);
    EXPECT_NEAR(r.detF, 1 + e, 1e-14);
  }
  {  // uniaxial strain along z, the same closed form with the axes turned
    const auto r = run(Mat3(Vec3(1, 1, 1 + e).asDiagonal()));
    Vec6 sig;
    sig << lambda * Exx / (1 + e), lambda * Exx / (1 + e), (1 + e) * (lambda + 2 * mu) * Exx, 0, 0, 0;
    EXPECT_LT((r.cauchy - sig).norm(), 1e-12 * sig.norm());
  }
  {  // hydrostatic: S = (3 lambda + 2 mu) E I = 3 K E I, sigma = S / (1 + e)
    const auto r = run((1 + e) * Mat3::Identity());
    const double S = (3 * lambda + 2 * mu) * Exx;
    Vec6 sig;
    sig << S / (1 + e), S / (1 + e), S / (1 + e), 0, 0, 0;
    EXPECT_LT((r.cauchy - sig).norm(), 1e-12 * sig.norm());
    EXPECT_NEAR(r.strain_energy, base.volume0 * 1.5 * (3 * lambda + 2 * mu) * Exx * Exx, 1e-12 * r.strain_energy);
    EXPECT_NEAR(r.detF, std::pow(1 + e, 3), 1e-14);
  }
  // Simple shear F = I + g e_i e_j^T: E_jj = g^2/2, engineering shear (ij) = g, so
  // S_ij = mu g, S_jj = (lambda + 2 mu) g^2/2, S_kk = lambda g^2/2 (k != j). The Voigt slot of
  // (i, j) is 3 for yz, 4 for xz, 5 for xy.
  const double g = 0.02;
  const int pairs[6][3] = {{1, 2, 3}, {2, 1, 3}, {0, 2, 4}, {2, 0, 4}, {0, 1, 5}, {1, 0, 5}};
  for (const auto& p : pairs) {
    const int i = p[0], j = p[1], slot = p[2];
    Mat3 F = Mat3::Identity();
    F(i, j) = g;
    Vec6 Eexp = Vec6::Zero(), Sexp = Vec6::Zero();
    Eexp[j] = 0.5 * g * g;
    Eexp[slot] = g;
    for (int k = 0; k < 3; ++k) Sexp[k] = lambda * 0.5 * g * g;
    Sexp[j] += 2 * mu * 0.5 * g * g;
    Sexp[slot] = mu * g;
    EXPECT_LT((fem::green_strain(F) - Eexp).norm(), 1e-15) << i << j;
    EXPECT_LT((fem::svk_stress(fem::green_strain(F), c) - Sexp).norm(), 1e-12 * Sexp.norm()) << i << j;
    const auto r = run(F);
    EXPECT_LT((r.green - Eexp).norm(), 1e-14) << i << j;
    const Mat3 sig = F * tensor(Sexp) * F.transpose();  // det F = 1
    EXPECT_LT((tensor(r.cauchy) - sig).norm(), 1e-12 * sig.norm()) << i << j;
    EXPECT_NEAR(r.detF, 1.0, 1e-14);
  }
}

// For small motion about the reference state the damping force of velocity v is the elastic
// force of the displacement beta v (C = beta K): linear in v, so the two agree to O(beta |grad v|).
TEST(Tet4, DampingForceIsTheElasticForceOfBetaTimesVelocity) {
  const auto c = test::elastic_constants(20e9, 0.25);
  const fem::TetInput base = reference_tet();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    fem::TetInput in = base;
    in.beta = 1e-3;
    for (auto& v : in.v) v = Vec3(u(rng), u(rng), u(rng)) * 1e-5;  // m/s: beta v ~ 1e-8 m
    fem::TetResponse r;
    std::array<Vec3, 4> fd;
    fem::tet_internal_force(in, c, r, fd);
    fem::TetInput disp = base;
    for (int a = 0; a < 4; ++a) disp.x[a] += in.beta * in.v[a];
    const auto re = evaluate(disp, c);
    const double fmax = max_force(re.force);
    ASSERT_GT(fmax, 1.0);
    // The elastic part does not see the velocities: the element is at rest in its reference state.
    EXPECT_LT(max_force(r.force), 1e-6 * fmax);
    for (int a = 0; a < 4; ++a) EXPECT_LT((fd[a] - re.force[a]).norm(), 1e-6 * fmax) << trial << " " << a;
  }
}

TEST(Tet4, DampingForceVanishesForRigidMotionAndWithoutBeta) {
  const auto c = test::elastic_constants(20e9, 0.25);
  fem::TetInput in = reference_tet();
  const Mat3 R = rotation(Vec3(1, -1, 2), 1.1);
  for (auto& x : in.x) x = R * x + Vec3(1, 2, 3);
  in.beta = 1e-3;
  // Spin with angular velocity w about a point, plus a translation: Edot = 0.
  const Vec3 w(0.3, -2.0, 1.1), ctr(0.5, 0.5, 0.5), vt(0.7, 0.1, -0.4);
  for (int a = 0; a < 4; ++a) in.v[a] = vt + w.cross(in.x[a] - ctr);
  fem::TetResponse r;
  std::array<Vec3, 4> fd;
  fem::tet_internal_force(in, c, r, fd);
  // Against the damping force of a stretching at the same speed scale.
  fem::TetInput stretch = in;
  for (int a = 0; a < 4; ++a) stretch.v[a] = w.norm() * Vec3(in.x[a].x(), 0.0, 0.0);
  std::array<Vec3, 4> fs;
  fem::tet_internal_force(stretch, c, r, fs);
  const double ref = max_force(fs);
  ASSERT_GT(ref, 1e5);
  EXPECT_LT(max_force(fd), 1e-12 * ref);
  // Stretching dissipates: negative damping power.
  double power = 0.0;
  for (int a = 0; a < 4; ++a) power += fs[a].dot(stretch.v[a]);
  EXPECT_LT(power, 0.0);
  // beta = 0: the damping forces are zeros even with velocities.
  stretch.beta = 0.0;
  fem::tet_internal_force(stretch, c, r, fs);
  for (const auto& f : fs) EXPECT_EQ(f, Vec3::Zero());
}

TEST(Tet4, CharacteristicLengthIsTheSmallestAltitude) {
  const double a = 0.7;
  // Regular tetrahedron of edge a: every altitude sqrt(2/3) a.
  const Vec3 X0(0, 0, 0), X1(a, 0, 0), X2(0.5 * a, 0.5 * std::sqrt(3.0) * a, 0),
      X3(0.5 * a, std::sqrt(3.0) / 6.0 * a, std::sqrt(2.0 / 3.0) * a);
  EXPECT_NEAR((X3 - X1).norm(), a, 1e-15);
  EXPECT_NEAR((X3 - X2).norm(), a, 1e-15);
  EXPECT_NEAR(fem::characteristic_length(X0, X1, X2, X3), std::sqrt(2.0 / 3.0) * a, 1e-15);
  EXPECT_NEAR(fem::tet_reference_geometry(X0, X1, X2, X3).volume, a * a * a / (6.0 * std::sqrt(2.0)), 1e-15);
  // The corner tetrahedron: altitudes 1, 1, 1 and 1/sqrt(3) (the origin to x + y + z = 1).
  const Vec3 O(0, 0, 0), ex(1, 0, 0), ey(0, 1, 0), ez(0, 0, 1);
  EXPECT_NEAR(fem::characteristic_length(O, ex, ey, ez), 1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(fem::characteristic_length(ez, ex, ey, O), 1.0 / std::sqrt(3.0), 1e-15);  // any order
  // A sliver (the fourth node 1 mm above the base's plane): the altitude 1e-3.
  EXPECT_NEAR(fem::characteristic_length(O, ex, ey, Vec3(0.3, 0.3, 1e-3)), 1e-3, 1e-15);
  EXPECT_EQ(fem::characteristic_length(O, ex, ey, Vec3(0.3, 0.3, 0.0)), 0.0);
  // The critical step is critical_time_step of that length.
  const double cp = 4000.0;
  EXPECT_DOUBLE_EQ(fem::tet_critical_time_step(X0, X1, X2, X3, cp, 0.0), std::sqrt(2.0 / 3.0) * a / cp);
  EXPECT_DOUBLE_EQ(fem::tet_critical_time_step(X0, X1, X2, X3, cp, 1e-5),
                   fem::critical_time_step(fem::characteristic_length(X0, X1, X2, X3), cp, 1e-5));
}

TEST(Tet4, LumpedMassSumsToRhoTimesVolume) {
  const double rho = 2650.0;
  EXPECT_DOUBLE_EQ(fem::tet_lumped_mass(rho, 0.6), 0.25 * rho * 0.6);
  const double a = 1.5, b = 0.8, c = 2.2;
  const Mesh mesh = cube_in_five(a, b, c);
  std::vector<double> m(mesh.X.size(), 0.0);
  double volume = 0.0;
  for (const auto& t : mesh.tets) {
    const double v = fem::tet_reference_geometry(mesh.X[t[0]], mesh.X[t[1]], mesh.X[t[2]], mesh.X[t[3]]).volume;
    EXPECT_GT(v, 0.0);
    volume += v;
    for (int k : t) m[k] += fem::tet_lumped_mass(rho, v);
  }
  EXPECT_NEAR(volume, a * b * c, 1e-14 * a * b * c);
  double total = 0.0;
  for (double mk : m) total += mk;
  EXPECT_NEAR(total, rho * a * b * c, 1e-13 * rho * a * b * c);
  // The central tetrahedron has a third of the box's volume: its four corners (1, 2, 4, 7) carry
  // rho V / 12 from it plus rho V / 24 from each of their three corner tetrahedra.
  EXPECT_NEAR(m[1], rho * a * b * c * (1.0 / 12.0 + 3.0 / 24.0), 1e-13 * rho * a * b * c);
  EXPECT_NEAR(m[0], rho * a * b * c / 24.0, 1e-13 * rho * a * b * c);
}

// The altitude step against the element's own stability limit 2 / omega_max, omega_max^2 the
// largest eigenvalue of M^-1 K (K by central differences of the kernel's forces, M = rho V / 4
// per node; the element's limit bounds the mesh's from below). The altitude step alone exceeds
// it, the more so as nu -> 1/2; half of it stays within it.
TEST(Tet4, HalfTheAltitudeStepIsWithinTheElementsStabilityLimit) {
  const double a = 1.0, rho = 2500.0, Y = 20e9;
  const std::array<std::array<Vec3, 4>, 5> shapes{{
      {Vec3(0, 0, 0), Vec3(a, 0, 0), Vec3(0.5 * a, 0.5 * std::sqrt(3.0) * a, 0),
       Vec3(0.5 * a, std::sqrt(3.0) / 6.0 * a, std::sqrt(2.0 / 3.0) * a)},          // regular
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)},                   // corner
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1, 1, 1)},                   // Kuhn
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.3, 0.3, 0.05)},            // sliver
      {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.1, 0), Vec3(0.03, 0.03, 1.0)}}};     // needle
  for (double nu : {0.0, 0.25, 0.45, 0.49})
    for (const auto& X : shapes) {
      const auto c = test::elastic_constants(Y, nu);
      const auto g = fem::tet_reference_geometry(X[0], X[1], X[2], X[3]);
      ASSERT_GT(g.volume, 0.0);
      fem::TetInput in;
      in.x = X;
      in.Dm_inv = g.Dm_inv;
      in.volume0 = g.volume;
      Eigen::Matrix<double, 12, 12> K;
      const double h = 1e-6;
      for (int b = 0; b < 4; ++b)
        for (int d = 0; d < 3; ++d) {
          fem::TetInput p = in, m = in;
          p.x[b][d] += h;
          m.x[b][d] -= h;
          const auto fp = evaluate(p, c).force, fm = evaluate(m, c).force;
          for (int e = 0; e < 4; ++e)
            for (int k = 0; k < 3; ++k) K(3 * e + k, 3 * b + d) = -(fp[e][k] - fm[e][k]) / (2.0 * h);
        }
      EXPECT_LT((K - K.transpose()).norm(), 1e-6 * K.norm());
      K = (0.5 * (K + K.transpose())).eval();
      const double mass = fem::tet_lumped_mass(rho, g.volume);
      const double omega = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>>(K / mass).eigenvalues().maxCoeff());
      const double cp = std::sqrt((c.lambda + 2.0 * c.mu) / rho);
      const double dt = fem::tet_critical_time_step(X[0], X[1], X[2], X[3], cp, 0.0);
      EXPECT_GT(dt, 2.0 / omega) << nu;  // the altitude alone is not a bound
      EXPECT_LT(0.5 * dt, 2.0 / omega) << nu;
    }
}
