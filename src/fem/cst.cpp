#include "fem/cst.hpp"

#include <algorithm>
#include <cmath>

namespace dsdem::fem {

ReferenceGeometry reference_geometry(const Vec2& X0, const Vec2& X1, const Vec2& X2) {
  Mat2 Dm;
  Dm.col(0) = X1 - X0;
  Dm.col(1) = X2 - X0;
  const double det = Dm.determinant();
  ReferenceGeometry g;
  g.area = 0.5 * det;
  g.Dm_inv = det != 0.0 ? Mat2(Dm.inverse()) : Mat2(Mat2::Zero());
  return g;
}

Mat2 deformation_gradient(const Vec2& x0, const Vec2& x1, const Vec2& x2, const Mat2& Dm_inv) {
  Mat2 Ds;
  Ds.col(0) = x1 - x0;
  Ds.col(1) = x2 - x0;
  return Ds * Dm_inv;
}

Vec3 green_strain(const Mat2& F) {
  const Mat2 C = F.transpose() * F;
  return Vec3(0.5 * (C(0, 0) - 1.0), 0.5 * (C(1, 1) - 1.0), C(0, 1));
}

Vec3 svk_stress(const Vec3& E, const ElasticConstants& c) {
  const double tr = E[0] + E[1];
  return Vec3(c.lambda * tr + 2.0 * c.mu * E[0], c.lambda * tr + 2.0 * c.mu * E[1], c.mu * E[2]);
}

static Mat2 to_tensor(const Vec3& s) {
  Mat2 m;
  m << s[0], s[2], s[2], s[1];
  return m;
}

Vec3 cauchy_from_pk2(const Mat2& F, const Vec3& S) {
  const Mat2 sigma = F * to_tensor(S) * F.transpose() / F.determinant();
  return Vec3(sigma(0, 0), sigma(1, 1), 0.5 * (sigma(0, 1) + sigma(1, 0)));
}

// Nodal forces -A0 t P grad0(N): nodes 1 and 2 take the columns of P Dm_inv^T, node 0
// the negative of their sum (the shape-function gradients sum to zero).
static void nodal_forces(const Mat2& P, const Mat2& Dm_inv, double scale, std::array<Vec2, 3>& f) {
  const Mat2 H = -scale * P * Dm_inv.transpose();
  f[1] = H.col(0);
  f[2] = H.col(1);
  f[0] = -(f[1] + f[2]);
}

void triangle_internal_force(const TriangleInput& in, const ElasticConstants& c,
                             TriangleResponse& out, std::array<Vec2, 3>& damping_force) {
  const Mat2 F = deformation_gradient(in.x[0], in.x[1], in.x[2], in.Dm_inv);
  out.detF = F.determinant();
  const Vec3 E = green_strain(F);
  const Vec3 S = in.S0 + svk_stress(E, c);
  const double scale = in.area0 * in.thickness;
  nodal_forces(F * to_tensor(S), in.Dm_inv, scale, out.force);
  out.green = E;
  if (in.cauchy) out.cauchy = cauchy_from_pk2(F, S);
  const Vec3 DE = svk_stress(E, c);
  out.strain_energy = scale * (in.S0.dot(E) + 0.5 * (DE[0] * E[0] + DE[1] * E[1] + DE[2] * E[2]));

  if (in.beta > 0.0) {
    // Edot = sym(F^T Fdot); damping stress beta * D Edot (DESIGN.md §6).
    const Mat2 Fdot = deformation_gradient(in.v[0], in.v[1], in.v[2], in.Dm_inv);
    const Mat2 Ed = 0.5 * (F.transpose() * Fdot + Fdot.transpose() * F);
    const Vec3 Sd = in.beta * svk_stress(Vec3(Ed(0, 0), Ed(1, 1), 2.0 * Ed(0, 1)), c);
    nodal_forces(F * to_tensor(Sd), in.Dm_inv, scale, damping_force);
  } else {
    damping_force = {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  }
}

double characteristic_length(const Vec2& x0, const Vec2& x1, const Vec2& x2) {
  const double area2 = std::abs((x1 - x0).x() * (x2 - x0).y() - (x1 - x0).y() * (x2 - x0).x());
  const double longest = std::max({(x1 - x0).norm(), (x2 - x1).norm(), (x0 - x2).norm()});
  return longest > 0.0 ? area2 / longest : 0.0;
}

double critical_time_step(double h, double cp, double beta) {
  const double omega = 2.0 * cp / h;
  const double xi = 0.5 * beta * omega;
  return (2.0 / omega) * (std::sqrt(1.0 + xi * xi) - xi);
}

}  // namespace dsdem::fem
