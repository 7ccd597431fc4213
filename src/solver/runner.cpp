#include "solver/runner.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include "dsdem_version.hpp"
#include "io/atomic_file.hpp"
#include "io/history_writer.hpp"
#include "io/json_writer.hpp"
#include "io/pvd.hpp"
#include "io/vtu_writer.hpp"
#include "io/crack_output.hpp"
#include "mesh/model_builder.hpp"
#include "solver/fragments.hpp"

namespace dsdem::solver {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

PreparedRun prepare_run(const io::Scenario& scenario, const std::string& work_dir) {
  PreparedRun run;
  run.scenario = scenario;
  const RawMesh raw = mesh::load_mesh(scenario, work_dir);
  run.model = mesh::build_model(scenario, raw);
  run.mesh_file = raw.msh_file;

  // Gauges must sit in (or within half an element of) the model.
  std::vector<std::string> errors;
  double mean_size = 0.0;
  for (double a : run.model.triangles.area0) mean_size += std::sqrt(2.0 * a);
  mean_size /= std::max<std::size_t>(1, run.model.triangles.size());
  for (const auto& g : scenario.output.gauges) {
    auto located = locate_gauge(run.model, g.name, g.at, 0.5 * mean_size);
    if (!located)
      errors.push_back(g.where.describe(
          fmt::format("gauge '{}' at ({}, {}) m lies outside the mesh", g.name, g.at.x(), g.at.y())));
    else
      run.gauges.push_back(*located);
  }
  if (!errors.empty()) throw io::ScenarioError(errors);

  double max_beta = 0.0;
  for (const auto& s : scenario.stages) max_beta = std::max(max_beta, s.damping.beta);
  run.stable = stable_time_step(run.model, max_beta);
  run.dt = scenario.dt.value_or(scenario.safety * run.stable.dt);
  if (scenario.dt && *scenario.dt > run.stable.dt)
    throw io::ScenarioError({fmt::format("{}: time.dt: {} s exceeds the stable time step {:.4g} s set by {}",
                                         scenario.file, *scenario.dt, run.stable.dt, run.stable.controlled_by)});
  run.estimated_steps = static_cast<long>(std::ceil(scenario.end_time() / run.dt));
  return run;
}

namespace {

std::string zone_name(Zone z) {
  switch (z) {
    case Zone::Discrete: return "discrete (A)";
    case Zone::Bedrock: return "continuous (B)";
    case Zone::ContactBedrock: return "contact (C)";
  }
  return "?";
}

std::string human_time(double s) {
  if (!std::isfinite(s)) return "?";
  if (s < 120) return fmt::format("{:.1f} s", s);
  if (s < 7200) return fmt::format("{:.1f} min", s / 60);
  return fmt::format("{:.1f} h", s / 3600);
}

void apply_stage(Solver& solver, const io::StageSpec& stage, const io::Scenario& sc, double dt) {
  StepSettings s;
  s.gravity = sc.gravity;
  s.alpha = stage.damping.alpha;
  s.beta = stage.damping.beta;
  s.dt = dt;
  s.failure = stage.failure;
  solver.set_settings(s);
  solver.set_constraints(build_constraints(solver.model(), stage.boundaries, solver.time()));
}

}  // namespace

std::string check_report(PreparedRun& run) {
  const Model& m = run.model;
  const io::Scenario& sc = run.scenario;
  std::string r;
  r += fmt::format("scenario   {}{}\n", sc.file, sc.title.empty() ? "" : "  (" + sc.title + ")");
  r += fmt::format("mesh       {}: {} nodes, {} triangles, {}\n", sc.resolve(sc.mesh_file), m.nodes.size(),
                   m.triangles.size(), sc.plane_stress ? fmt::format("plane stress, t = {} m", sc.thickness) : "plane strain");
  for (std::size_t g = 0; g < m.groups.size(); ++g) {
    const Group& grp = m.groups[g];
    if (grp.kind == GroupKind::Surface) {
      if (grp.triangles.empty()) continue;
      const Index t0 = grp.triangles.front();
      r += fmt::format("  surface  {:<16} {:>7} triangles  material {:<12} zone {}\n", grp.name, grp.triangles.size(),
                       m.materials[m.triangles.material[t0]].name, zone_name(m.triangles.zone[t0]));
    } else {
      r += fmt::format("  {:<8} {:<16} {:>7} nodes\n", grp.kind == GroupKind::Curve ? "curve" : "point", grp.name,
                       grp.nodes.size());
    }
  }
  for (const auto& mat : m.materials)
    r += fmt::format("material   {:<12} E = {:.4g} Pa, nu = {}, rho = {} kg/m^3, cp = {:.5g} m/s, cs = {:.5g} m/s\n",
                     mat.name, mat.E, mat.nu, mat.rho, mat.cp(), mat.cs());
  r += fmt::format("stable dt  {:.4g} s, controlled by {}\n", run.stable.dt, run.stable.controlled_by);
  r += fmt::format("time step  {:.4g} s ({}), {} steps for {} s in {} stage{}\n", run.dt,
                   sc.dt ? "fixed" : fmt::format("safety {}", sc.safety), run.estimated_steps, sc.end_time(),
                   sc.stages.size(), sc.stages.size() == 1 ? "" : "s");
  for (const auto& st : sc.stages)
    r += fmt::format("  stage    {:<12} {} s, alpha = {} 1/s, beta = {} s, {} boundary conditions\n", st.name,
                     st.duration, st.damping.alpha, st.damping.beta, st.boundaries.size());
  for (const auto& g : run.gauges)
    r += fmt::format("gauge      {:<12} at ({}, {}) m in triangle {}\n", g.name, g.at.x(), g.at.y(), g.triangle);

  // Time a few steps on a copy to estimate the run time.
  Model copy = m;
  Solver solver(copy);
  apply_stage(solver, sc.stages.front(), sc, run.dt);
  solver.initialise();
  const int probe = static_cast<int>(std::min<long>(50, std::max<long>(1, run.estimated_steps)));
  const auto t0 = Clock::now();
  for (int i = 0; i < probe; ++i) solver.step();
  const double per_step = std::chrono::duration<double>(Clock::now() - t0).count() / probe;
  r += fmt::format("estimate   {:.3g} ms per step ({} threads) -> about {} of wall time\n", per_step * 1e3,
                   omp_get_max_threads(), human_time(per_step * run.estimated_steps));
  return r;
}

RunResult run(PreparedRun& prepared, const RunOptions& options) {
  const auto wall_start = Clock::now();
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const int threads = omp_get_max_threads();
  const fs::path out(options.output_dir);
  io::ensure_writable_directory(out);
  // Keep the mesh the run used next to its results.
  if (!prepared.mesh_file.empty() && fs::exists(prepared.mesh_file)) {
    std::error_code ec;
    fs::copy_file(prepared.mesh_file, out / fs::path(prepared.mesh_file).filename(), fs::copy_options::overwrite_existing, ec);
  }

  // Log: file always, terminal unless quiet.
  auto file_sink = std::make_shared<spdlog::sinks::basic_file_sink_mt>((out / "dsdem.log").string(), true);
  std::vector<spdlog::sink_ptr> sinks{file_sink};
  if (!options.quiet) sinks.push_back(std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  auto log = std::make_shared<spdlog::logger>("dsdem", sinks.begin(), sinks.end());
  log->set_pattern("[%H:%M:%S] %v");
  log->flush_on(spdlog::level::info);

  io::Scenario& sc = prepared.scenario;
  Model& model = prepared.model;
  log->info("dsdem {} ({}), {} threads", DSDEM_VERSION, DSDEM_GIT_COMMIT, threads);
  log->info("scenario {}: {} nodes, {} triangles, {} joints", sc.file, model.nodes.size(), model.triangles.size(),
            model.joints.size());
  log->info("dt = {:.4g} s ({} x stable {:.4g} s, controlled by {})", prepared.dt, sc.dt ? 1.0 : sc.safety,
            prepared.stable.dt, prepared.stable.controlled_by);

  Solver solver(model);
  const bool plane_strain = !model.plane_stress;
  const std::string energy_unit = plane_strain ? "J_per_m" : "J";

  std::vector<io::HistoryColumn> columns{{"time", "s"},
                                         {"step", ""},
                                         {"stage", ""},
                                         {"kinetic", energy_unit},
                                         {"strain", energy_unit},
                                         {"gravity_potential", energy_unit},
                                         {"external_work", energy_unit},
                                         {"damping_dissipated", energy_unit},
                                         {"joint_elastic", energy_unit},
                                         {"fracture_dissipated", energy_unit},
                                         {"energy_balance_error", ""},
                                         {"contact_elastic", energy_unit},
                                         {"friction_dissipated", energy_unit},
                                         {"broken_joints", ""},
                                         {"fragments", ""},
                                         {"contacts", ""}};
  // Reaction on every group that carries a prescribed motion (loading plates, supports).
  std::vector<std::pair<std::string, const std::vector<Index>*>> reaction_groups;
  for (const auto& stage : sc.stages)
    for (const auto& b : stage.boundaries) {
      if (b.type == io::BoundaryType::Free) continue;
      if (std::any_of(reaction_groups.begin(), reaction_groups.end(), [&](const auto& r) { return r.first == b.group; }))
        continue;
      reaction_groups.emplace_back(b.group, &model.groups[model.find_group(b.group)].nodes);
    }
  const std::string force_unit = plane_strain ? "N_per_m" : "N";
  for (const auto& [name, nodes] : reaction_groups)
    for (const char* c : {"x", "y"}) columns.push_back({fmt::format("{}_reaction_{}", name, c), force_unit});
  for (const auto& g : prepared.gauges)
    for (const auto& [q, unit] : std::vector<std::pair<std::string, std::string>>{
             {"displacement", "m"}, {"velocity", "m_per_s"}, {"acceleration", "m_per_s2"}})
      for (const char* c : {"x", "y"}) columns.push_back({fmt::format("{}_{}_{}", g.name, q, c), unit});
  io::HistoryWriter history(out / "history.csv", columns);
  io::PvdSeries fields(out / "fields.pvd");

  std::vector<double> row(columns.size());
  std::vector<Index> fragment_label;
  const bool has_joints = model.joints.size() > 0;
  std::optional<io::PvdSeries> cracks;
  if (has_joints) cracks.emplace(out / "cracks.pvd");
  struct GaugeStats {
    double max_disp = 0.0, max_speed = 0.0, time_of_max_speed = 0.0;
  };
  std::vector<GaugeStats> gauge_stats(prepared.gauges.size());
  auto write_history = [&](int stage_index) {
    const auto& e = solver.energy();
    std::size_t k = 0;
    row[k++] = solver.time();
    row[k++] = static_cast<double>(solver.step_count());
    row[k++] = stage_index;
    row[k++] = e.kinetic;
    row[k++] = e.strain;
    row[k++] = e.gravity_potential;
    row[k++] = e.external_work;
    row[k++] = e.damping_dissipated;
    row[k++] = e.joint_elastic;
    row[k++] = e.fracture_dissipated;
    row[k++] = e.balance_error();
    row[k++] = e.contact_elastic;
    row[k++] = e.friction_dissipated;
    row[k++] = static_cast<double>(solver.broken_joints());
    row[k++] = count_fragments(model, fragment_label);
    row[k++] = static_cast<double>(solver.active_contacts());
    for (const auto& [name, nodes] : reaction_groups) {
      const Vec2 r = solver.reaction_on(*nodes);
      row[k++] = r.x();
      row[k++] = r.y();
    }
    for (std::size_t gi = 0; gi < prepared.gauges.size(); ++gi) {
      const auto& g = prepared.gauges[gi];
      const Vec2 u = gauge_value(model, g, model.nodes.u), v = gauge_value(model, g, model.nodes.v),
                 a = gauge_value(model, g, model.nodes.a);
      for (const Vec2& q : {u, v, a}) {
        row[k++] = q.x();
        row[k++] = q.y();
      }
    }
    history.append(row);
  };
  auto update_gauge_stats = [&] {
    for (std::size_t gi = 0; gi < prepared.gauges.size(); ++gi) {
      const auto& g = prepared.gauges[gi];
      const double d = gauge_value(model, g, model.nodes.u).norm();
      const double s = gauge_value(model, g, model.nodes.v).norm();
      gauge_stats[gi].max_disp = std::max(gauge_stats[gi].max_disp, d);
      if (s > gauge_stats[gi].max_speed) {
        gauge_stats[gi].max_speed = s;
        gauge_stats[gi].time_of_max_speed = solver.time();
      }
    }
  };
  auto write_fields = [&] {
    if (!options.write_fields) return;
    const fs::path file = fields.frame_path(fields.size());
    io::VtuOptions vo;
    vo.time_s = solver.time();
    // The fragment each triangle belongs to (as counted in the history), so that piece
    // sizes can be measured from the frames.
    io::FieldSet cell_extra;
    if (has_joints) {
      count_fragments(model, fragment_label);
      cell_extra.push_back(io::scalar_field("fragment", "", std::span<const std::int32_t>(fragment_label)));
    }
    io::write_triangles_vtu(file, model.nodes, model.triangles, model.materials, {}, cell_extra, vo);
    fields.add(solver.time(), file);
    if (cracks) {
      const fs::path cfile = cracks->frame_path(cracks->size());
      io::write_cracks_vtu(cfile, model, solver.time());
      cracks->add(solver.time(), cfile);
    }
  };

  const bool tty = !options.quiet && isatty(STDERR_FILENO);
  double max_balance_error = 0.0;
  double next_field = 0.0, next_history = 0.0;
  double stage_end = 0.0;
  const double end_time = sc.end_time();
  const auto loop_start = Clock::now();
  auto last_progress = loop_start;
  long steps_at_last_progress = 0;
  try {
    for (std::size_t si = 0; si < sc.stages.size(); ++si) {
      const io::StageSpec& stage = sc.stages[si];
      apply_stage(solver, stage, sc, prepared.dt);
      if (si == 0) {
        solver.initialise();
        write_fields();
        write_history(0);
        next_field = sc.output.field_interval;
        next_history = sc.output.history_interval;
      }
      stage_end += stage.duration;
      log->info("stage {} '{}': {} s to t = {} s, alpha = {} 1/s, beta = {} s, joints {}", si + 1, stage.name,
                stage.duration, stage_end, stage.damping.alpha, stage.damping.beta,
                stage.failure ? "may break" : "elastic (no failure)");
      double peak_kinetic = 0.0;
      // Stop within half a step of the stage end.
      while (solver.time() < stage_end - 0.5 * prepared.dt) {
        solver.step();
        update_gauge_stats();
        const double t = solver.time();
        if (t >= next_history - 0.5 * prepared.dt) {
          write_history(static_cast<int>(si));
          next_history += sc.output.history_interval;
          max_balance_error = std::max(max_balance_error, solver.energy().balance_error());
        }
        if (t >= next_field - 0.5 * prepared.dt) {
          write_fields();
          next_field += sc.output.field_interval;
        }
        peak_kinetic = std::max(peak_kinetic, solver.energy().kinetic);
        if (stage.stop_kinetic_ratio > 0 && solver.energy().kinetic < stage.stop_kinetic_ratio * peak_kinetic &&
            t > 0.05 * stage.duration + (stage_end - stage.duration)) {
          log->info("stage '{}' at rest at t = {:.4g} s (kinetic energy below {} of its peak)", stage.name, t,
                    stage.stop_kinetic_ratio);
          break;
        }
        const auto now = Clock::now();
        if (std::chrono::duration<double>(now - last_progress).count() >= sc.output.progress_interval) {
          const double rate = (solver.step_count() - steps_at_last_progress) /
                              std::chrono::duration<double>(now - last_progress).count();
          const double eta = (end_time - t) / prepared.dt / rate;
          const std::string line =
              fmt::format("[{}] t = {:.4g} / {:.4g} s  {:.0f} steps/s  ETA {}  energy balance {:.2e}", stage.name, t,
                          end_time, rate, human_time(eta), solver.energy().balance_error());
          if (tty)
            fmt::print(stderr, "\r{:<100}", line);
          else if (!options.quiet)
            fmt::print(stderr, "{}\n", line);
          file_sink->log(spdlog::details::log_msg("dsdem", spdlog::level::info, line));
          last_progress = now;
          steps_at_last_progress = solver.step_count();
        }
      }
    }
  } catch (const InstabilityError& e) {
    if (tty) fmt::print(stderr, "\n");
    log->error("run stopped: {}", e.what());
    write_fields();
    write_history(-1);
    history.close();
    if (has_joints) io::write_crack_log_csv(out / "cracks.csv", model);
    io::Json diag = io::Json::object({{"kind", e.kind},
                                      {"message", std::string(e.what())},
                                      {"id", e.id},
                                      {"position_m", io::Json::array({e.position.x(), e.position.y()})},
                                      {"step", e.step},
                                      {"time_s", e.time}});
    io::write_json_file(out / "diagnosis.json", diag);
    throw;
  }
  if (tty) fmt::print(stderr, "\n");
  // Last state, unless just written.
  if (fields.size() == 0 || std::abs(next_field - sc.output.field_interval - solver.time()) > 0.5 * prepared.dt) write_fields();
  write_history(static_cast<int>(sc.stages.size()) - 1);
  history.close();
  max_balance_error = std::max(max_balance_error, solver.energy().balance_error());

  const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();
  io::Json summary = io::Json::object();
  summary["title"] = sc.title;
  summary["scenario"] = sc.file;
  summary["dsdem_version"] = std::string(DSDEM_VERSION) + " (" + DSDEM_GIT_COMMIT + ")";
  summary["elements"] = static_cast<long>(model.triangles.size());
  summary["nodes"] = static_cast<long>(model.nodes.size());
  summary["joints"] = static_cast<long>(model.joints.size());
  summary["broken_joints"] = solver.broken_joints();
  summary["fragments"] = count_fragments(model, fragment_label);
  summary["steps"] = solver.step_count();
  summary["dt_s"] = prepared.dt;
  summary["dt_controlled_by"] = prepared.stable.controlled_by;
  summary["end_time_s"] = solver.time();
  summary["threads"] = threads;
  summary["wall_time_s"] = wall;
  summary["element_steps_per_s"] = model.triangles.size() * static_cast<double>(solver.step_count()) /
                                   std::max(1e-9, std::chrono::duration<double>(Clock::now() - loop_start).count());
  summary["energy_balance_error"] = max_balance_error;
  io::Json energies = io::Json::object();
  const auto& e = solver.energy();
  energies["unit"] = energy_unit;
  energies["kinetic"] = e.kinetic;
  energies["strain"] = e.strain;
  energies["gravity_potential"] = e.gravity_potential;
  energies["external_work"] = e.external_work;
  energies["damping_dissipated"] = e.damping_dissipated;
  energies["joint_elastic"] = e.joint_elastic;
  energies["fracture_dissipated"] = e.fracture_dissipated;
  energies["contact_elastic"] = e.contact_elastic;
  energies["friction_dissipated"] = e.friction_dissipated;
  summary["final_energies"] = energies;
  io::Json gauges = io::Json::array();
  for (std::size_t gi = 0; gi < prepared.gauges.size(); ++gi) {
    const Vec2 u = gauge_value(model, prepared.gauges[gi], model.nodes.u);
    gauges.push_back(io::Json::object({{"name", prepared.gauges[gi].name},
                                       {"max_displacement_m", gauge_stats[gi].max_disp},
                                       {"peak_velocity_mps", gauge_stats[gi].max_speed},
                                       {"time_of_peak_velocity_s", gauge_stats[gi].time_of_max_speed},
                                       {"final_displacement_m", io::Json::array({u.x(), u.y()})}}));
  }
  summary["gauges"] = gauges;
  if (has_joints) io::write_crack_log_csv(out / "cracks.csv", model);
  io::write_json_file(out / "summary.json", summary);
  log->info("done: {} steps in {}, energy balance error {:.2e}; results in {}", solver.step_count(), human_time(wall),
            max_balance_error, out.string());
  spdlog::drop("dsdem");

  RunResult result;
  result.steps = solver.step_count();
  result.wall_time_s = wall;
  result.energy_balance_error = max_balance_error;
  result.summary_path = (out / "summary.json").string();
  return result;
}

}  // namespace dsdem::solver
