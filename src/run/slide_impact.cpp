#include "run/slide_impact.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "run/water.hpp"

namespace dsdem::run {

namespace {

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void fail(const io::ReservoirSpec& spec, const std::string& what) {
  throw io::ScenarioError({spec.where.describe(what)});
}

Vec2 centroid_velocity(const Model& m, std::size_t t) {
  const auto& c = m.triangles.conn[t];
  return (m.nodes.v[c[0]] + m.nodes.v[c[1]] + m.nodes.v[c[2]]) / 3.0;
}

bool moving_discrete(const Model& m, std::size_t t) {
  return m.triangles.zone[t] == Zone::Discrete && centroid_velocity(m, t).squaredNorm() > kSlideSpeed * kSlideSpeed;
}

}  // namespace

bool has_slide(const Model& model) {
  return std::any_of(model.triangles.zone.begin(), model.triangles.zone.end(), [](Zone z) { return z == Zone::Discrete; });
}

Shore find_shore(const Model& model, const io::ReservoirSpec& spec) {
  Shore s;
  s.level = spec.level;
  s.x_min = spec.x_min;
  s.x_max = spec.x_max;
  s.density = spec.density;
  double discrete_area = 0.0, discrete_x = 0.0;
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    if (model.triangles.zone[t] != Zone::Discrete) continue;
    const auto& c = model.triangles.conn[t];
    const double a = model.triangles.area0[t];
    discrete_area += a;
    discrete_x += a * (model.nodes.X[c[0]].x() + model.nodes.X[c[1]].x() + model.nodes.X[c[2]].x()) / 3.0;
  }
  if (!(discrete_area > 0.0)) fail(spec, "the model has no discrete zone: no slide can enter the reservoir");
  const std::vector<Vec2> ground = ground_surface(model, /*without_discrete=*/true);
  // The deepest bed inside the reservoir.
  std::size_t deep = ground.size();
  for (std::size_t i = 0; i < ground.size(); ++i)
    if (ground[i].x() >= s.x_min && ground[i].x() <= s.x_max && std::isfinite(ground[i].y()) &&
        (deep == ground.size() || ground[i].y() < ground[deep].y()))
      deep = i;
  if (deep == ground.size() || !(ground[deep].y() < s.level))
    fail(spec, fmt::format("no bed below the level {} m between x = {} and {} m", s.level, s.x_min, s.x_max));
  s.depth = s.level - ground[deep].y();
  // From the deepest bed toward the slide, the first sample at or above the level is the bank.
  const int dir = discrete_x / discrete_area < ground[deep].x() ? -1 : 1;
  auto rise = [&](double z) -> std::optional<Vec2> {
    for (auto i = static_cast<std::ptrdiff_t>(deep); i >= 0 && i < static_cast<std::ptrdiff_t>(ground.size()); i += dir) {
      const Vec2& q = ground[static_cast<std::size_t>(i)];
      if (!std::isfinite(q.y()) || q.y() < z) continue;
      const Vec2& p = ground[static_cast<std::size_t>(i - dir)];  // below z: interpolate the crossing
      return p + (q - p) * ((z - p.y()) / (q.y() - p.y()));
    }
    return std::nullopt;
  };
  const std::optional<Vec2> top = rise(s.level), mid = rise(s.level - 0.5 * s.depth);
  if (!top || !mid)
    fail(spec, fmt::format("the ground does not rise through the level {} m on the slide's side of the reservoir", s.level));
  s.shoreline = *top;
  const Vec2 bank = *mid - *top;  // down the bank
  s.downslope = bank.normalized();
  s.slope_deg = std::atan2(-bank.y(), std::abs(bank.x())) * 180.0 / kPi;
  return s;
}

water::SlideImpact measure_slide(const Model& model, const Shore& shore) {
  water::SlideImpact out;
  out.slope_deg = shore.slope_deg;
  out.depth = shore.depth;
  out.water_density = shore.density;
  const auto& tri = model.triangles;
  Vec2 momentum = Vec2::Zero();
  double mass = 0.0, size = 0.0;
  std::size_t n = 0;
  for (std::size_t t = 0; t < tri.size(); ++t) {
    if (!moving_discrete(model, t)) continue;
    const double m = model.materials[tri.material[t]].rho * tri.area0[t] * model.thickness;
    mass += m;
    momentum += m * centroid_velocity(model, t);
    size += std::sqrt(2.0 * tri.area0[t]);
    ++n;
  }
  if (n == 0) return out;
  out.mass = mass;
  out.speed = (momentum / mass).norm();
  // Thickness across the bank: in bins along it, the spread of the nodes' normal coordinate.
  const Vec2 d = shore.downslope, normal(-d.y(), d.x());
  const double bin = 4.0 * size / static_cast<double>(n);
  std::map<long, std::pair<double, double>> spread;
  for (std::size_t t = 0; t < tri.size(); ++t) {
    if (!moving_discrete(model, t)) continue;
    for (Index i : tri.conn[t]) {
      const Vec2 x = model.nodes.x(i);
      const auto key = static_cast<long>(std::floor(d.dot(x) / bin));
      auto [it, fresh] = spread.try_emplace(key, normal.dot(x), normal.dot(x));
      if (!fresh) it->second = {std::min(it->second.first, normal.dot(x)), std::max(it->second.second, normal.dot(x))};
    }
  }
  for (const auto& [key, lohi] : spread) out.thickness = std::max(out.thickness, lohi.second - lohi.first);
  return out;
}

double slide_front(const Model& model, const Shore& shore) {
  const int dir = wave_direction(shore);
  double front = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    if (model.triangles.zone[t] != Zone::Discrete) continue;
    for (Index i : model.triangles.conn[t]) {
      const double x = model.nodes.x(i).x();
      if (std::isnan(front) || (x - front) * dir > 0.0) front = x;
    }
  }
  return front;
}

std::vector<double> moved_rock_tops(const Model& model, std::span<const double> xs, double min_displacement) {
  std::vector<double> top(xs.size(), -std::numeric_limits<double>::infinity());
  if (xs.empty()) return top;  // a run without gauges: no pass over the triangles at each row
  const double d2 = min_displacement * min_displacement;
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    if (model.triangles.zone[t] != Zone::Discrete) continue;
    const auto& c = model.triangles.conn[t];
    bool moved = false;
    double x0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (Index i : c) {
      const Vec2 x = model.nodes.x(i);
      moved = moved || (x - model.nodes.X[static_cast<std::size_t>(i)]).squaredNorm() > d2;
      x0 = std::min(x0, x.x()), x1 = std::max(x1, x.x()), y1 = std::max(y1, x.y());
    }
    if (!moved) continue;
    for (std::size_t g = 0; g < xs.size(); ++g)
      if (xs[g] >= x0 && xs[g] <= x1) top[g] = std::max(top[g], y1);
  }
  return top;
}

bool SlideImpactWatch::observe(const Model& model, double time) {
  if (impact_) return false;
  const auto& tri = model.triangles;
  std::optional<Vec2> lowest;
  for (std::size_t t = 0; t < tri.size(); ++t) {
    if (tri.zone[t] != Zone::Discrete) continue;
    for (Index i : tri.conn[t]) {
      // A node that started above the level and is now below it, inside the reservoir.
      const Vec2 x = model.nodes.x(i);
      if (x.y() < shore_.level && model.nodes.X[i].y() >= shore_.level && x.x() >= shore_.x_min &&
          x.x() <= shore_.x_max && (!lowest || x.y() < lowest->y()) && moving_discrete(model, t))
        lowest = x;
    }
  }
  if (!lowest) return false;
  impact_ = SlideAtImpact{time, *lowest, measure_slide(model, shore_)};
  return true;
}

}  // namespace dsdem::run
