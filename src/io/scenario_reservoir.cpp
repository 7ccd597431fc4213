// The reservoir section of the scenario (DESIGN.md §13).
#include <fmt/format.h>

#include "io/scenario_sections.hpp"

namespace dsdem::io::detail {

void read_reservoir(SchemaReader& r, YAML::Node& root, Scenario& sc) {
  const KeyPath top{"", ""};
  YAML::Node s = r.section(root, top, "reservoir", YAML::NodeType::Map);
  if (!s.IsDefined()) return;
  const KeyPath p = top.child("reservoir");
  r.check_keys(s, p);
  ReservoirSpec& res = sc.reservoir;
  res.present = true;
  res.where = location(r, s, p.actual);
  res.level = r.number(s, p, "level").value_or(0.0);
  if (auto x = r.vector2(s, p, "x")) {
    res.x_min = (*x)[0];
    res.x_max = (*x)[1];
    if (!(res.x_max > res.x_min))
      r.error(s["x"], p.child("x").actual, fmt::format("[{}, {}]: give [x_min, x_max] with x_min < x_max", res.x_min, res.x_max));
  }
  res.density = r.number(s, p, "density").value_or(1000.0);
}

}  // namespace dsdem::io::detail
