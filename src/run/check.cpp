#include "run/check.hpp"

#include <omp.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "law/registry.hpp"
#include "run/stage.hpp"
#include "run/text.hpp"
#include "sph/kernels.hpp"

namespace dsdem::run {

namespace {

using Clock = std::chrono::steady_clock;
// Water sub-steps per solid step beyond which `check` questions the water's sound speed (a
// realistic pool steps once over one or more solid steps).
constexpr double kManyWaterSteps = 10.0;

std::string zone_name(Zone z) {
  switch (z) {
    case Zone::Discrete: return "discrete (A)";
    case Zone::Bedrock: return "continuous (B)";
    case Zone::ContactBedrock: return "contact (C)";
  }
  return "?";
}

// Scenario, mesh, groups, materials and what model building logged.
std::string model_report(const PreparedRun& run) {
  const Model& m = run.model;
  const io::Scenario& sc = run.scenario;
  std::string r;
  r += fmt::format("scenario   {}{}\n", sc.file, sc.title.empty() ? "" : "  (" + sc.title + ")");
  r += fmt::format("mesh       {}: {} nodes, {} triangles{}, {}\n", sc.resolve(sc.mesh_file), m.nodes.size(),
                   m.triangles.size(), sc.crossed_mesh ? " (crossed)" : "",
                   sc.plane_stress ? fmt::format("plane stress, t = {} m", sc.thickness) : "plane strain");
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
  for (const auto& mat : m.materials) {
    r += fmt::format("material   {:<12} E = {:.4g} Pa, nu = {}, rho = {} kg/m^3, cp = {:.5g} m/s, cs = {:.5g} m/s\n",
                     mat.name, mat.E, mat.nu, mat.rho, mat.cp(), mat.cs());
    // The law's own parameters past E, nu, rho, by their declared names and units (law/registry.hpp).
    if (const law::LawDecl* decl = law::material_laws().find(mat.model); decl && decl->params.size() > 3) {
      std::string params;
      for (std::size_t k = 3; k < decl->params.size() && k < mat.params.size(); ++k)
        params += fmt::format("{}{} = {:.4g}{}{}", params.empty() ? "" : ", ", decl->params[k].name, mat.params[k],
                              decl->params[k].unit.empty() ? "" : " ", decl->params[k].unit);
      r += fmt::format("           {:<12} {}: {}\n", "", mat.model, params);
    }
  }
  for (const auto& line : run.build_log)
    r += fmt::format("{}{}\n", line.level >= static_cast<int>(spdlog::level::warn) ? "warning: " : "model      ", line.text);
  return r;
}

// A stage's water at rest (docs/theory.md §8) in a few words.
std::string water_text(const io::WaterSpec& w) {
  if (!w.present) return "";
  std::string s = w.ru > 0.0                ? fmt::format(", water: ru = {} below the ground surface", w.ru)
                  : w.line.size() == 1      ? fmt::format(", water: level {} m", w.line.front().y())
                                            : fmt::format(", water: line of {} points", w.line.size());
  if (!w.pore_pressure_in_matrix) s += " (discontinuities only)";
  for (const auto& c : w.cracks) s += fmt::format(", {} filled to {} m", c.curve, c.level);
  return s;
}

// The time step and its control, the stages and the gauges.
std::string time_report(const PreparedRun& run) {
  const io::Scenario& sc = run.scenario;
  std::string r;
  r += fmt::format("stable dt  {:.4g} s, controlled by {}\n", run.stable.dt, run.stable.controlled_by);
  const bool grows = sc.adaptive_dt && run.fixed_limit.dt > run.stable.dt;
  r += fmt::format("time step  {:.4g} s ({}{}), {}{} steps for {} s in {} stage{}\n", run.dt,
                   sc.dt ? "fixed" : fmt::format("safety {}", sc.safety),
                   grows ? fmt::format("; adaptive: up to {:.4g} s as joints break, then set by {}",
                                       sc.safety * run.fixed_limit.dt, run.fixed_limit.controlled_by)
                         : "",
                   grows ? "at most " : "", run.estimated_steps, sc.end_time(), sc.stages.size(),
                   sc.stages.size() == 1 ? "" : "s");
  for (const auto& st : sc.stages)
    r += fmt::format("  stage    {:<12} {} s, alpha = {} 1/s, beta = {} s, {} boundary conditions{}\n", st.name,
                     st.duration, st.damping.alpha, st.damping.beta, st.boundaries.size(), water_text(st.water));
  for (const auto& g : run.gauges)
    r += fmt::format("gauge      {:<12} at ({}, {}) m in triangle {}\n", g.name, g.at.x(), g.at.y(), g.triangle);
  return r;
}

struct StepTiming {
  double per_step_s = 0.0;
  int steps_timed = 0;
};

// Times a few steps on a copy of the model.
StepTiming time_steps(const PreparedRun& run) {
  Model copy = run.model;
  solver::Solver solver(copy);
  apply_stage(solver, run.scenario.stages.front(), run.scenario, run.dt, 0.0);
  solver.initialise();
  // The first steps pay for the contact search set-up, first-touch of the arrays and the
  // solver's timed choice between one thread and OpenMP: untimed, or the estimate comes
  // out several times too long. Then at least 40 steps, up to 0.5 s.
  const long total = std::max<long>(1, run.estimated_steps);
  const int warmup = static_cast<int>(std::min<long>(3 * solver::Solver::kProbeSteps + 6, total));
  for (int i = 0; i < warmup; ++i) solver.step();
  int probe = 0;
  const auto t0 = Clock::now();
  double elapsed = 0.0;
  while (probe < total - warmup && probe < 1000 && (probe < 40 || elapsed < 0.5)) {
    solver.step();
    ++probe;
    elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  return {probe > 0 ? elapsed / probe : 0.0, probe};
}

}  // namespace

WaterEstimate estimate_water_steps(const PreparedRun& run) {
  const MovingWaterLayout& w = *run.moving_water;
  sph::Fluid fluid(w.parameters, w.fluid, w.walls, false);
  const double dt = fluid.stable_dt();
  WaterEstimate e;
  for (int i = 0; i < 3; ++i) fluid.step(dt);  // first touch of the lists
  const auto t0 = Clock::now();
  double elapsed = 0.0;
  while (e.steps_timed < 20 || (elapsed < 0.3 && e.steps_timed < 1000)) {
    fluid.step(dt);
    ++e.steps_timed;
    elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  e.per_step_s = elapsed / e.steps_timed;
  // In the run the water moves, up to the c0 / 10 its sound speed was chosen for (docs/theory.md
  // §11), and its step shortens to cfl h / (c0 + v): counted at that speed.
  const sph::FluidParameters& p = fluid.parameters();
  const double dt_flow = std::min(dt, sph::stable_time_step(p.h(), p.c0, 0.1 * p.c0, 0.0, p.cfl));
  e.per_solid_step = std::ceil(run.dt / dt_flow);
  const double during_run = dt_flow < run.dt ? static_cast<double>(run.estimated_steps) * e.per_solid_step
                                             : std::ceil(run.scenario.end_time() / dt_flow);
  e.steps = std::ceil(run.scenario.reservoir.sph.settle / dt) + during_run;
  return e;
}

std::string check_report(PreparedRun& run) {
  std::string r = model_report(run) + time_report(run);
  const StepTiming timing = time_steps(run);
  double wall = timing.per_step_s * static_cast<double>(run.estimated_steps);
  r += fmt::format("estimate   {:.3g} ms per step ({} threads, {} steps timed) -> about {} of wall time (from the "
                   "first steps: contacts that form later make steps slower)\n",
                   timing.per_step_s * 1e3, omp_get_max_threads(), timing.steps_timed, human_time(wall));
  if (run.moving_water) {
    const WaterEstimate water = estimate_water_steps(run);
    const double water_wall = water.per_step_s * water.steps;
    wall += water_wall;
    r += fmt::format("estimate   the water: {:.3g} ms per water step (at rest, {} steps timed), about {:.3g} water steps "
                     "with the settle's, the run's at c0 / 10 ({}) -> about {} more, {} in all\n",
                     water.per_step_s * 1e3, water.steps_timed, water.steps,
                     water.per_solid_step > 1.0 ? fmt::format("{:.0f} per solid step", water.per_solid_step)
                                                : std::string("one over one or more solid steps"),
                     human_time(water_wall), human_time(wall));
    // A sound speed far beyond the flow's (a speed typed in the wrong unit) shows as water
    // steps many to a solid step.
    if (water.per_solid_step > kManyWaterSteps)
      r += fmt::format("warning: the water takes {:.0f} steps per solid step: its sound speed {:.4g} m/s "
                       "(reservoir.sph.sound_speed, or 10 max(sqrt(g H), reservoir.sph.expected_speed)) sets its step\n",
                       water.per_solid_step, run.moving_water->parameters.c0);
  }
  const std::size_t mem = estimate_memory_bytes(run), avail = available_memory_bytes();
  r += fmt::format("memory     about {} needed, {} available; output about {}\n", human_bytes(static_cast<double>(mem)),
                   avail ? human_bytes(static_cast<double>(avail)) : std::string("unknown"),
                   human_bytes(static_cast<double>(estimate_output_bytes(run))));
  for (const auto& w : resource_warnings(mem, avail, wall)) r += fmt::format("warning: {}\n", w);
  return r;
}

std::size_t estimate_memory_bytes(const PreparedRun& run) {
  const Model& m = run.model;
  // Per entity, from the data structures (model + solver scratch + output buffers):
  //   node: Nodes (X u v a: 4 Vec2, m, origin) ~ 76 B, solver (incidence of the nodes of
  //         continuous zones; damping forces x2 and u_prev in a damped stage) ~ 60 B, VTU
  //         frame ~ 100 B;
  //   triangle: Triangles (conn, group, material, zone, Dm_inv, area0; stress0 when set;
  //         stress and strain while a frame is written) ~ 110 B, solver (energy, joint slots;
  //         element forces and incidence in continuous zones; damping forces when beta > 0)
  //         ~ 130 B, contact shape and broad-phase entries ~ 220 B, VTU frame ~ 250 B;
  //   joint: Joints (4 nodes, 2 triangles, two 48-byte end-point states, length, scale,
  //         break record) ~ 150 B, force slots 32 B, crack output ~ 100 B.
  // Plus ~60 MB for the program, its libraries (VTK, HDF5) and set-up.
  constexpr std::size_t kNode = 260, kTriangle = 750, kJoint = 280, kBase = 60u << 20;
  std::size_t bytes = kBase + m.nodes.size() * kNode + m.triangles.size() * kTriangle + m.joints.size() * kJoint;
  for (const auto& rec : {run.quake_horizontal, run.quake_vertical})
    if (rec) bytes += rec->a.size() * 3 * sizeof(double);
  // The moving water: its particles in the Fluid and in the layout the run keeps, the wall
  // particles (BoundaryParticles, ~14 values each, and their cell entries).
  if (const auto& w = run.moving_water) {
    constexpr std::size_t kWallParticle = 128;
    bytes += w->fluid.size() * (sph::Fluid::bytes_per_particle(w->parameters) + 14 * sizeof(double)) +
             2 * w->walls.size() * kWallParticle;
  }
  return bytes;
}

std::size_t estimate_output_bytes(const PreparedRun& run, bool write_fields) {
  const Model& m = run.model;
  const io::Scenario& sc = run.scenario;
  const double end = sc.end_time();
  const double frames = write_fields && sc.output.field_interval > 0 ? std::floor(end / sc.output.field_interval) + 2 : 0;
  // A VTU frame: ~ 60 B per node, ~ 150 B per triangle (binary arrays, base64); a crack frame per joint ~ 100 B.
  const double frame = 60.0 * m.nodes.size() + 150.0 * m.triangles.size() + 100.0 * m.joints.size();
  const double rows = sc.output.history_interval > 0 ? std::floor(end / sc.output.history_interval) + 2 : 0;
  const double row = 24.0 * (16 + 2 * 4 + 6 * sc.output.gauges.size());
  // The water's frames (water.vtu: position, velocity, pressure, density, id, base64) ~ 70 B per particle.
  const double water_frame = run.moving_water ? 70.0 * static_cast<double>(run.moving_water->fluid.size()) : 0.0;
  const double total = frames * (frame + water_frame) + rows * row + (1u << 20);
  return total > 1e18 ? static_cast<std::size_t>(1e18) : static_cast<std::size_t>(total);
}

std::size_t available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::size_t value = 0;
  std::string unit;
  while (in >> key >> value) {
    std::getline(in, unit);
    if (key == "MemAvailable:") return value * 1024;
  }
  return 0;
}

std::vector<std::string> resource_warnings(std::size_t memory_bytes, std::size_t available_bytes, double wall_seconds) {
  std::vector<std::string> w;
  if (available_bytes > 0 && memory_bytes > available_bytes)
    w.push_back(fmt::format("this run needs about {} of memory but the machine has {} available (MemAvailable): "
                            "use a coarser mesh or a larger machine",
                            human_bytes(static_cast<double>(memory_bytes)), human_bytes(static_cast<double>(available_bytes))));
  constexpr double kDay = 24 * 3600.0;
  if (std::isfinite(wall_seconds) && wall_seconds > kDay)
    w.push_back(fmt::format("this run would take about {:.1f} h of wall time (more than 24 h): shorten time.end, "
                            "coarsen the mesh or raise time.safety",
                            wall_seconds / 3600.0));
  return w;
}

}  // namespace dsdem::run
