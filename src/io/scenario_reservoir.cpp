// The reservoir section of the scenario (docs/theory.md §11, §12).
#include <cmath>
#include <fmt/format.h>

#include "io/scenario_sections.hpp"

namespace dsdem::io::detail {

namespace {

// Each map of a list section, with its path; a non-map entry is an error.
template <class F>
void for_each_entry(SchemaReader& r, const YAML::Node& parent, const KeyPath& p, const std::string& key, F&& f) {
  YAML::Node list = r.section(parent, p, key, YAML::NodeType::Sequence);
  if (!list.IsDefined()) return;
  const KeyPath lp = p.child(key);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const KeyPath ip = lp.index(i);
    if (!list[i].IsMap()) {
      r.error(list[i], ip.actual, "expected a map (key: value lines)");
      continue;
    }
    r.check_keys(list[i], ip);
    f(list[i], ip);
  }
}

// Names within one list must differ: they become history columns.
template <class T>
void check_unique_names(SchemaReader& r, const YAML::Node& node, const KeyPath& ip, const std::vector<T>& seen,
                        const std::string& name) {
  for (const auto& o : seen)
    if (!name.empty() && o.name == name) r.error(node["name"], ip.child("name").actual, fmt::format("two entries are named '{}'", name));
}

void read_fill(SchemaReader& r, const YAML::Node& s, const KeyPath& p, SphSpec& w) {
  for_each_entry(r, s, p, "fill", [&](const YAML::Node& e, const KeyPath& ip) {
    WaterFillSpec f;
    f.where = location(r, e, ip.actual);
    const bool rect = e["rectangle"].IsDefined(), poly = e["polygon"].IsDefined();
    if (rect == poly) {
      r.error(e, ip.actual, "give either rectangle: [[x0, y0], [x1, y1]] or polygon: [[x, y], ...]");
      return;
    }
    if (rect) {
      if (auto c = r.points(e, ip, "rectangle", 2)) {
        if (c->size() != 2 || !((*c)[1].x() > (*c)[0].x()) || !((*c)[1].y() > (*c)[0].y())) {
          r.error(e["rectangle"], ip.child("rectangle").actual, "expected two corners [[x0, y0], [x1, y1]] with x1 > x0, y1 > y0");
          return;
        }
        const Vec2 a = (*c)[0], b = (*c)[1];
        f.polygon = {a, Vec2(b.x(), a.y()), b, Vec2(a.x(), b.y())};
      }
    } else if (auto c = r.points(e, ip, "polygon", 3)) {
      f.polygon = *c;
    }
    if (auto level = r.number(e, ip, "level")) f.level = *level;
    w.fill.push_back(std::move(f));
  });
}

void read_curves(SchemaReader& r, const YAML::Node& s, const KeyPath& p, const std::string& key,
                 std::vector<WaterCurveSpec>& out) {
  for_each_entry(r, s, p, key, [&](const YAML::Node& e, const KeyPath& ip) {
    WaterCurveSpec c;
    c.name = r.string(e, ip, "name").value_or("");
    check_unique_names(r, e, ip, out, c.name);
    c.where = location(r, e, ip.actual);
    if (auto pts = r.points(e, ip, "polyline", 2)) c.polyline = *pts;
    out.push_back(std::move(c));
  });
}

void read_sph(SchemaReader& r, const YAML::Node& res, const KeyPath& top, SphSpec& w) {
  YAML::Node s = r.section(res, top, "sph", YAML::NodeType::Map);
  if (!s.IsDefined()) return;
  const KeyPath p = top.child("sph");
  r.check_keys(s, p);
  w.present = true;
  w.where = location(r, s, p.actual);
  w.spacing = r.number(s, p, "spacing").value_or(0.0);
  w.smoothing = r.number(s, p, "smoothing").value_or(1.5);
  w.sound_speed = r.number(s, p, "sound_speed").value_or(0.0);
  w.expected_speed = r.number(s, p, "expected_speed").value_or(0.0);
  w.viscosity = r.number(s, p, "viscosity").value_or(0.02);
  w.wall_free_slip = r.string(s, p, "wall_viscosity").value_or("no_slip") == "free_slip";
  w.excluded_limit = r.number(s, p, "excluded_limit").value_or(0.01);
  w.density_diffusion = r.number(s, p, "density_diffusion").value_or(0.1);
  w.settle = r.number(s, p, "settle").value_or(0.0);
  w.freeboard = r.number(s, p, "freeboard").value_or(-1.0);
  read_fill(r, s, p, w);
  for_each_entry(r, s, p, "gauges", [&](const YAML::Node& e, const KeyPath& ip) {
    WaterGaugeSpec g;
    g.name = r.string(e, ip, "name").value_or("");
    check_unique_names(r, e, ip, w.gauges, g.name);
    g.x = r.number(e, ip, "x").value_or(0.0);
    g.where = location(r, e, ip.actual);
    w.gauges.push_back(std::move(g));
  });
  read_curves(r, s, p, "runup", w.runup);
  read_curves(r, s, p, "pressure", w.pressure);
  for_each_entry(r, s, p, "crests", [&](const YAML::Node& e, const KeyPath& ip) {
    CrestSpec c;
    c.name = r.string(e, ip, "name").value_or("");
    check_unique_names(r, e, ip, w.crests, c.name);
    if (auto at = r.vector2(e, ip, "at")) c.at = Vec2((*at)[0], (*at)[1]);
    c.direction = r.string(e, ip, "side").value_or("right") == "left" ? -1 : 1;
    c.where = location(r, e, ip.actual);
    w.crests.push_back(std::move(c));
  });
}

}  // namespace

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
  read_sph(r, s, p, res.sph);
  // A region without its own level holds no water above the reservoir's.
  for (WaterFillSpec& f : res.sph.fill)
    if (std::isinf(f.level)) f.level = res.level;
}

}  // namespace dsdem::io::detail
