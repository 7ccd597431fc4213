#include "run/water.hpp"

#include <fmt/format.h>

#include <algorithm>
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
  w.line = water::PiezometricLine(spec.line);
  w.density = spec.density;
  w.gravity = gravity.norm();
  w.pore_pressure_in_matrix = spec.pore_pressure_in_matrix;
  for (const auto& c : spec.cracks) w.crack_levels.emplace_back(crack_group(c, model), c.level);
  return w;
}

}  // namespace dsdem::run
