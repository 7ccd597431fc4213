#pragma once
// Contact force to nodes (docs/theory.md §4; paper eq. 5): a force acting at a point of a
// triangle goes to its 3 nodes by the linear shape functions (barycentric
// coordinates) at that point, f_k = N_k(x_c) F. Since sum N_k = 1 and
// sum N_k x_k = x_c, the nodal forces have the same resultant and the same moment as
// the point force, so equal and opposite point forces on two triangles conserve
// momentum and angular momentum. Velocities at the point use the same N_k.
#include <array>
#include <cmath>
#include <span>

#include "model/types.hpp"

namespace dsdem::contact {

// Barycentric coordinates (N0, N1, N2) of p in the triangle x0 x1 x2 (either
// orientation). Outside the triangle some are negative; they still reproduce p
// exactly, so they are not clamped. A degenerate triangle gives (1/3, 1/3, 1/3).
Vec3 barycentric(const Vec2& p, const Vec2& x0, const Vec2& x1, const Vec2& x2);

// The per-triangle part of barycentric(), for several points of one triangle (the
// contacts of a pair): barycentric(p, barycentric_frame(x0, x1, x2)) is
// barycentric(p, x0, x1, x2) bit for bit (the same operations).
struct BarycentricFrame {
  Vec2 x0 = Vec2::Zero(), e1 = Vec2::Zero(), e2 = Vec2::Zero();
  double det = 0.0;
  bool degenerate = true;
};
inline BarycentricFrame barycentric_frame(const Vec2& x0, const Vec2& x1, const Vec2& x2) {
  BarycentricFrame f;
  f.x0 = x0;
  f.e1 = x1 - x0;
  f.e2 = x2 - x0;
  f.det = f.e1.x() * f.e2.y() - f.e1.y() * f.e2.x();
  const double scale = f.e1.squaredNorm() + f.e2.squaredNorm();
  f.degenerate = !(std::abs(f.det) > 1e-14 * scale);
  return f;
}
inline Vec3 barycentric(const Vec2& p, const BarycentricFrame& f) {
  if (f.degenerate) return Vec3::Constant(1.0 / 3.0);
  const Vec2 d = p - f.x0;
  const double n1 = (d.x() * f.e2.y() - d.y() * f.e2.x()) / f.det;
  const double n2 = (f.e1.x() * d.y() - f.e1.y() * d.x()) / f.det;
  return Vec3(1.0 - n1 - n2, n1, n2);
}

// Nodal forces N_k F.
inline std::array<Vec2, 3> distribute(const Vec3& N, const Vec2& F) {
  return {N[0] * F, N[1] * F, N[2] * F};
}

// Adds N_k F to f[nodes[k]].
inline void add_point_force(const Vec3& N, const std::array<Index, 3>& nodes, const Vec2& F,
                            std::span<Vec2> f) {
  f[nodes[0]] += N[0] * F;
  f[nodes[1]] += N[1] * F;
  f[nodes[2]] += N[2] * F;
}

// Velocity of the material point at N: sum N_k v_k.
inline Vec2 point_velocity(const Vec3& N, const std::array<Index, 3>& nodes,
                           std::span<const Vec2> v) {
  return N[0] * v[nodes[0]] + N[1] * v[nodes[1]] + N[2] * v[nodes[2]];
}

// Inverse of the mass a point force at N drives: the point's acceleration under F is
// F * sum N_k^2 / m_k. Nodes with m <= 0 count as immovable (zero inverse mass).
inline double point_inverse_mass(const Vec3& N, const std::array<Index, 3>& nodes,
                                 std::span<const double> m) {
  double inv = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double mk = m[nodes[k]];
    if (mk > 0.0) inv += N[k] * N[k] / mk;
  }
  return inv;
}

}  // namespace dsdem::contact
