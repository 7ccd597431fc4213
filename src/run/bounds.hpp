#pragma once
// The axis-aligned bounds of a set of points (a polyline, a polygon): what the water's fill
// regions, measuring curves and their checks look at before any finer test.
#include <algorithm>
#include <limits>
#include <span>

#include "model/types.hpp"

namespace dsdem::run {

struct Bounds {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
  double x1 = -std::numeric_limits<double>::infinity(), y1 = x1;
};
inline Bounds bounds_of(std::span<const Vec2> points) {
  Bounds b;
  for (const Vec2& p : points)
    b.x0 = std::min(b.x0, p.x()), b.y0 = std::min(b.y0, p.y()), b.x1 = std::max(b.x1, p.x()), b.y1 = std::max(b.y1, p.y());
  return b;
}

}  // namespace dsdem::run
