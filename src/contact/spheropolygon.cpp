#include "contact/spheropolygon.hpp"

#include <algorithm>

namespace dsdem::contact {

double rounding_radius(const Vec2& p0, const Vec2& p1, const Vec2& p2, double factor) {
  return factor * incircle(p0, p1, p2).radius;
}

}  // namespace dsdem::contact
