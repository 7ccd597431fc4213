#include "run/prepare.hpp"
#include "run/water.hpp"

#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "boundary/boundary_setup.hpp"
#include "mesh/model_builder.hpp"
#include "run/bounds.hpp"
#include "run/time_step.hpp"
#include "seismic/artificial_wave.hpp"
#include "water/hydrostatic.hpp"

namespace dsdem::run {

namespace fs = std::filesystem;

namespace {

// Routes the default logger into a buffer while it lives (restored on any exit).
class BuildLogCapture {
 public:
  BuildLogCapture()
      : previous_(spdlog::default_logger()), sink_(std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(100000)) {
    auto logger = std::make_shared<spdlog::logger>("dsdem-build", sink_);
    logger->set_level(spdlog::level::info);
    spdlog::set_default_logger(logger);
  }
  ~BuildLogCapture() { spdlog::set_default_logger(previous_); }
  BuildLogCapture(const BuildLogCapture&) = delete;
  BuildLogCapture& operator=(const BuildLogCapture&) = delete;
  std::vector<PreparedRun::LogLine> lines() const {
    std::vector<PreparedRun::LogLine> out;
    for (const auto& m : sink_->last_raw())
      out.push_back({static_cast<int>(m.level), std::string(m.payload.begin(), m.payload.end())});
    return out;
  }

 private:
  std::shared_ptr<spdlog::logger> previous_;
  std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> sink_;
};

// The mesh and the model built on it, with what building logged; the .msh's bytes when it
// was meshed into work_dir.
void load_model(PreparedRun& run, const std::string& work_dir) {
  RawMesh raw;
  {
    BuildLogCapture capture;
    raw = mesh::load_mesh(run.scenario, work_dir);
    run.model = mesh::build_model(run.scenario, raw);
    run.build_log = capture.lines();
  }
  run.mesh_file = raw.msh_file;
  if (work_dir.empty() || run.mesh_file.empty()) return;
  std::error_code ec_mesh, ec_work;
  const fs::path mesh = fs::weakly_canonical(run.mesh_file, ec_mesh), work = fs::weakly_canonical(work_dir, ec_work);
  if (!ec_mesh && !ec_work && mesh.parent_path() == work) {  // meshed here from the .geo: keep its bytes
    std::ifstream in(mesh, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (in) run.mesh_text = std::move(bytes).str();
  }
}

// Gauges must sit in (or within half an element of) the model.
void locate_gauges(PreparedRun& run) {
  std::vector<std::string> errors;
  double mean_size = 0.0;
  for (double a : run.model.triangles.area0) mean_size += std::sqrt(2.0 * a);
  mean_size /= std::max<std::size_t>(1, run.model.triangles.size());
  for (const auto& g : run.scenario.output.gauges) {
    auto located = solver::locate_gauge(run.model, g.name, g.at, 0.5 * mean_size);
    if (!located)
      errors.push_back(g.where.describe(
          fmt::format("gauge '{}' at ({}, {}) m lies outside the mesh", g.name, g.at.x(), g.at.y())));
    else
      run.gauges.push_back(*located);
  }
  if (!errors.empty()) throw io::ScenarioError(errors);
}

// Earthquake: records, and stages that can carry it.
void load_earthquake(PreparedRun& run) {
  const io::Scenario& scenario = run.scenario;
  const io::EarthquakeSpec& q = scenario.earthquake;
  try {
    if (q.horizontal.present) run.quake_horizontal = load_motion(q.horizontal, run.dt);
    if (q.vertical.present) run.quake_vertical = load_motion(q.vertical, run.dt);
  } catch (const io::ScenarioError&) {
    throw;
  } catch (const std::exception& e) {
    throw io::ScenarioError({fmt::format("{}: earthquake: {}", scenario.file, e.what())});
  }
  std::vector<std::string> errors;
  for (const auto& st : scenario.stages) {
    if (!st.earthquake) continue;
    if (!run.quake_horizontal && !run.quake_vertical)
      errors.push_back(fmt::format("{}: stage '{}' has earthquake: true but the scenario has no earthquake section",
                                   scenario.file, st.name));
    const bool input = std::any_of(st.boundaries.begin(), st.boundaries.end(), [](const io::BoundarySpec& b) {
      return b.type == io::BoundaryType::ViscousSpring && b.free_field;
    });
    if (!input)
      errors.push_back(fmt::format("{}: stage '{}' has earthquake: true but no viscous_spring boundary with free_field "
                                   "to bring it in",
                                   scenario.file, st.name));
    // The boundary must be buildable (curves on the outline).
    boundary::build_viscous_boundary(run.model, st.boundaries);
  }
  if (!errors.empty()) throw io::ScenarioError(errors);
}

// The run-up curves, force curves and crests wholly outside the region the water can reach
// (the coupled faces' region) measure nothing: said at their keys before the run, not found in
// an empty summary after it.
void warn_of_places_the_water_cannot_reach(const io::SphSpec& sph, const MovingWaterLayout& w,
                                           std::vector<PreparedRun::LogLine>& log) {
  // The polyline's bounding box misses the region's.
  auto outside = [&](const std::vector<Vec2>& line) {
    const Bounds b = bounds_of(line);
    return b.x1 < w.coupled_x0 || b.x0 > w.coupled_x1 || b.y0 > w.coupled_top || b.y1 < w.coupled_bottom;
  };
  const std::string region = fmt::format("x {:.6g} to {:.6g} m, up to y = {:.6g} m (reservoir.sph.freeboard above the "
                                         "level)", w.coupled_x0, w.coupled_x1, w.coupled_top);
  for (const auto* curves : {&sph.runup, &sph.pressure})
    for (const auto& c : *curves)
      if (outside(c.polyline))
        log.push_back({3, c.where.describe(fmt::format("'{}' lies outside the region the water can reach ({}): it will "
                                                       "read nothing", c.name, region))});
  for (const auto& c : sph.crests)
    if (c.at.y() > w.coupled_top || c.at.x() < w.coupled_x0 || c.at.x() > w.coupled_x1)
      log.push_back({3, c.where.describe(fmt::format("crest '{}' at ({:.6g}, {:.6g}) m lies outside the region the water "
                                                     "can reach ({}): no water will pass it",
                                                     c.name, c.at.x(), c.at.y(), region))});
}

// The water-at-rest section's piezometric line over the moving water's span should stand at
// the pool's level: elsewhere the rock's pore pressure under the pool does not match the water
// above it (docs/theory.md §8, §11). Said once per distinct line, at its key.
void warn_of_a_piezometric_line_off_the_pool(const io::Scenario& sc, const MovingWaterLayout& w,
                                             std::vector<PreparedRun::LogLine>& log) {
  std::vector<std::vector<Vec2>> said;
  for (const auto& st : sc.stages) {
    const io::WaterSpec& ws = st.water;
    if (!ws.present || ws.ru > 0.0 || ws.line.empty()) continue;
    if (std::find(said.begin(), said.end(), ws.line) != said.end()) continue;
    said.push_back(ws.line);
    const water::PiezometricLine line(ws.line);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    constexpr int kSamples = 64;
    for (int k = 0; k <= kSamples; ++k) {
      const double z = line.elevation(w.x_min + (w.x_max - w.x_min) * k / kSamples);
      lo = std::min(lo, z), hi = std::max(hi, z);
    }
    const double level = sc.reservoir.level, off = std::max(hi - level, level - lo);
    if (off > 0.5 * w.parameters.dp)
      log.push_back({3, ws.where.describe(fmt::format(
                            "the piezometric line over the moving water (x {:.6g} to {:.6g} m) stands at {} m, the "
                            "pool at reservoir.level {:.6g} m: the rock's pore pressure under the pool does not match "
                            "the water above it",
                            w.x_min, w.x_max,
                            hi - lo > 1e-9 * std::max(1.0, std::fabs(hi)) ? fmt::format("{:.6g} to {:.6g}", lo, hi)
                                                                          : fmt::format("{:.6g}", hi),
                            level))});
  }
}

// The reservoir's shore where a slide may enter it. Without a discrete zone there is no slide:
// the reservoir is water alone (docs/theory.md §12), which only moving water makes something to
// compute, so a still reservoir with nothing to enter it is refused at its key.
void find_reservoir_shore(PreparedRun& run) {
  const io::ReservoirSpec& res = run.scenario.reservoir;
  if (has_slide(run.model)) {
    run.shore = find_shore(run.model, res);
    return;
  }
  if (!res.sph.present)
    throw io::ScenarioError({res.where.describe(
        "the model has no discrete zone, so no slide can enter the reservoir, and without reservoir.sph its water does "
        "not move: there is nothing to compute (give reservoir.sph for moving water alone against the solid's faces, "
        "a region with zone: discrete for a slide, or the water: section for water at rest in the slope)")});
  run.build_log.push_back({2, "reservoir: water alone (the model has no discrete zone): no slide enters it, so no "
                              "impact, slide speed or Heller & Hager estimate (summary.json heller_hager.applicable: "
                              "false)"});
}

// Rows of water over its depth below which the run warns.
constexpr double kFewestRows = 10.0;

// The moving water's particles and coupled faces, and its measuring places against them.
void lay_out_water(PreparedRun& run) {
  const io::ReservoirSpec& res = run.scenario.reservoir;
  MovingWaterLayout w = lay_out_moving_water(run.scenario, run.model);
  std::vector<std::string> errors;
  for (const auto& g : res.sph.gauges)
    if (g.x < w.x_min || g.x > w.x_max)
      errors.push_back(
          g.where.describe(fmt::format("gauge '{}': x = {:.6g} m lies outside the water, {:.6g} to {:.6g} m", g.name, g.x, w.x_min, w.x_max)));
  if (!errors.empty()) throw io::ScenarioError(errors);
  warn_of_places_the_water_cannot_reach(res.sph, w, run.build_log);
  const auto& par = w.parameters;
  run.build_log.push_back({2, fmt::format("reservoir water: {} particles {:.6g} m apart, {:.6g} m deep, sound speed {:.4g} m/s, "
                                          "{} coupled faces up to {:.6g} m carrying {} wall particles",
                                          w.fluid.size(), par.dp, w.depth, par.c0, w.edges.size(), w.coupled_top,
                                          w.walls.size())});
  // The artificial sound speed (docs/theory.md §11: c0 >= 10 sqrt(g H), not water's 1480 m/s) puts
  // the pool's first compression mode c0 / 4H inside an earthquake's band: the shaking's own
  // hydrodynamic pressures are not real water's, though the wave (a gravity wave) is.
  if (run.scenario.earthquake.present && w.depth > 0.0)
    run.build_log.push_back({2, fmt::format("reservoir water: its first compression mode c0 / 4H = {:.3g} Hz (real "
                                            "water: {:.3g} Hz): the pressures of the shaking itself above about {:.2g} "
                                            "Hz are not real water's, though the wave (a gravity wave) is",
                                            par.c0 / (4.0 * w.depth), 1480.0 / (4.0 * w.depth),
                                            par.c0 / (4.0 * w.depth))});
  if (w.faces_without_walls > 0)
    run.build_log.push_back(
        {3, fmt::format("reservoir water: {} faces of the discrete zone carry no wall particles (their triangle has "
                        "none): the water passes through them (summary.json moving_water.faces_without_walls)",
                        w.faces_without_walls)});
  // The lattice hangs from the level (its top row dp/2 below it): where the depth is no
  // whole number of spacings the bottom row is missing and the water settles below the level.
  if (run.shore && run.shore->depth - w.depth > 0.25 * par.dp) {
    run.build_log.push_back(
        {3, spacing_key(res.sph).describe(fmt::format(
                "the particles fill {:.4g} m of the {:.4g} m from the level down to the deepest bed: the water will "
                "settle about {:.3g} m below reservoir.level (the wave's amplitude is measured from the settled "
                "level); a spacing that divides the depth, e.g. {:.6g} m, fills it",
                w.depth, run.shore->depth, run.shore->depth - w.depth,
                run.shore->depth / std::max(1.0, std::round(run.shore->depth / par.dp))))});
  }
  warn_of_a_piezometric_line_off_the_pool(run.scenario, w, run.build_log);
  // Few rows over the depth: the wave, the pressures and the settled level are all resolved
  // on them (the validation cases use 20 or more, docs/validation.md §5).
  if (w.depth < kFewestRows * par.dp) {
    run.build_log.push_back({3, spacing_key(res.sph).describe(fmt::format(
                                    "the water is {:.3g} spacings deep ({:.4g} m at {:.4g} m): fewer than {:.0f} rows "
                                    "resolve neither the wave nor the pressures; a spacing of {:.3g} m or less gives "
                                    "{:.0f}",
                                    w.depth / par.dp, w.depth, par.dp, kFewestRows, w.depth / kFewestRows, kFewestRows))});
  }
  run.moving_water = std::move(w);
}

}  // namespace

namespace {
// The keys of a 3D model in a plane scenario (docs/theory.md §14: the mesh decides).
void refuse_3d_keys(const io::Scenario& sc) {
  std::vector<std::string> errors;
  if (sc.gravity_components == 3)
    errors.push_back(sc.where_gravity.describe("a plane model (the mesh has no volumes) takes gravity as [x, y] in m/s^2"));
  for (const auto& st : sc.stages)
    for (const auto& b : st.boundaries) {
      if (b.z) errors.push_back(b.where.describe(fmt::format("boundary '{}': z belongs to 3D models; a plane model "
                                                             "moves in x and y", b.group)));
      if (b.type == io::BoundaryType::Roller && b.direction == 2)
        errors.push_back(b.where.describe(fmt::format("boundary '{}': a plane model's roller holds x or y", b.group)));
      if (b.scattering_centre_3d)
        errors.push_back(b.where.describe(fmt::format("boundary '{}': a plane model takes scattering_centre as [x, y]",
                                                      b.group)));
    }
  for (const auto& g : sc.output.gauges)
    if (g.components == 3)
      errors.push_back(g.where.describe(fmt::format("gauge '{}': a plane model's gauge is at [x, y]", g.name)));
  const io::MotionSpec& h = sc.earthquake.horizontal;
  if (h.present && h.direction_given && h.azimuth_deg != 0.0)
    errors.push_back(h.where.describe("direction: a plane model's horizontal record moves along x"));
  if (!errors.empty()) throw io::ScenarioError(errors);
}
}  // namespace

PreparedRun prepare_run(const io::Scenario& scenario, const std::string& work_dir) {
  refuse_3d_keys(scenario);
  PreparedRun run;
  run.scenario = scenario;
  load_model(run, work_dir);
  locate_gauges(run);
  check_water(run.scenario, run.model);
  if (run.scenario.reservoir.present) find_reservoir_shore(run);
  if (run.scenario.reservoir.sph.present) lay_out_water(run);
  choose_time_step(run);
  run.estimated_steps = static_cast<long>(std::ceil(scenario.end_time() / run.dt));
  load_earthquake(run);
  return run;
}

seismic::Accelerogram load_motion(const io::MotionSpec& spec, double dt) {
  seismic::Accelerogram rec;
  if (spec.generate) {
    seismic::ArtificialWaveParams p;
    p.spectrum.kind = seismic::parse_design_spectrum_kind(spec.spectrum);
    p.spectrum.pga = spec.pga_g * kStandardGravity;
    p.spectrum.Tg = spec.Tg;
    p.spectrum.beta_max = spec.beta_max;
    p.spectrum.damping = spec.damping;
    p.dt = spec.dt;
    p.duration = spec.duration;
    p.t1 = spec.t1;
    p.t2 = spec.t2;
    p.c = spec.c;
    p.seed = spec.seed;
    rec = seismic::generate_artificial_wave(p).wave;
  } else {
    rec = seismic::read_accelerogram(spec.file, seismic::parse_accel_units(spec.units));
  }
  if (spec.scale != 1.0) seismic::scale(rec, spec.scale);
  return seismic::resample(rec, dt);
}

}  // namespace dsdem::run
