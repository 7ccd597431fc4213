#pragma once
// Gauges follow a material point: the triangle that contains the reference point and
// the point's barycentric coordinates in it; values are interpolated with the shape
// functions, so a gauge moves with the mass it sits in (a slide, a fragment).
#include <optional>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "model/model3d.hpp"

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

// A gauge in a 3D model: the tetrahedron that holds the reference point and its four
// barycentric coordinates there.
struct Gauge3 {
  std::string name;
  Vec3 at = Vec3::Zero();  // reference position, m
  Index tetrahedron = kNoIndex;
  std::array<double, 4> weights{};
};

// As locate_gauge, over tetrahedra.
std::optional<Gauge3> locate_gauge(const Model3& model, const std::string& name, const Vec3& p, double tolerance);

Vec3 gauge_value(const Model3& model, const Gauge3& g, const std::vector<Vec3>& field);

}  // namespace dsdem::solver
