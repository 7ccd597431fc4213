#pragma once
// Gauges follow a material point: the triangle that contains the reference point and
// the point's barycentric coordinates in it; values are interpolated with the shape
// functions, so a gauge moves with the mass it sits in (a slide, a fragment).
#include <optional>
#include <string>
#include <vector>

#include "model/model.hpp"

namespace dsdem::solver {

struct Gauge {
  std::string name;
  Vec2 at = Vec2::Zero();  // reference position, m
  Index triangle = kNoIndex;
  std::array<double, 3> weights{};  // barycentric coordinates
};

// The triangle containing p (reference configuration), or the nearest one when p lies
// in no triangle within `tolerance` (m); nullopt when nothing is that close.
std::optional<Gauge> locate_gauge(const Model& model, const std::string& name, const Vec2& p, double tolerance);

Vec2 gauge_value(const Model& model, const Gauge& g, const std::vector<Vec2>& field);

}  // namespace dsdem::solver
