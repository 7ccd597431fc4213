#include "contact/shape_map.hpp"

#include <cmath>

#include "contact/spheropolygon.hpp"

namespace dsdem::contact {

Vec3 barycentric(const Vec2& p, const Vec2& x0, const Vec2& x1, const Vec2& x2) {
  const Vec2 e1 = x1 - x0;
  const Vec2 e2 = x2 - x0;
  const double det = cross(e1, e2);
  const double scale = e1.squaredNorm() + e2.squaredNorm();
  if (!(std::abs(det) > 1e-14 * scale)) return Vec3::Constant(1.0 / 3.0);
  const Vec2 d = p - x0;
  const double n1 = cross(d, e2) / det;
  const double n2 = cross(e1, d) / det;
  return Vec3(1.0 - n1 - n2, n1, n2);
}

}  // namespace dsdem::contact
