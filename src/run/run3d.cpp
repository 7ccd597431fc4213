// A scenario on a volume mesh: prepared, checked and run (docs/theory.md §14).
#include "run/run3d.hpp"

#include <fmt/format.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>

#include "boundary/boundary_setup3d.hpp"
#include "fem/tet4.hpp"
#include "io/history_writer.hpp"
#include "io/json_file.hpp"
#include "io/pvd.hpp"
#include "io/vtu_writer.hpp"
#include "mesh/model_builder3d.hpp"
#include "run/prepare.hpp"
#include "solver/constraints.hpp"
#include "solver/continuum3d.hpp"
#include "solver/solver.hpp"
#include "dsdem_version.hpp"

namespace dsdem::run {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// The record scaled by f (the horizontal record's part along x or y).
seismic::Accelerogram scaled(const seismic::Accelerogram& r, double f) {
  seismic::Accelerogram s = r;
  for (auto* v : {&s.a, &s.v, &s.d})
    for (double& x : *v) x *= f;
  return s;
}

// Every key a 3D model does not take (yet), and every 2D form of a key it does.
std::vector<std::string> dimension_problems(const io::Scenario& sc) {
  std::vector<std::string> errors;
  auto refuse = [&](const io::SourceLocation& where, const std::string& what) {
    errors.push_back(where.file.empty() ? fmt::format("{}: {}", sc.file, what) : where.describe(what));
  };
  const io::SourceLocation top{sc.file, -1, -1, ""};
  if (sc.gravity_components == 2)
    refuse(sc.where_gravity, "a 3D model (the mesh has volumes) needs gravity as [x, y, z] in m/s^2");
  if (sc.plane_stress) refuse(sc.where_mesh, "mesh.plane: a 3D model is neither plane strain nor plane stress");
  if (sc.crossed_mesh) refuse(sc.where_mesh, "mesh.crossed splits quadrilaterals of a plane mesh; a volume mesh has none");
  for (const auto& r : sc.regions)
    if (r.zone != Zone::Bedrock)
      refuse(r.where_group, fmt::format("region '{}': only continuous zones exist in 3D so far (joints and contact "
                                        "between tetrahedra come next)", r.group));
  if (sc.joints.present) refuse(top, "joints: a 3D model has no cohesive joints yet (only continuous zones)");
  if (sc.contact.present) refuse(top, "contact: a 3D model has no contact between tetrahedra yet");
  for (const auto& st : sc.stages)
    if (st.water.present) {
      refuse(top, fmt::format("water (stage '{}'): water at rest is not in 3D yet", st.name));
      break;
    }
  if (sc.reservoir.present) refuse(top, "reservoir: moving water is not in 3D yet");
  if (!sc.stability.monitor.empty())
    refuse(sc.stability.monitor.front().where, "stability.monitor: monitored points at [x, y] are plane; a 3D model's "
                                               "factor of safety watches every node (leave stability.monitor out)");
  if (!sc.output.gauges.empty()) refuse(sc.output.gauges.front().where, "output.gauges: gauges at [x, y] are plane; a 3D model's gauges are not in yet");
  auto check_boundaries = [&](const std::vector<io::BoundarySpec>& list) {
    for (const auto& b : list)
      if (b.scattering_centre && !b.scattering_centre_3d)
        refuse(b.where, fmt::format("boundary '{}': a 3D model needs scattering_centre as [x, y, z] in m", b.group));
  };
  for (const auto& st : sc.stages) check_boundaries(st.boundaries);
  if (sc.earthquake.vertical.present && sc.earthquake.vertical.direction_given)
    refuse(sc.earthquake.vertical.where, "earthquake.vertical: the vertical record moves along z; it takes no direction");
  return errors;
}

// The viscous-spring surfaces of one stage's boundaries.
std::vector<boundary::ViscousSurface> viscous_surfaces(const std::vector<io::BoundarySpec>& list) {
  std::vector<boundary::ViscousSurface> out;
  for (const auto& b : list)
    if (b.type == io::BoundaryType::ViscousSpring)
      out.push_back({b.group, b.R, b.scattering_centre_3d, b.free_field});
  return out;
}

std::string human_time(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  if (s < 120) return fmt::format("{:.0f} s", s);
  if (s < 7200) return fmt::format("{:.0f} min", s / 60);
  return fmt::format("{:.1f} h", s / 3600);
}

}  // namespace

PreparedRun3 prepare_run_3d(const io::Scenario& scenario, const RawMesh3& mesh) {
  PreparedRun3 run;
  run.scenario = scenario;
  const io::Scenario& sc = run.scenario;
  std::vector<std::string> errors = dimension_problems(sc);
  if (!errors.empty()) throw io::ScenarioError(errors);
  run.model = mesh::build_model_3d(sc, mesh);
  run.mesh_file = mesh.msh_file;
  try {  // every material's law runs on tetrahedra, with admissible parameters
    const solver::Solver3 probe(run.model);
  } catch (const std::invalid_argument& e) {
    throw io::ScenarioError({fmt::format("{}: materials: {}", sc.file, e.what())});
  }
  if (sc.gravity_components == 3) run.gravity = sc.gravity_3d;
  // The step: safety x the smallest altitude over cp (docs/theory.md §2), or time.dt.
  const auto& n = run.model.nodes;
  const auto& tet = run.model.tetrahedra;
  double beta = 0.0;  // the stiffness damping of any stage shortens the stable step (docs/theory.md §6)
  for (const auto& st : sc.stages) beta = std::max(beta, st.damping.beta);
  run.stable_dt = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < tet.size(); ++t) {
    const auto& c = tet.conn[t];
    const double cp = run.model.materials[static_cast<std::size_t>(tet.material[t])].cp();
    const double dt = fem::tet_critical_time_step(n.X[c[0]], n.X[c[1]], n.X[c[2]], n.X[c[3]], cp, beta);
    if (dt < run.stable_dt) {
      run.stable_dt = dt;
      run.controlling_tetrahedron = static_cast<Index>(t);
    }
  }
  if (sc.safety > solver::kMaxSafety3D)
    throw io::ScenarioError({fmt::format("{}: time.safety {} is above {} : in 3D the altitude step can exceed a "
                                         "tetrahedron's own stability limit by up to 1.87 times (docs/theory.md §2)",
                                         sc.file, sc.safety, solver::kMaxSafety3D)});
  run.dt = sc.dt ? *sc.dt : sc.safety * run.stable_dt;
  if (sc.dt && *sc.dt > solver::kMaxSafety3D * run.stable_dt)
    throw io::ScenarioError({fmt::format("{}: time.dt {} s is above {} of the stable step {:.4g} s", sc.file, *sc.dt,
                                         solver::kMaxSafety3D, run.stable_dt)});
  run.estimated_steps = static_cast<long>(std::ceil(sc.end_time() / run.dt));
  // The earthquake: the horizontal record along its azimuth, the vertical along z.
  const auto& q = sc.earthquake;
  try {
    if (q.horizontal.present) {
      const seismic::Accelerogram h = load_motion(q.horizontal, run.dt);
      const double az = q.horizontal.azimuth_deg * kPi / 180.0;
      const double cx = std::abs(q.horizontal.azimuth_deg - 90.0) < 1e-12 ? 0.0 : std::cos(az);
      const double cy = std::abs(q.horizontal.azimuth_deg) < 1e-12 ? 0.0 : std::sin(az);
      if (cx != 0.0) run.quake_x = cx == 1.0 ? h : scaled(h, cx);
      if (cy != 0.0) run.quake_y = cy == 1.0 ? h : scaled(h, cy);
    }
    if (q.vertical.present) run.quake_z = load_motion(q.vertical, run.dt);
  } catch (const io::ScenarioError&) {
    throw;
  } catch (const std::exception& e) {
    throw io::ScenarioError({fmt::format("{}: earthquake: {}", sc.file, e.what())});
  }
  // Every stage's boundaries must build: groups of the mesh, surfaces on the outside.
  for (const auto& st : sc.stages) {
    for (const auto& b : st.boundaries)
      if (run.model.find_group(b.group) == kNoIndex)
        errors.push_back(b.where.describe(fmt::format("the mesh {} has no group '{}'", mesh.source, b.group)));
    if (!errors.empty()) continue;
    try {
      boundary::build_viscous_boundary_3d(run.model, viscous_surfaces(st.boundaries));
    } catch (const std::invalid_argument& e) {
      errors.push_back(fmt::format("{}: stage '{}': {}", sc.file, st.name, e.what()));
    }
    if (st.earthquake && !run.quake_x && !run.quake_y && !run.quake_z)
      errors.push_back(fmt::format("{}: stage '{}' has earthquake: true but the scenario has no earthquake section",
                                   sc.file, st.name));
  }
  if (!errors.empty()) throw io::ScenarioError(errors);
  return run;
}

std::string check_report_3d(const PreparedRun3& p) {
  const io::Scenario& sc = p.scenario;
  const auto& tet = p.model.tetrahedra;
  std::string out = fmt::format("scenario {}\n3D model (the mesh {} has volumes): {} nodes, {} tetrahedra\n", sc.file,
                                sc.mesh_file, p.model.nodes.size(), tet.size());
  for (const auto& m : p.model.materials)
    out += fmt::format("  material {}: {} (E {:.4g} Pa, nu {}, rho {} kg/m^3, cp {:.4g} m/s)\n", m.name, m.model, m.E,
                       m.nu, m.rho, m.cp());
  if (p.controlling_tetrahedron != kNoIndex) {
    const auto& c = tet.conn[static_cast<std::size_t>(p.controlling_tetrahedron)];
    Vec3 at = Vec3::Zero();
    for (const Index v : c) at += 0.25 * p.model.nodes.X[v];
    out += fmt::format("time step {:.4g} s = {} x {:.4g} s, the smallest altitude over cp, at tetrahedron {} near "
                       "({:.4g}, {:.4g}, {:.4g}) m\n",
                       p.dt, sc.dt ? p.dt / p.stable_dt : sc.safety, p.stable_dt, p.controlling_tetrahedron, at.x(),
                       at.y(), at.z());
  }
  out += fmt::format("{} stages, {:.4g} s simulated, about {} steps\n", sc.stages.size(), sc.end_time(),
                     p.estimated_steps);
  for (const auto& st : sc.stages)
    out += fmt::format("  stage {}: {} s, alpha {} 1/s, beta {} s{}\n", st.name, st.duration, st.damping.alpha,
                       st.damping.beta, st.earthquake ? ", earthquake" : "");
  return out;
}

void apply_stage_3d(solver::Solver3& s, const io::StageSpec& stage, const PreparedRun3& p, const Vec3& gravity,
                    double start_time) {
  const Model3& model = s.model();
  solver::StepSettings3 st;
  st.gravity = gravity;
  st.alpha = stage.damping.alpha;
  st.beta = stage.damping.beta;
  st.local_damping = stage.damping.local;
  st.dt = p.dt;
  s.set_settings(st);
  const std::vector<solver::PrescribedDof> previous = s.constraints();  // the stage before's supports
  s.set_constraints(solver::build_constraints(model, stage.boundaries, start_time));
  s.set_viscous_boundary(boundary::build_viscous_boundary_3d(model, viscous_surfaces(stage.boundaries)), previous);
  const double f = p.scenario.earthquake.incident_factor;
  if (stage.earthquake)
    s.set_earthquake(p.quake_x ? &*p.quake_x : nullptr, p.quake_y ? &*p.quake_y : nullptr,
                     p.quake_z ? &*p.quake_z : nullptr, f, start_time);
  else
    s.set_earthquake(nullptr, nullptr, nullptr, 0.0, 0.0);
}

RunResult run_3d(PreparedRun3& prepared, const RunOptions& options) {
  const io::Scenario& sc = prepared.scenario;
  Model3& model = prepared.model;
  const fs::path out = options.output_dir;
  fs::create_directories(out);
  auto file_sink = std::make_shared<spdlog::sinks::basic_file_sink_mt>((out / "dsdem.log").string(), true);
  std::vector<spdlog::sink_ptr> sinks{file_sink};
  if (!options.quiet) sinks.push_back(std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  auto log = std::make_shared<spdlog::logger>("dsdem3d", sinks.begin(), sinks.end());
  log->set_pattern("[%H:%M:%S] %v");
  log->flush_on(spdlog::level::info);
  log->info("dsdem {} ({}), 3D continuum", DSDEM_VERSION, DSDEM_GIT_COMMIT);
  log->info("scenario {}: {} nodes, {} tetrahedra", sc.file, model.nodes.size(), model.tetrahedra.size());
  log->info("time step {:.4g} s ({} of the stable step {:.4g} s)", prepared.dt, prepared.dt / prepared.stable_dt,
            prepared.stable_dt);

  solver::Solver3 solver(model);
  const auto wall_start = Clock::now();
  io::PvdSeries pvd(out / "fields.pvd");
  std::size_t frame = 0;
  double last_history = -1.0, last_field = -1.0;  // s: the end writes only what the steps did not
  auto write_fields = [&] {
    if (!options.write_fields || solver.time() == last_field) return;
    last_field = solver.time();
    solver.update_stress();
    const fs::path f = pvd.frame_path(frame++);
    io::write_tetrahedra_vtu(f, model.nodes, model.tetrahedra, model.materials, {}, {}, {.time_s = solver.time()});
    pvd.add(solver.time(), f);
  };
  io::HistoryWriter history(out / "history.csv",
                            {{"time", "s"}, {"stage", ""}, {"kinetic_energy", "J"}, {"strain_energy", "J"},
                             {"gravity_potential", "J"}, {"external_work", "J"}, {"damping_dissipated", "J"},
                             {"plastic_dissipated", "J"}, {"energy_balance_error", ""}, {"max_displacement", "m"},
                             {"max_speed", "m_per_s"}});
  double max_balance = 0.0, max_displacement = 0.0;
  Index max_displacement_node = kNoIndex;
  auto write_history = [&](std::size_t si) {
    if (solver.time() == last_history) return;
    last_history = solver.time();
    const auto& e = solver.energy();
    double umax = 0.0, vmax = 0.0;
    for (std::size_t i = 0; i < model.nodes.size(); ++i) {
      const double u = model.nodes.u[i].norm();
      if (u > umax) umax = u;
      vmax = std::max(vmax, model.nodes.v[i].norm());
      if (u > max_displacement) {
        max_displacement = u;
        max_displacement_node = static_cast<Index>(i);
      }
    }
    max_balance = std::max(max_balance, e.balance_error());
    history.append({solver.time(), static_cast<double>(si), e.kinetic, e.strain, e.gravity_potential, e.external_work,
                    e.damping_dissipated, e.plastic_dissipated, e.balance_error(), umax, vmax});
  };

  nlohmann::ordered_json stages = nlohmann::ordered_json::array();
  double stage_end = 0.0, next_field = 0.0, next_history = 0.0;
  auto last_progress = Clock::now();
  long steps_at_progress = 0;
  std::string stopped_why;
  try {
    for (std::size_t si = 0; si < sc.stages.size(); ++si) {
      const io::StageSpec& stage = sc.stages[si];
      apply_stage_3d(solver, stage, prepared, prepared.gravity, solver.time());
      if (si == 0) {
        solver.initialise();
        write_fields();
        write_history(0);
        next_field = sc.output.field_interval;
        next_history = sc.output.history_interval;
      }
      stage_end += stage.duration;
      log->info("stage {} '{}': {} s to t = {} s, alpha = {} 1/s, beta = {} s{}", si + 1, stage.name, stage.duration,
                stage_end, stage.damping.alpha, stage.damping.beta, stage.earthquake ? ", earthquake" : "");
      double peak_kinetic = 0.0;
      const double stage_start = solver.time();
      const long steps_before = solver.step_count();
      bool at_rest = false;
      while (solver.time() < stage_end - 0.5 * prepared.dt) {
        if (options.stop_signal && *options.stop_signal) break;
        solver.step();
        const double t = solver.time();
        if (t >= next_history - 0.5 * prepared.dt) {
          write_history(si);
          next_history += sc.output.history_interval;
        }
        if (t >= next_field - 0.5 * prepared.dt) {
          write_fields();
          next_field += sc.output.field_interval;
        }
        const double ek = solver.kinetic_energy();
        peak_kinetic = std::max(peak_kinetic, ek);
        if (stage.stop_kinetic_ratio > 0.0 && t - stage_start > 0.05 * stage.duration &&
            ek < stage.stop_kinetic_ratio * peak_kinetic) {
          log->info("stage '{}' at rest at t = {:.4g} s (kinetic energy below {} of its peak)", stage.name, t,
                    stage.stop_kinetic_ratio);
          at_rest = true;
          break;
        }
        const auto now = Clock::now();
        const double since = std::chrono::duration<double>(now - last_progress).count();
        if (since >= sc.output.progress_interval) {
          const double rate = static_cast<double>(solver.step_count() - steps_at_progress) / since;
          log->info("[{}] t = {:.4g} / {:.4g} s  {:.0f} steps/s  ETA {}  energy balance {:.2e}", stage.name, t,
                    sc.end_time(), rate, human_time((sc.end_time() - t) / prepared.dt / rate),
                    solver.energy().balance_error());
          last_progress = now;
          steps_at_progress = solver.step_count();
        }
      }
      stages.push_back({{"name", stage.name},
                        {"end_time_s", solver.time()},
                        {"steps", solver.step_count() - steps_before},
                        {"at_rest", at_rest}});
      if (options.stop_signal && *options.stop_signal) break;
    }
  } catch (const solver::InstabilityError& e) {
    stopped_why = e.what();
    log->error("run stopped: {}", e.what());
  }
  write_history(sc.stages.empty() ? 0 : sc.stages.size() - 1);
  write_fields();
  history.close();
  const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();
  // The plane run's keys where they mean the same (run/summary.cpp), energies in J.
  nlohmann::ordered_json summary;
  summary["title"] = sc.title;
  summary["scenario"] = sc.file;
  summary["overrides"] = sc.overrides;
  summary["dsdem_version"] = DSDEM_VERSION;
  summary["dimension"] = 3;
  summary["elements"] = model.tetrahedra.size();
  summary["nodes"] = model.nodes.size();
  summary["steps"] = solver.step_count();
  summary["dt_s"] = prepared.dt;
  summary["dt_controlled_by"] = fmt::format("tetrahedron {} (its smallest altitude over cp; stable step {:.6g} s)",
                                            prepared.controlling_tetrahedron, prepared.stable_dt);
  summary["end_time_s"] = solver.time();
  summary["threads"] = options.threads;
  summary["wall_time_s"] = wall;
  summary["element_steps_per_s"] =
      wall > 0.0 ? static_cast<double>(model.tetrahedra.size()) * static_cast<double>(solver.step_count()) / wall : 0.0;
  summary["energy_balance_error"] = max_balance;
  summary["completed"] = stopped_why.empty() && !(options.stop_signal && *options.stop_signal);
  if (!stopped_why.empty()) summary["stopped"] = stopped_why;
  summary["stages"] = stages;
  const auto& e = solver.energy();
  summary["final_energies"] = {{"unit", "J"},
                               {"kinetic", e.kinetic},
                               {"strain", e.strain},
                               {"gravity_potential", e.gravity_potential},
                               {"external_work", e.external_work},
                               {"damping_dissipated", e.damping_dissipated},
                               {"plastic_dissipated", e.plastic_dissipated}};
  nlohmann::ordered_json umax = {{"value_m", max_displacement}};
  if (max_displacement_node != kNoIndex) {
    const Vec3 X = model.nodes.X[static_cast<std::size_t>(max_displacement_node)];
    umax["at_m"] = {X.x(), X.y(), X.z()};
  }
  summary["max_displacement"] = umax;
  io::write_json_file(out / "summary.json", summary);
  log->info("{} steps in {:.1f} s; largest energy balance error {:.2e}", solver.step_count(), wall, max_balance);
  if (!stopped_why.empty()) throw std::runtime_error(fmt::format("the run went unstable: {}", stopped_why));
  RunResult result;
  result.steps = solver.step_count();
  result.wall_time_s = wall;
  result.energy_balance_error = max_balance;
  result.summary_path = (out / "summary.json").string();
  result.stopped_by_signal = options.stop_signal ? static_cast<int>(*options.stop_signal) : 0;
  return result;
}

}  // namespace dsdem::run
