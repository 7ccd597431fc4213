#pragma once
// Spheropolygon geometry of one triangle (docs/theory.md §4; paper §1.1, Fig. 1): the core
// triangle eroded by the rounding radius r, swept by a disc of radius r, so that the
// rounded outline lies inside the triangle and touches each of its edges.
#include <algorithm>
#include <array>
#include <cmath>

#include "model/types.hpp"

namespace dsdem::contact {

// Paper §1.1: rounding radius = 0.05 * radius of the inscribed circle.
constexpr double kDefaultRoundingFactor = 0.05;

// z-component of the 2D cross product a x b.
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Axis-aligned box; closed intervals, so boxes that only touch do overlap.
struct Aabb {
  Vec2 lo = Vec2::Zero();
  Vec2 hi = Vec2::Zero();
};
inline bool overlaps(const Aabb& a, const Aabb& b) {
  return a.lo.x() <= b.hi.x() && b.lo.x() <= a.hi.x() && a.lo.y() <= b.hi.y() &&
         b.lo.y() <= a.hi.y();
}

// p inside the closed box (the broad phase's rebuild test: a node that left its box).
inline bool contains(const Aabb& b, const Vec2& p) {
  return !(p.x() < b.lo.x() || p.x() > b.hi.x() || p.y() < b.lo.y() || p.y() > b.hi.y());
}

// How far apart two boxes are along x or y (the larger), > 0 only when they do not
// overlap. Each bound of a triangle's box moves at most as far as its farthest vertex,
// so the gap shrinks by at most the two triangles' vertex motions (ContactForces).
inline double box_gap(const Aabb& a, const Aabb& b) {
  return std::max(std::max(b.lo.x() - a.hi.x(), a.lo.x() - b.hi.x()), std::max(b.lo.y() - a.hi.y(), a.lo.y() - b.hi.y()));
}

struct Incircle {
  Vec2 centre = Vec2::Zero();
  double radius = 0.0;  // m
};

// Inscribed circle of the triangle p0 p1 p2 (either orientation). A degenerate
// triangle (zero perimeter) gives radius 0 at p0.
inline Incircle incircle(const Vec2& p0, const Vec2& p1, const Vec2& p2) {
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

// r = factor * inradius (paper §1.1). Computed once per triangle, from the
// reference configuration, and then kept fixed (the core follows the deformation).
double rounding_radius(const Vec2& p0, const Vec2& p1, const Vec2& p2,
                       double factor = kDefaultRoundingFactor);

// A triangle's spheropolygon: core vertices in the triangle's vertex order (so core
// edge k runs from core[k] to core[(k+1)%3]) and the rounding radius.
struct Spheropolygon {
  std::array<Vec2, 3> core{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  double r = 0.0;  // m
};

// Erodes the current triangle by r: every edge moved inward by r, which for a
// triangle is the triangle scaled about its incentre by (rho - r)/rho. The core's
// inradius is then rho - r and the rounded outline touches all three edges, so two
// triangles sharing an edge touch with zero overlap (docs/theory.md §4). If the triangle
// has been squashed to rho <= r the core collapses to the incentre (a disc).
inline Spheropolygon make_spheropolygon(const Vec2& p0, const Vec2& p1, const Vec2& p2, double r) {
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

// Bounding box of the rounded shape (core box enlarged by r).
inline Aabb bounding_box(const Spheropolygon& s) {
  Aabb box;
  box.lo = s.core[0].cwiseMin(s.core[1]).cwiseMin(s.core[2]).array() - s.r;
  box.hi = s.core[0].cwiseMax(s.core[1]).cwiseMax(s.core[2]).array() + s.r;
  return box;
}

}  // namespace dsdem::contact
