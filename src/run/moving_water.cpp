#include "run/moving_water.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

#include <fmt/format.h>

#include "run/bounds.hpp"
#include "run/check.hpp"
#include "run/text.hpp"
#include "sph/kernels.hpp"
#include "sph/setup.hpp"
#include "sph/surface.hpp"

namespace dsdem::run {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();


// Even-odd rule.
bool inside_polygon(const std::vector<Vec2>& poly, const Vec2& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 &a = poly[i], &b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double s = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + s * ab)).norm();
}

// The model's triangles and surface faces by cell (set-up only): is a point in the solid,
// or nearer than a distance to its surface?
class SolidLocator {
 public:
  SolidLocator(const Model& m, double cell) : m_(m), cell_(cell) {
    x0_ = y0_ = std::numeric_limits<double>::infinity();
    double x1 = -x0_, y1 = -y0_;
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
      const Vec2 p = m.nodes.x(static_cast<Index>(i));
      x0_ = std::min(x0_, p.x()), y0_ = std::min(y0_, p.y()), x1 = std::max(x1, p.x()), y1 = std::max(y1, p.y());
    }
    nx_ = std::max(1, static_cast<int>(std::ceil((x1 - x0_) / cell_)) + 1);
    ny_ = std::max(1, static_cast<int>(std::ceil((y1 - y0_) / cell_)) + 1);
    tri_.resize(static_cast<std::size_t>(nx_) * ny_);
    face_.resize(tri_.size());
    const auto& T = m.triangles;
    for (std::size_t t = 0; t < T.size(); ++t) {
      const auto& c = T.conn[t];
      add_box(tri_, t, {m.nodes.x(c[0]), m.nodes.x(c[1]), m.nodes.x(c[2])}, 0.0);
    }
    for (const auto& f : surface_faces(m)) {
      faces_.push_back(f);
      add_box(face_, faces_.size() - 1, {m.nodes.x(f[0]), m.nodes.x(f[1])}, cell_);
    }
  }

  bool in_solid(const Vec2& p) const {
    for (std::size_t t : tri_[cell(p)]) {
      const auto& c = m_.triangles.conn[t];
      const Vec2 a = m_.nodes.x(c[0]), b = m_.nodes.x(c[1]), d = m_.nodes.x(c[2]);
      auto cross = [](const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
      if (cross(b - a, p - a) >= 0.0 && cross(d - b, p - b) >= 0.0 && cross(a - d, p - d) >= 0.0) return true;
    }
    return false;
  }
  // Distance to the nearest surface face, capped at the cell size.
  double surface_distance(const Vec2& p) const {
    double d = cell_;
    for (std::size_t f : face_[cell(p)])
      d = std::min(d, distance_to_segment(p, m_.nodes.x(faces_[f][0]), m_.nodes.x(faces_[f][1])));
    return d;
  }

  // Triangle edges on no other triangle: the model's outline and every joint face.
  static std::vector<std::array<Index, 2>> surface_faces(const Model& m) {
    std::unordered_map<std::uint64_t, int> count;
    auto key = [](Index a, Index b) {
      return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint64_t>(std::max(a, b));
    };
    for (const auto& c : m.triangles.conn)
      for (int k = 0; k < 3; ++k) ++count[key(c[k], c[(k + 1) % 3])];
    std::vector<std::array<Index, 2>> faces;
    for (const auto& c : m.triangles.conn)
      for (int k = 0; k < 3; ++k)
        if (count[key(c[k], c[(k + 1) % 3])] == 1) faces.push_back({c[k], c[(k + 1) % 3]});
    return faces;
  }

 private:
  std::size_t cell(const Vec2& p) const {
    const int i = std::clamp(static_cast<int>(std::floor((p.x() - x0_) / cell_)), 0, nx_ - 1);
    const int j = std::clamp(static_cast<int>(std::floor((p.y() - y0_) / cell_)), 0, ny_ - 1);
    return static_cast<std::size_t>(j) * nx_ + i;
  }
  void add_box(std::vector<std::vector<std::size_t>>& cells, std::size_t item, std::initializer_list<Vec2> pts,
               double grow) {
    double a = std::numeric_limits<double>::infinity(), b = a, c = -a, d = -a;
    for (const Vec2& p : pts) a = std::min(a, p.x()), b = std::min(b, p.y()), c = std::max(c, p.x()), d = std::max(d, p.y());
    const std::size_t lo = cell(Vec2(a - grow, b - grow)), hi = cell(Vec2(c + grow, d + grow));
    const std::size_t i0 = lo % nx_, j0 = lo / nx_, i1 = hi % nx_, j1 = hi / nx_;
    for (std::size_t j = j0; j <= j1; ++j)
      for (std::size_t i = i0; i <= i1; ++i) cells[j * nx_ + i].push_back(item);
  }

  const Model& m_;
  double cell_ = 1.0, x0_ = 0.0, y0_ = 0.0;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<std::size_t>> tri_, face_;
  std::vector<std::array<Index, 2>> faces_;
};

// A region's water surface: its level, or its top where it gives none.
double region_top(const io::WaterFillSpec& r) {
  double top = -std::numeric_limits<double>::infinity();
  for (const Vec2& p : r.polygon) top = std::max(top, p.y());
  return std::min(top, r.level);
}

// The fill regions as polygons with their levels; the default: the reservoir's span below
// its level down to the model's bottom.
std::vector<io::WaterFillSpec> fill_regions(const io::ReservoirSpec& res, const Model& m) {
  if (!res.sph.fill.empty()) {
    auto regions = res.sph.fill;
    for (auto& r : regions) r.level = region_top(r);
    return regions;
  }
  double y_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m.nodes.size(); ++i) y_min = std::min(y_min, m.nodes.x(static_cast<Index>(i)).y());
  io::WaterFillSpec f;
  f.polygon = {Vec2(res.x_min, y_min), Vec2(res.x_max, y_min), Vec2(res.x_max, res.level), Vec2(res.x_min, res.level)};
  f.level = res.level;
  f.where = res.sph.where;
  return {f};
}



sph::FluidParameters fluid_parameters(const io::Scenario& sc, double depth) {
  const io::SphSpec& w = sc.reservoir.sph;
  sph::FluidParameters par;
  par.rho0 = sc.reservoir.density;
  par.dp = w.spacing;
  par.h_over_dp = w.smoothing;
  par.alpha = w.viscosity;
  par.wall_viscosity = w.wall_free_slip ? sph::WallViscosity::FreeSlip : sph::WallViscosity::NoSlip;
  par.delta = w.density_diffusion;
  par.excluded_limit = w.excluded_limit;
  par.gravity = sc.gravity;
  par.c0 = w.sound_speed > 0.0 ? w.sound_speed : sph::sound_speed_for(depth, w.expected_speed, sc.gravity.norm());
  return par;
}

// Calls at(p, r, cell) for the lattice points of each region r, `step` apart (or coarser
// across a span wider than max_points steps: span / max_points; 0 never), its top row half a
// step below its level, inside its polygon, outside the solid's triangles and outside the water
// of earlier regions; cell is the area each point stands for. The step goes a millionth past
// the span: a spacing rounded to six digits that divides it keeps its last row.
template <class At>
void for_each_lattice_point(const std::vector<io::WaterFillSpec>& regions, const SolidLocator& solid, double step,
                            double max_points, At&& at) {
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const auto& poly = regions[r].polygon;
    const auto [x0, y0, x1, y1] = bounds_of(poly);
    const double top = std::min(y1, regions[r].level);
    const double sx = max_points > 0.0 ? std::max(step, (x1 - x0) / max_points) : step;
    const double sy = max_points > 0.0 ? std::max(step, (top - y0) / max_points) : step;
    const double columns = std::floor((x1 - x0) / sx + 1e-9), rows = std::floor((top - y0) / sy + 1e-9);
    if (!(columns < 2e9 && rows < 2e9)) continue;  // a span no lattice can walk (or not finite); priced first
    const int nx = static_cast<int>(columns), ny = static_cast<int>(rows);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Vec2 p(x0 + (i + 0.5) * sx, top - (j + 0.5) * sy);
        if (!inside_polygon(poly, p) || solid.in_solid(p)) continue;
        bool earlier = false;
        for (std::size_t q = 0; q < r && !earlier; ++q)
          earlier = inside_polygon(regions[q].polygon, p) && p.y() < regions[q].level;
        if (!earlier) at(p, r, sx * sy);
      }
  }
}

// The particles of the regions dp apart, each at least dp/2 from the solid's surface (less a
// thousandth: a spacing rounded to six digits that divides the depth keeps its bottom row).
void fill_particles(const std::vector<io::WaterFillSpec>& regions, const SolidLocator& solid, MovingWaterLayout& out) {
  const double dp = out.parameters.dp;
  for_each_lattice_point(regions, solid, dp, 0.0, [&](const Vec2& p, std::size_t r, double) {
    if (solid.surface_distance(p) < 0.5 * dp * (1.0 - 1e-3)) return;
    out.fluid.add(p.x(), p.y(), sph::hydrostatic_density(regions[r].level - p.y(), out.parameters));
  });
  out.fluid.mass = out.parameters.mass();
}

// Water laid beyond the model's bounding box has no solid to hold it: it would fall out of
// the model at once. Refused at the keys of the regions that reach past the box.
void refuse_water_outside_the_model(const std::vector<io::WaterFillSpec>& regions, const Model& model,
                                    const sph::FluidParticles& fluid) {
  const Bounds box = bounds_of(model.nodes.X);
  long outside = 0;
  for (std::size_t i = 0; i < fluid.size(); ++i)
    outside += fluid.x[i] < box.x0 || fluid.x[i] > box.x1 || fluid.y[i] < box.y0 || fluid.y[i] > box.y1;
  if (outside == 0) return;
  std::vector<std::string> errors;
  for (const auto& region : regions) {
    const Bounds b = bounds_of(region.polygon);
    if (b.x0 < box.x0 || b.x1 > box.x1 || b.y0 < box.y0 || std::min(b.y1, region.level) > box.y1)
      errors.push_back(region.where.describe(fmt::format(
          "the region reaches beyond the model (x {:.6g} to {:.6g} m, y {:.6g} to {:.6g} m): {} water particles "
          "would lie where no solid holds them",
          box.x0, box.x1, box.y0, box.y1, outside)));
  }
  if (errors.empty())
    errors.push_back(fmt::format("reservoir.sph.fill: {} water particles lie beyond the model", outside));
  throw io::ScenarioError(errors);
}

// Whether the region's extent (width and height below its level) is a finite number.
bool finite_extent(const io::WaterFillSpec& region) {
  const Bounds b = bounds_of(region.polygon);
  return std::isfinite(b.x1 - b.x0) && std::isfinite(std::min(b.y1, region.level) - b.y0);
}

// How many particles the regions take at the spacing dp, counted on a lattice of at most
// kCountingPoints^2 points a region (coarser than dp across a long span, so that a thin region
// still gets rows) and scaled by the area each point stands for (without the dp/2 clearance):
// what laying them out would cost, known before it is paid.
constexpr double kCountingPoints = 450.0;
double estimated_particles(const std::vector<io::WaterFillSpec>& regions, const SolidLocator& solid, double dp) {
  double area = 0.0;
  for_each_lattice_point(regions, solid, dp, kCountingPoints,
                         [&](const Vec2&, std::size_t, double cell) { area += cell; });
  return area / (dp * dp);
}

// The faces the water may meet: every face of a discrete triangle (its fragments' walls when
// joints open), and the other surface faces between `bottom` and `top` over [x0, x1] (the
// banks the water may run up; not the model's base or far sides).
std::vector<sph::SolidEdge> coupled_faces(const Model& m, double x0, double x1, double bottom, double top) {
  std::vector<sph::SolidEdge> edges;
  const auto faces = SolidLocator::surface_faces(m);
  std::unordered_map<std::uint64_t, Index> third;  // the face's triangle's third node
  auto key = [](Index a, Index b) { return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b); };
  std::unordered_map<std::uint64_t, bool> discrete;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& c = m.triangles.conn[t];
    for (int k = 0; k < 3; ++k) {
      third[key(c[k], c[(k + 1) % 3])] = c[(k + 2) % 3];
      discrete[key(c[k], c[(k + 1) % 3])] = m.triangles.zone[t] == Zone::Discrete;
    }
  }
  for (const auto& f : faces) {
    const Vec2 a = m.nodes.x(f[0]), b = m.nodes.x(f[1]), mid = 0.5 * (a + b);
    if (discrete[key(f[0], f[1])]) {
      edges.push_back({f[0], f[1], third[key(f[0], f[1])]});
    } else if (mid.x() >= x0 && mid.x() <= x1 && std::min(a.y(), b.y()) <= top && std::max(a.y(), b.y()) >= bottom) {
      edges.push_back({f[0], f[1], kNoIndex});
    }
  }
  return edges;
}

}  // namespace

MovingWaterLayout lay_out_moving_water(const io::Scenario& sc, const Model& model) {
  const io::SphSpec& w = sc.reservoir.sph;
  const auto regions = fill_regions(sc.reservoir, model);
  MovingWaterLayout out;
  out.parameters = fluid_parameters(sc, 1.0);  // dp, h; c0 set below from the depth
  double mean_size = 0.0;
  for (double a : model.triangles.area0) mean_size += std::sqrt(2.0 * a);
  mean_size /= std::max<std::size_t>(1, model.triangles.size());
  const SolidLocator solid(model, std::max({mean_size, 2.0 * w.spacing, 1e-9}));
  // A spacing the machine cannot hold (a value typed in the wrong unit) is refused before the
  // lattice is walked, not after the memory is gone.
  for (const auto& region : regions)
    if (!finite_extent(region))
      throw io::ScenarioError({region.where.describe("the region's extent overflows: no lattice of water can cover it")});
  const double expected = estimated_particles(regions, solid, w.spacing);
  const double bytes = expected * static_cast<double>(sph::Fluid::bytes_per_particle(out.parameters));
  if (const std::size_t available = available_memory_bytes(); available > 0 && bytes > 0.5 * static_cast<double>(available)) {
    throw io::ScenarioError({spacing_key(w).describe(fmt::format(
        "{} m apart the fill regions take about {:.3g} particles, about {} of memory; the machine has {} available: "
        "a spacing of {:.3g} m or more fits in half of it",
        w.spacing, expected, human_bytes(bytes), human_bytes(static_cast<double>(available)),
        w.spacing * std::sqrt(bytes / (0.5 * static_cast<double>(available)))))});
  }
  // The depth first (c0 depends on it, the densities on c0): lay out, measure, lay out again.
  fill_particles(regions, solid, out);
  if (out.fluid.size() == 0)
    throw io::ScenarioError({w.where.describe(fmt::format(
        "no water fits: the fill regions lie inside the solid, above their level (reservoir.level, {} m, unless a region "
        "gives its own) or are thinner than the spacing {} m",
        sc.reservoir.level, w.spacing))});
  refuse_water_outside_the_model(regions, model, out.fluid);
  double lowest = std::numeric_limits<double>::infinity(), level = -lowest;
  out.x_min = lowest, out.x_max = -lowest;
  for (std::size_t i = 0; i < out.fluid.size(); ++i) {
    lowest = std::min(lowest, out.fluid.y[i] - 0.5 * w.spacing);
    out.x_min = std::min(out.x_min, out.fluid.x[i] - 0.5 * w.spacing);
    out.x_max = std::max(out.x_max, out.fluid.x[i] + 0.5 * w.spacing);
  }
  for (const auto& r : regions) level = std::max(level, r.level);
  out.depth = level - lowest;
  out.parameters = fluid_parameters(sc, out.depth);
  out.fluid = sph::FluidParticles{};
  fill_particles(regions, solid, out);
  const double freeboard = w.freeboard >= 0.0 ? w.freeboard : out.depth;
  const int layers = sph::wall_layers(out.parameters);
  const double reach = layers * w.spacing, width = out.x_max - out.x_min;
  out.coupled_top = level + freeboard;
  out.coupled_x0 = out.x_min - width - reach;
  out.coupled_x1 = out.x_max + width + reach;
  out.coupled_bottom = lowest - reach;
  out.edges = coupled_faces(model, out.coupled_x0, out.coupled_x1, out.coupled_bottom, out.coupled_top);
  // Water with no face to hold it (no discrete zone, no bedrock around it) would fall through the
  // model at once: refused at the section (docs/theory.md §11: the walls ride the solid's faces).
  if (out.edges.empty())
    throw io::ScenarioError({w.where.describe(fmt::format(
        "no solid face holds the water: no face of a discrete zone and no bedrock surface within x {:.6g} to {:.6g} m, "
        "y {:.6g} to {:.6g} m (the water's span widened by its width, up to the freeboard): the water needs walls, the "
        "surface of a continuous or contact zone around it (a tank, a valley) or a discrete zone in it",
        out.coupled_x0, out.coupled_x1, out.coupled_bottom, out.coupled_top))});
  std::vector<Vec2> x(model.nodes.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = model.nodes.x(static_cast<Index>(i));
  sph::lay_edge_particles(out.walls, out.edges, x, layers, out.parameters, level);
  // A discrete triangle's wall particles ride any of its faces (a small one's single particle
  // rides one): a face is bare when its triangle carries none.
  std::vector<int> walls(out.edges.size(), 0);
  for (const Index e : out.walls.edge)
    if (e != kNoIndex) ++walls[static_cast<std::size_t>(e)];
  std::map<std::array<Index, 3>, int> per_triangle;
  auto triangle = [](const sph::SolidEdge& f) {
    std::array<Index, 3> t{f.a, f.b, f.c};
    std::sort(t.begin(), t.end());
    return t;
  };
  for (std::size_t e = 0; e < out.edges.size(); ++e)
    if (out.edges[e].c != kNoIndex) per_triangle[triangle(out.edges[e])] += walls[e];
  for (const sph::SolidEdge& f : out.edges)
    if (f.c != kNoIndex && per_triangle[triangle(f)] == 0) ++out.faces_without_walls;
  return out;
}

double settling_rate(double depth, double g) { return 2.0 * std::sqrt(g / std::max(depth, 1e-12)); }

double settle_moving_water(sph::Fluid& fluid, double duration, double depth) {
  return sph::settle(fluid, duration, settling_rate(depth, fluid.parameters().gravity.norm()));
}

}  // namespace dsdem::run
