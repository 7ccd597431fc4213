// A scenario on a volume mesh: prepared, checked and run (docs/theory.md §14).
#include "run/run3d.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>

#include "boundary/boundary_setup3d.hpp"
#include "fem/tet4.hpp"
#include "mesh/model_builder3d.hpp"
#include "run/outputs3d.hpp"
#include "run/check.hpp"
#include "run/text.hpp"
#include "run/summary.hpp"
#include "run/prepare.hpp"
#include "solver/constraints.hpp"
#include "solver/continuum3d.hpp"
#include "solver/solver.hpp"
#include "dsdem_version.hpp"

namespace dsdem::run {

namespace fs = std::filesystem;

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
  for (const auto& g : sc.output.gauges)
    if (g.components == 2) refuse(g.where, fmt::format("gauge '{}': a 3D model's gauge is at [x, y, z]", g.name));
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


}  // namespace

PreparedRun3 prepare_run_3d(const io::Scenario& scenario, const RawMesh3& mesh) {
  PreparedRun3 run;
  run.scenario = scenario;
  const io::Scenario& sc = run.scenario;
  std::vector<std::string> errors = dimension_problems(sc);
  if (!errors.empty()) throw io::ScenarioError(errors);
  run.model = mesh::build_model_3d(sc, mesh);
  run.mesh_file = mesh.msh_file;
  {  // Gauges within half the mean element size of the mesh (as in a plane model).
    double mean_size = 0.0;
    for (double v : run.model.tetrahedra.volume0) mean_size += std::cbrt(6.0 * v);
    mean_size /= static_cast<double>(std::max<std::size_t>(1, run.model.tetrahedra.size()));
    for (const auto& g : sc.output.gauges) {
      if (auto located = solver::locate_gauge(run.model, g.name, g.at_3d, 0.5 * mean_size))
        run.gauges.push_back(*located);
      else
        errors.push_back(g.where.describe(fmt::format("gauge '{}' at ({}, {}, {}) m lies outside the mesh", g.name,
                                                      g.at_3d.x(), g.at_3d.y(), g.at_3d.z())));
    }
  }
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
  for (const auto& g : p.gauges)
    out += fmt::format("gauge      {:<12} at ({}, {}, {}) m in tetrahedron {}\n", g.name, g.at.x(), g.at.y(), g.at.z(),
                       g.tetrahedron);
  // The cost: a few steps timed on a copy of the model in the first stage (after the first
  // ones, which pay for first-touch and the timed thread choice), the memory its solver holds.
  Model3 copy = p.model;
  solver::Solver3 s(copy);
  apply_stage_3d(s, sc.stages.front(), p, p.gravity, 0.0);
  s.initialise();
  const long total = std::max<long>(1, p.estimated_steps);
  const long warmup = std::min<long>(20, total);
  for (long i = 0; i < warmup; ++i) s.step();
  long timed = 0;
  double elapsed = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  while (timed < total - warmup && timed < 1000 && (timed < 20 || elapsed < 0.5)) {
    s.step();
    ++timed;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  const double per_step = timed > 0 ? elapsed / static_cast<double>(timed) : 0.0;
  const double wall = per_step * static_cast<double>(p.estimated_steps);
  out += fmt::format("estimate   {:.3g} ms per step ({} threads, {} steps timed, {:.3g} M tetrahedron-steps/s) -> about "
                     "{} of wall time\n",
                     per_step * 1e3, omp_get_max_threads(), timed,
                     per_step > 0.0 ? static_cast<double>(tet.size()) / per_step / 1e6 : 0.0, human_time(wall));
  // The solver's arrays as measured, the model's copy they act on, and the program (~60 MB).
  const std::size_t mem = s.memory_bytes() + (60u << 20), avail = available_memory_bytes();
  out += fmt::format("memory     about {} needed, {} available; output about {}\n", human_bytes(static_cast<double>(mem)),
                     avail ? human_bytes(static_cast<double>(avail)) : std::string("unknown"),
                     human_bytes(static_cast<double>(estimate_output_bytes(p))));
  for (const auto& w : resource_warnings(mem, avail, wall)) out += fmt::format("warning: {}\n", w);
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

std::string time_step_log_line(const PreparedRun3& p) {
  return fmt::format("dt = {:.4g} s ({:.3g} x stable {:.4g} s, the smallest altitude over cp at tetrahedron {})", p.dt,
                     p.dt / p.stable_dt, p.stable_dt, p.controlling_tetrahedron);
}

std::size_t estimate_output_bytes(const PreparedRun3& p, bool write_fields) {
  const io::Scenario& sc = p.scenario;
  const double end = sc.end_time();
  const double frames = write_fields && sc.output.field_interval > 0 ? std::floor(end / sc.output.field_interval) + 2 : 0;
  // A VTU frame: ~ 90 B per node (position, displacement, velocity), ~ 200 B per tetrahedron
  // (connectivity, stress, strain, material; binary, base64); a history row ~ 250 B.
  const double frame = 90.0 * static_cast<double>(p.model.nodes.size()) + 200.0 * static_cast<double>(p.model.tetrahedra.size());
  const double rows = sc.output.history_interval > 0 ? std::floor(end / sc.output.history_interval) + 2 : 0;
  return static_cast<std::size_t>(frames * frame + rows * 250.0 + (1u << 20));
}

nlohmann::ordered_json make_summary_3d(const PreparedRun3& prepared, const solver::Solver3& solver,
                                       const RunOutputs3& outputs, const std::vector<GaugeStats>& gauges,
                                       const RunFacts& facts) {
  const io::Scenario& sc = prepared.scenario;
  const Model3& model = prepared.model;
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
  summary["threads"] = facts.threads;
  summary["wall_time_s"] = facts.wall_time_s;
  summary["wall_time_total_s"] = facts.wall_time_before_s + facts.wall_time_s;
  const long steps_run = solver.step_count() - facts.first_step;
  summary["element_steps_per_s"] =
      facts.loop_time_s > 0.0
          ? static_cast<double>(model.tetrahedra.size()) * static_cast<double>(steps_run) / facts.loop_time_s
          : 0.0;
  if (!facts.restarted_from.empty()) {
    summary["restarted_from"] = facts.restarted_from;
    summary["restart_step"] = facts.first_step;
  }
  summary["checkpoint"] = facts.checkpoint;
  summary["energy_balance_error"] = facts.max_balance_error;
  summary["completed"] = facts.completed;
  if (facts.stopped_by) summary["stopped_by_signal"] = facts.stopped_by;
  if (facts.stopped_at_step) summary["stopped_at_step"] = solver.step_count();
  const auto& e = solver.energy();
  summary["final_energies"] = {{"unit", "J"},
                               {"kinetic", e.kinetic},
                               {"strain", e.strain},
                               {"gravity_potential", e.gravity_potential},
                               {"external_work", e.external_work},
                               {"damping_dissipated", e.damping_dissipated},
                               {"plastic_dissipated", e.plastic_dissipated}};
  nlohmann::ordered_json umax = {{"value_m", outputs.max_displacement()}};
  if (const Index node = outputs.max_displacement_node(); node != kNoIndex) {
    const Vec3 X = model.nodes.X[static_cast<std::size_t>(node)];
    umax["at_m"] = {X.x(), X.y(), X.z()};
  }
  summary["max_displacement"] = umax;
  nlohmann::ordered_json gj = nlohmann::ordered_json::array();
  for (std::size_t gi = 0; gi < prepared.gauges.size(); ++gi) {
    const solver::Gauge3& g = prepared.gauges[gi];
    const Vec3 u = solver::gauge_value(model, g, model.nodes.u);
    gj.push_back({{"name", g.name},
                  {"at_m", {g.at.x(), g.at.y(), g.at.z()}},
                  {"max_displacement_m", gauges[gi].max_disp},
                  {"peak_velocity_mps", gauges[gi].max_speed},
                  {"time_of_peak_velocity_s", gauges[gi].time_of_max_speed},
                  {"final_displacement_m", {u.x(), u.y(), u.z()}}});
  }
  summary["gauges"] = gj;
  return summary;
}

nlohmann::ordered_json make_diagnosis_3d(const solver::InstabilityError& e, const solver::Solver3& solver,
                                         const PreparedRun3& prepared) {
  return {{"kind", e.kind},
          {"message", std::string(e.what())},
          {"entity", e.kind == "inverted_element" ? "element" : "model"},
          {"id", e.id},
          {"position_m", {e.position.x(), e.position.y(), e.z}},
          {"step", e.step},
          {"time_s", e.time},
          {"dt_s", solver.dt()},
          {"stable_dt_s", prepared.stable_dt},
          {"stable_dt_controlled_by", fmt::format("tetrahedron {}", prepared.controlling_tetrahedron)}};
}

}  // namespace dsdem::run
