#include "contact/shape_map.hpp"

#include <cmath>

#include "contact/spheropolygon.hpp"

namespace dsdem::contact {

Vec3 barycentric(const Vec2& p, const Vec2& x0, const Vec2& x1, const Vec2& x2) {
  return barycentric(p, barycentric_frame(x0, x1, x2));
}

}  // namespace dsdem::contact
