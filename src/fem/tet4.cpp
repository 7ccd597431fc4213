#include "fem/tet4.hpp"

#include <algorithm>
#include <cmath>

namespace dsdem::fem {

TetReferenceGeometry tet_reference_geometry(const Vec3& X0, const Vec3& X1, const Vec3& X2, const Vec3& X3) {
  Mat3 Dm;
  Dm.col(0) = X1 - X0;
  Dm.col(1) = X2 - X0;
  Dm.col(2) = X3 - X0;
  const double det = Dm.determinant();
  TetReferenceGeometry g;
  g.volume = det / 6.0;
  g.Dm_inv = det != 0.0 ? Mat3(Dm.inverse()) : Mat3(Mat3::Zero());
  return g;
}

double characteristic_length(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  // 3 V / A_max = |det| / (2 A_max), and 2 A of a face is its edges' cross product's norm.
  const Vec3 a = x1 - x0, b = x2 - x0, c = x3 - x0;
  const double det6 = std::abs(a.dot(b.cross(c)));
  const double face2 = std::max({a.cross(b).norm(), a.cross(c).norm(), b.cross(c).norm(), (x2 - x1).cross(x3 - x1).norm()});
  return face2 > 0.0 ? det6 / face2 : 0.0;
}

}  // namespace dsdem::fem
