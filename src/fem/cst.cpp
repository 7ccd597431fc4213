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
