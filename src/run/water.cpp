#include "run/water.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace dsdem::run {

namespace {

// The crack's curve group, or kNoIndex unless it is a curve some joint lies on.
Index crack_group(const io::CrackWaterSpec& c, const Model& model) {
  const Index g = model.find_group(c.curve);
  if (g == kNoIndex) return kNoIndex;
  const auto& cg = model.joints.curve_group;
  return std::find(cg.begin(), cg.end(), g) == cg.end() ? kNoIndex : g;
}

}  // namespace

std::vector<Vec2> ground_surface(const Model& model, bool without_discrete) {
  const auto& X = model.nodes.X;
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min, h_min = x_min;
  for (const Vec2& p : X) x_min = std::min(x_min, p.x()), x_max = std::max(x_max, p.x());
  for (double a : model.triangles.area0) h_min = std::min(h_min, std::sqrt(2.0 * a));
  // Samples half the smallest element apart: each triangle edge raises the samples under it.
  const std::size_t n = std::max<std::size_t>(2, static_cast<std::size_t>(std::ceil((x_max - x_min) / (0.5 * h_min))) + 1);
  const double dx = (x_max - x_min) / static_cast<double>(n - 1);
  std::vector<double> top(n, -std::numeric_limits<double>::infinity());
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    if (without_discrete && model.triangles.zone[t] == Zone::Discrete) continue;
    const auto& c = model.triangles.conn[t];
    for (int k = 0; k < 3; ++k) {
      Vec2 a = X[c[k]], b = X[c[(k + 1) % 3]];
      if (a.x() > b.x()) std::swap(a, b);
      const auto i0 = static_cast<std::size_t>(std::max(0.0, std::ceil((a.x() - x_min) / dx - 1e-9)));
      const auto i1 = std::min(n - 1, static_cast<std::size_t>(std::floor((b.x() - x_min) / dx + 1e-9)));
      for (std::size_t i = i0; i <= i1; ++i) {
        const double x = x_min + static_cast<double>(i) * dx;
        const double y = b.x() > a.x() ? a.y() + (b.y() - a.y()) * std::clamp((x - a.x()) / (b.x() - a.x()), 0.0, 1.0)
                                       : std::max(a.y(), b.y());
        top[i] = std::max(top[i], y);
      }
    }
  }
  std::vector<Vec2> line;
  line.reserve(n);
  for (std::size_t i = 0; i < n; ++i) line.emplace_back(x_min + static_cast<double>(i) * dx, top[i]);
  return line;
}

bool has_water(const io::Scenario& sc) {
  return std::any_of(sc.stages.begin(), sc.stages.end(), [](const io::StageSpec& st) { return st.water.present; });
}

void check_water(const io::Scenario& sc, const Model& model) {
  std::vector<std::string> errors;
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
  for (const Vec2& X : model.nodes.X) x_min = std::min(x_min, X.x()), x_max = std::max(x_max, X.x());
  const double tol = 1e-9 * std::max(1.0, x_max - x_min);
  auto check = [&](const io::WaterSpec& w) {
    if (!w.present) return;
    if (w.line.size() > 1 && (w.line.front().x() > x_min + tol || w.line.back().x() < x_max - tol))
      errors.push_back(w.where.describe(
          fmt::format("the piezometric line spans x = {:.6g} to {:.6g} m but the model spans {:.6g} to {:.6g} m: "
                      "extend it over the whole model",
                      w.line.front().x(), w.line.back().x(), x_min, x_max)));
    for (const auto& c : w.cracks)
      if (crack_group(c, model) == kNoIndex)
        errors.push_back(c.where.describe(fmt::format(
            "no mesh curve '{}' with joints: a crack's water needs a named curve inside a discrete zone", c.curve)));
  };
  for (const auto& st : sc.stages) check(st.water);
  std::sort(errors.begin(), errors.end());
  errors.erase(std::unique(errors.begin(), errors.end()), errors.end());  // stages that share the top-level water
  if (!errors.empty()) throw io::ScenarioError(errors);
}

solver::WaterSetup water_setup(const io::WaterSpec& spec, const Model& model, Vec2 gravity) {
  solver::WaterSetup w;
  if (spec.ru <= 0.0) w.line = water::PiezometricLine(spec.line);
  w.density = spec.density;
  w.gravity = gravity.norm();
  w.pore_pressure_in_matrix = spec.pore_pressure_in_matrix;
  for (const auto& c : spec.cracks) w.crack_levels.emplace_back(crack_group(c, model), c.level);
  if (spec.ru > 0.0) {
    w.ru = spec.ru;
    w.line = water::PiezometricLine(ground_surface(model));
    for (const auto& m : model.materials) w.material_unit_weight.push_back(spec.ru * m.rho * w.gravity);
  }
  return w;
}

}  // namespace dsdem::run
