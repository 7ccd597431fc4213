#include "run/summary.hpp"
#include "run/water.hpp"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "dsdem_version.hpp"
#include "io/json_file.hpp"
#include "run/text.hpp"
#include "run/time_step.hpp"

namespace dsdem::run {

using Json = nlohmann::ordered_json;

namespace {

Json final_energies(const solver::EnergyLedger& e, const std::string& unit) {
  Json energies = Json::object();
  energies["unit"] = unit;
  energies["kinetic"] = e.kinetic;
  energies["strain"] = e.strain;
  energies["gravity_potential"] = e.gravity_potential;
  energies["external_work"] = e.external_work;
  energies["damping_dissipated"] = e.damping_dissipated;
  energies["joint_elastic"] = e.joint_elastic;
  energies["fracture_dissipated"] = e.fracture_dissipated;
  energies["contact_elastic"] = e.contact_elastic;
  energies["friction_dissipated"] = e.friction_dissipated;
  energies["contact_damping_dissipated"] = e.contact_damping_dissipated;
  energies["plastic_dissipated"] = e.plastic_dissipated;
  energies["water_work"] = e.water_work;
  energies["moving_water_work"] = e.moving_water_work;  // the SPH water's on the solid; closes the balance with it
  energies["verlet_kinetic_offset"] = e.verlet_kinetic_offset;
  return energies;
}

// Each stage's water at rest (docs/theory.md §8) as run, overrides included: what renders and
// reports draw.
Json water_stages(const io::Scenario& sc) {
  Json stages = Json::array();
  double start = 0.0;
  for (const auto& st : sc.stages) {
    Json w = Json::object();
    w["stage"] = st.name;
    w["start_s"] = start;
    w["end_s"] = start += st.duration;
    if (st.water.present) {
      Json line = Json::array();
      for (const Vec2& p : st.water.line) line.push_back(Json::array({p.x(), p.y()}));
      w["piezometric_line_m"] = std::move(line);  // one point: a level
      w["density_kg_per_m3"] = st.water.density;
      w["pore_pressure"] = st.water.pore_pressure_in_matrix ? "saturated" : "discontinuities";
      if (st.water.ru > 0.0) w["ru"] = st.water.ru;  // below the ground surface; no line
      Json cracks = Json::array();
      for (const auto& c : st.water.cracks) cracks.push_back(Json::object({{"curve", c.curve}, {"level_m", c.level}}));
      w["cracks"] = std::move(cracks);
    } else {
      w["piezometric_line_m"] = nullptr;
    }
    stages.push_back(std::move(w));
  }
  return stages;
}

// The primary wave at each gauge on the open water's side of the shoreline against Heller &
// Hager's 2D decay laws at its distance x from where the slide met the level (docs/theory.md §12):
// the wave the run raised along the reservoir beside the one the equations give.
Json wave_along_reservoir(const Shore& shore, const water::ImpulseWave& w, const WaterWatch& watch, double t_entry) {
  Json gauges = Json::array();
  const int dir = wave_direction(shore);
  auto number = [](double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); };
  for (const WaterWatch::GaugeWave& g : watch.primary_waves(t_entry)) {
    const double x = (g.x - shore.shoreline.x()) * dir;
    if (!(x > 0.0)) continue;  // on the slide's side of the shoreline
    const double a = water::heller_hager_amplitude_at(w, shore.depth, x), H = water::heller_hager_height_at(w, shore.depth, x);
    gauges.push_back(Json::object({{"name", g.name},
                                   {"x_m", g.x},
                                   {"distance_m", x},
                                   {"relative_distance", x / shore.depth},
                                   {"crest_m", number(g.wave.crest)},
                                   {"crest_time_s", number(g.wave.crest_t)},
                                   {"trough_m", number(-g.wave.trough)},
                                   {"height_m", number(g.wave.height())},
                                   {"slide_at_gauge_s", number(g.overrun_t)},
                                   {"heller_hager_crest_m", a},
                                   {"heller_hager_height_m", H},
                                   {"crest_ratio", number(g.wave.crest / a)},
                                   {"height_ratio", number(g.wave.height() / H)}}));
  }
  return gauges;
}

// The slide where it entered the reservoir and the Heller & Hager (2010) wave it raises
// (docs/theory.md §12), or that it has not entered it; with the moving water, the run's wave at
// its gauges beside the equations' decay.
Json heller_hager_summary(const Shore& shore, const std::optional<SlideAtImpact>& impact, const WaterWatch* watch) {
  Json h = Json::object();
  h["still_level_m"] = shore.level;
  h["depth_m"] = shore.depth;
  h["shoreline_m"] = Json::array({shore.shoreline.x(), shore.shoreline.y()});
  h["bank_slope_deg"] = shore.slope_deg;
  h["slide_entered_water"] = impact.has_value();
  if (!impact || !(impact->slide.mass > 0.0)) return h;
  const water::SlideImpact& sl = impact->slide;
  h["impact_time_s"] = impact->time;
  h["impact_point_m"] = Json::array({impact->entry.x(), impact->entry.y()});
  h["slide_speed_mps"] = sl.speed;
  h["slide_thickness_m"] = sl.thickness;
  h["slide_mass_kg_per_m"] = sl.mass;
  const water::ImpulseWave w = water::heller_hager(sl);
  h["froude"] = w.froude;
  h["relative_thickness"] = w.relative_thickness;
  h["relative_mass"] = w.relative_mass;
  h["impulse_product"] = w.impulse_product;
  h["amplitude_m"] = w.amplitude_m;
  h["height_m"] = w.height_m;
  h["distance_of_max_height_m"] = w.distance_m;
  h["inside_validity"] = w.inside_validity();
  Json outside = Json::array();
  for (const water::RangeCheck& c : w.checks)
    if (!c.inside()) outside.push_back(Json::object({{"parameter", c.name}, {"value", c.value}, {"min", c.min}, {"max", c.max}}));
  h["outside_validity"] = outside;
  h["decay_onset_relative_distance"] = water::heller_hager_decay_onset();
  if (watch) h["gauges"] = wave_along_reservoir(shore, w, *watch, impact->time);
  return h;
}

// The moving water's peaks (docs/theory.md §12): the wave's amplitude above the still level (where
// and when), run-up per bank, overtopping per crest, force and pressure per curve, the wave
// period at each gauge, and the energy the water took from the slide.
Json moving_water_summary(const PreparedRun& prepared, const WaterWatch& w, const std::optional<SlideAtImpact>& impact,
                          const solver::Solver& solver, const std::string& energy_unit) {
  auto peak = [](const WaterWatch::Peak& p, const char* value_key, bool with_x) {
    Json j = Json::object();
    j[value_key] = p.seen ? Json(p.value) : Json(nullptr);
    if (with_x) j["x_m"] = p.x;
    j["time_s"] = p.t;
    return j;
  };
  Json m = Json::object();
  const MovingWaterLayout& layout = *prepared.moving_water;
  m["particles"] = static_cast<long>(layout.fluid.size());
  m["spacing_m"] = layout.parameters.dp;
  m["depth_m"] = layout.depth;
  m["sound_speed_mps"] = layout.parameters.c0;
  m["coupled_faces"] = static_cast<long>(layout.edges.size());
  // The water's own steps (the settle's included): the part of the run's cost it takes.
  if (const sph::Fluid* fluid = solver.moving_water()) m["steps"] = fluid->steps();
  m["escaped_particles"] = w.escaped_particles();
  m["coupled_top_m"] = w.coupled_top();
  m["faces_without_walls"] = layout.faces_without_walls;
  m["particles_inside_solid"] = w.particles_inside_solid();
  if (const sph::Fluid* fluid = solver.moving_water()) {
    // The particles taken out of the water (reservoir.sph.excluded_limit): how many, and the
    // first and the last, where and why.
    const auto ex = fluid->excluded();
    Json x = Json::object();
    x["particles"] = static_cast<long>(ex.size());
    x["fraction"] = static_cast<double>(ex.size()) / static_cast<double>(fluid->initial_size());
    x["limit"] = fluid->parameters().excluded_limit;
    x["energy_" + energy_unit] = fluid->excluded_energy();
    // The run's time: the water's clock also ran through the settle before step 0 (negative there).
    const double settle = prepared.scenario.reservoir.sph.settle;
    auto one = [settle](const sph::Fluid::ExcludedParticle& p) {
      return Json{{"id", p.id},          {"time_s", p.time - settle},  {"x_m", p.x}, {"y_m", p.y},
                  {"speed_mps", p.speed}, {"density_kg_per_m3", p.density}};
    };
    x["first"] = ex.empty() ? Json(nullptr) : one(ex.front());
    x["last"] = ex.empty() ? Json(nullptr) : one(ex.back());
    m["excluded"] = x;
  }
  m["above_freeboard_particles"] = w.above_freeboard_particles();
  m["still_level_m"] = w.still_level();
  m["max_speed"] = peak(w.max_speed(), "speed_mps", true);
  m["flow_speed"] = peak(w.flow_speed(), "speed_mps", false);
  m["max_wave_amplitude"] = peak(w.max_amplitude(), "amplitude_m", true);
  // At a wall the highest water is the wave's reflection there (up to twice the incident
  // wave): the height the wall sees, not the travelling wave's amplitude.
  m["max_wave_amplitude"]["at_wall"] = w.max_amplitude().seen && w.against_wall(w.max_amplitude().x);
  Json runup = Json::object();
  for (const auto& r : w.runup()) {
    // The rise above the bank's own reading at rest: what the wave added there.
    Json j = peak(r.peak, "elevation_m", false);
    const double at_rest = r.at_rest();
    const bool rest = r.peak.seen && std::isfinite(at_rest);
    j["at_rest_elevation_m"] = rest ? Json(at_rest) : Json(nullptr);
    j["rise_m"] = rest ? Json(r.peak.value - at_rest) : Json(nullptr);
    j["peak_at_end_of_run"] = w.at_last_row(r.peak);
    runup[r.name] = j;
  }
  m["runup"] = runup;
  Json crests = Json::object();
  for (const auto& c : w.crests()) crests[c.name] = peak(c.peak, "volume_m2_per_m", false);
  m["overtopping"] = crests;
  Json forces = Json::object();
  for (const auto& c : w.forces()) {
    Json j = peak(c.peak, "max_force_N_per_m", false);
    j["peak_pressure_Pa"] = c.pressure;
    // The water at rest against it (the median before the slide met the water): the
    // hydrostatic load the peak stands over.
    const double at_rest = c.at_rest();
    j["at_rest_force_N_per_m"] = std::isfinite(at_rest) ? Json(at_rest) : Json(nullptr);
    forces[c.name] = j;
  }
  m["force_on_curves"] = forces;
  Json periods = Json::object();
  for (const auto& [name, T] : w.gauge_periods()) periods[name] = std::isnan(T) ? Json(nullptr) : Json(T);
  m["wave_period_s"] = periods;
  // When the slide's rock rose to each gauge's surface: its record after that is not the wave.
  // Water alone has no slide: no such times.
  if (prepared.shore) {
    Json overrun = Json::object();
    for (std::size_t g = 0; g < w.gauge_overrun_times().size(); ++g) {
      const double t = w.gauge_overrun_times()[g];
      overrun[prepared.scenario.reservoir.sph.gauges[g].name] = std::isnan(t) ? Json(nullptr) : Json(t);
    }
    m["slide_at_gauges_s"] = overrun;
  }
  m["energy_gain_" + energy_unit] = w.energy_gain().value;
  m["moving_water_work_" + energy_unit] = solver.energy().moving_water_work;
  // The energy the modified boundary's wall pressure put into the water (no wall stores it).
  if (const sph::Fluid* fluid = solver.moving_water()) m["boundary_work_" + energy_unit] = fluid->boundary_work();
  if (impact && impact->slide.mass > 0.0) {
    const double ke = 0.5 * impact->slide.mass * impact->slide.speed * impact->slide.speed;
    m["slide_kinetic_energy_at_impact_" + energy_unit] = ke;
    m["energy_handed_to_water_ratio"] = w.energy_gain().value / ke;
  }
  return m;
}

Json gauge_summaries(const PreparedRun& prepared, const std::vector<GaugeStats>& stats) {
  Json gauges = Json::array();
  for (std::size_t gi = 0; gi < prepared.gauges.size(); ++gi) {
    const Vec2 u = solver::gauge_value(prepared.model, prepared.gauges[gi], prepared.model.nodes.u);
    gauges.push_back(Json::object({{"name", prepared.gauges[gi].name},
                                   {"max_displacement_m", stats[gi].max_disp},
                                   {"peak_velocity_mps", stats[gi].max_speed},
                                   {"time_of_peak_velocity_s", stats[gi].time_of_max_speed},
                                   {"final_displacement_m", Json::array({u.x(), u.y()})}}));
  }
  return gauges;
}

}  // namespace

Json make_summary(const PreparedRun& prepared, const solver::Solver& solver, const std::vector<GaugeStats>& gauges,
                  const RunFacts& f) {
  const io::Scenario& sc = prepared.scenario;
  const Model& model = prepared.model;
  Json s = Json::object();
  s["title"] = sc.title;
  s["scenario"] = sc.file;
  s["overrides"] = sc.overrides;  // --set, in order: the scenario as run is the file with these
  s["dsdem_version"] = std::string(DSDEM_VERSION) + " (" + DSDEM_GIT_COMMIT + ")";
  s["elements"] = static_cast<long>(model.triangles.size());
  s["nodes"] = static_cast<long>(model.nodes.size());
  s["joints"] = static_cast<long>(model.joints.size());
  s["broken_joints"] = solver.broken_joints();
  s["fragments"] = f.fragments;
  s["steps"] = solver.step_count();
  s["dt_s"] = prepared.dt;
  s["dt_controlled_by"] = prepared.stable.controlled_by;
  s["dt_adaptive"] = sc.adaptive_dt;
  s["triangle_order"] = std::string(io::Scenario::triangle_order_name(sc.spatial_triangle_order));  // to rerun it bit for bit
  s["dt_last_s"] = solver.settings().dt;
  s["dt_last_controlled_by"] = step_control(solver, prepared).controlled_by;
  s["end_time_s"] = solver.time();
  s["threads"] = f.threads;
  if (f.threads > 1) s["steps_on_one_thread"] = solver.serial_steps_chosen();
  s["wall_time_s"] = f.wall_time_s;
  if (!f.restarted_from.empty()) {
    s["restarted_from"] = f.restarted_from;
    s["restart_step"] = f.first_step;
    s["wall_time_total_s"] = f.wall_time_before_s + f.wall_time_s;
  }
  s["checkpoint"] = f.checkpoint;
  s["element_steps_per_s"] =
      model.triangles.size() * static_cast<double>(solver.step_count() - f.first_step) / std::max(1e-9, f.loop_time_s);
  s["energy_balance_error"] = f.max_balance_error;
  s["completed"] = f.completed;
  if (f.stopped_by) s["stopped_by"] = signal_name(f.stopped_by);
  if (f.stopped_at_step) s["stopped_at_step"] = solver.step_count();
  s["final_energies"] = final_energies(solver.energy(), f.energy_unit);
  s["gauges"] = gauge_summaries(prepared, gauges);
  if (has_water(sc)) s["water"] = water_stages(sc);
  if (prepared.shore) {
    s["heller_hager"] = heller_hager_summary(*prepared.shore, f.slide_impact, f.water);
  } else if (sc.reservoir.present) {
    // Water alone: nothing enters the water, so there is no impact, slide or estimate to give.
    s["heller_hager"] = Json::object({{"applicable", false},
                                      {"reason", "the model has no discrete zone: no slide enters the water"},
                                      {"still_level_m", sc.reservoir.level}});
  }
  if (f.water) {
    const WaterWatch& w = *f.water;
    s["max_wave_amplitude_m"] = w.max_amplitude().seen ? Json(w.max_amplitude().value) : Json(nullptr);
    Json runup = Json::object();
    for (const auto& r : w.runup()) runup[r.name] = r.peak.seen ? Json(r.peak.value - w.level()) : Json(nullptr);
    s["max_runup_m"] = runup;
    s["moving_water"] = moving_water_summary(prepared, w, f.slide_impact, solver, f.energy_unit);
  }
  return s;
}

Json make_diagnosis(const solver::InstabilityError& e, const solver::Solver& solver, const PreparedRun& prepared) {
  const std::string entity = e.kind == "inverted_element" ? "element"
                             : e.kind == "water_unsound"  ? "water_particle"
                             : e.id == kNoIndex           ? "model"
                                                          : "node";
  const solver::StableStep control = step_control(solver, prepared);
  return Json::object({{"kind", e.kind},
                       {"message", std::string(e.what())},
                       {"entity", entity},
                       {"id", e.id},
                       {"position_m", Json::array({e.position.x(), e.position.y()})},
                       {"step", e.step},
                       {"time_s", e.time},
                       {"dt_s", solver.settings().dt},
                       {"stable_dt_s", control.dt},
                       {"stable_dt_controlled_by", control.controlled_by}});
}

Json read_summary(const std::filesystem::path& out_dir) { return io::read_json_file(out_dir / "summary.json"); }

}  // namespace dsdem::run
