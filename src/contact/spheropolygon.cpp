#include "contact/spheropolygon.hpp"

#include <algorithm>

namespace dsdem::contact {

Incircle incircle(const Vec2& p0, const Vec2& p1, const Vec2& p2) {
  // Incentre = vertices weighted by the lengths of the opposite edges.
  const double a = (p1 - p2).norm();
  const double b = (p2 - p0).norm();
  const double c = (p0 - p1).norm();
  const double perimeter = a + b + c;
  if (!(perimeter > 0.0)) return {p0, 0.0};
  Incircle ic;
  ic.centre = (a * p0 + b * p1 + c * p2) / perimeter;
  ic.radius = std::abs(cross(p1 - p0, p2 - p0)) / perimeter;  // r = 2A / perimeter
  return ic;
}

double rounding_radius(const Vec2& p0, const Vec2& p1, const Vec2& p2, double factor) {
  return factor * incircle(p0, p1, p2).radius;
}

Spheropolygon make_spheropolygon(const Vec2& p0, const Vec2& p1, const Vec2& p2, double r) {
  const Incircle ic = incircle(p0, p1, p2);
  // Each edge lies at distance rho from the incentre; scaling by s puts it at s*rho
  // = rho - r, i.e. moved inward by r.
  const double s = ic.radius > r ? (ic.radius - r) / ic.radius : 0.0;
  Spheropolygon sp;
  sp.core[0] = ic.centre + s * (p0 - ic.centre);
  sp.core[1] = ic.centre + s * (p1 - ic.centre);
  sp.core[2] = ic.centre + s * (p2 - ic.centre);
  sp.r = r;
  return sp;
}

Aabb bounding_box(const Spheropolygon& s) {
  Aabb box;
  box.lo = s.core[0].cwiseMin(s.core[1]).cwiseMin(s.core[2]).array() - s.r;
  box.hi = s.core[0].cwiseMax(s.core[1]).cwiseMax(s.core[2]).array() + s.r;
  return box;
}

}  // namespace dsdem::contact
