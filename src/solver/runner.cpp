#include "solver/runner.hpp"

#include "mesh/node_order.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <optional>

#include "dsdem_version.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "io/history_writer.hpp"
#include "io/json_writer.hpp"
#include "io/pvd.hpp"
#include "io/vtu_writer.hpp"
#include "io/crack_output.hpp"
#include "mesh/model_builder.hpp"
#include "seismic/artificial_wave.hpp"
#include "solver/fragments.hpp"

namespace dsdem::solver {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

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

}  // namespace

PreparedRun prepare_run(const io::Scenario& scenario, const std::string& work_dir) {
  PreparedRun run;
  run.scenario = scenario;
  RawMesh raw;
  {
    BuildLogCapture capture;
    raw = mesh::load_mesh(scenario, work_dir);
    run.model = mesh::build_model(scenario, raw);
    run.build_log = capture.lines();
  }
  run.mesh_file = raw.msh_file;
  if (!work_dir.empty() && !run.mesh_file.empty()) {
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
  run.fixed_limit = triangle_step_limit(run.model, max_beta);
  if (StableStep c = contact_step_limit(run.model); c.dt < run.fixed_limit.dt) run.fixed_limit = std::move(c);
  run.dt = scenario.dt.value_or(scenario.safety * run.stable.dt);
  if (scenario.dt && *scenario.dt > run.stable.dt)
    throw io::ScenarioError({fmt::format("{}: time.dt: {} s exceeds the stable time step {:.4g} s set by {}",
                                         scenario.file, *scenario.dt, run.stable.dt, run.stable.controlled_by)});
  run.estimated_steps = static_cast<long>(std::ceil(scenario.end_time() / run.dt));

  // Earthquake: records, and stages that can carry it.
  const io::EarthquakeSpec& q = scenario.earthquake;
  try {
    if (q.horizontal.present) run.quake_horizontal = load_motion(q.horizontal, run.dt);
    if (q.vertical.present) run.quake_vertical = load_motion(q.vertical, run.dt);
  } catch (const io::ScenarioError&) {
    throw;
  } catch (const std::exception& e) {
    throw io::ScenarioError({fmt::format("{}: earthquake: {}", scenario.file, e.what())});
  }
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

namespace {

std::string zone_name(Zone z) {
  switch (z) {
    case Zone::Discrete: return "discrete (A)";
    case Zone::Bedrock: return "continuous (B)";
    case Zone::ContactBedrock: return "contact (C)";
  }
  return "?";
}

std::string signal_name(int sig) {
  if (sig == SIGINT) return "SIGINT";
  if (sig == SIGTERM) return "SIGTERM";
  return fmt::format("signal {}", sig);
}

std::string human_time(double s) {
  if (!std::isfinite(s)) return "?";
  if (s < 120) return fmt::format("{:.1f} s", s);
  if (s < 7200) return fmt::format("{:.1f} min", s / 60);
  return fmt::format("{:.1f} h", s / 3600);
}

// Settings, supports, viscous boundary and earthquake of a stage that starts at
// `start_time` (prescribed motions and the earthquake's time zero are the stage start).
void apply_stage(Solver& solver, const io::StageSpec& stage, const io::Scenario& sc, double dt, double start_time,
                 const PreparedRun* prepared = nullptr) {
  StepSettings s;
  s.gravity = sc.gravity;
  s.alpha = stage.damping.alpha;
  s.beta = stage.damping.beta;
  s.dt = dt;
  s.failure = stage.failure;
  solver.set_settings(s);
  const std::vector<PrescribedDof> previous = solver.constraints();
  solver.set_constraints(build_constraints(solver.model(), stage.boundaries, start_time));
  solver.set_viscous_boundary(boundary::build_viscous_boundary(solver.model(), stage.boundaries), previous);
  if (stage.earthquake && prepared)
    solver.set_earthquake(prepared->quake_horizontal ? &*prepared->quake_horizontal : nullptr,
                          prepared->quake_vertical ? &*prepared->quake_vertical : nullptr,
                          sc.earthquake.incident_factor, start_time);
  else
    solver.set_earthquake(nullptr, nullptr, 0.5, 0.0);
}

}  // namespace

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
  // Plus ~60 MB for the program, its libraries (VTK, HDF5) and set-up (elastic slope,
  // 1083 triangles: 63 MB peak measured, 63.9 MB estimated).
  constexpr std::size_t kNode = 260, kTriangle = 750, kJoint = 280, kBase = 60u << 20;
  std::size_t bytes = kBase + m.nodes.size() * kNode + m.triangles.size() * kTriangle + m.joints.size() * kJoint;
  for (const auto& rec : {run.quake_horizontal, run.quake_vertical})
    if (rec) bytes += rec->a.size() * 3 * sizeof(double);
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
  const double total = frames * frame + rows * row + (1u << 20);
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

namespace {
std::string human_bytes(double b) {
  if (b < 1e6) return fmt::format("{:.0f} kB", b / 1e3);
  if (b < 1e9) return fmt::format("{:.1f} MB", b / 1e6);
  return fmt::format("{:.2f} GB", b / 1e9);
}
}  // namespace

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
  for (const auto& line : run.build_log)
    r += fmt::format("{}{}\n", line.level >= static_cast<int>(spdlog::level::warn) ? "warning: " : "model      ", line.text);
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
    r += fmt::format("  stage    {:<12} {} s, alpha = {} 1/s, beta = {} s, {} boundary conditions\n", st.name,
                     st.duration, st.damping.alpha, st.damping.beta, st.boundaries.size());
  for (const auto& g : run.gauges)
    r += fmt::format("gauge      {:<12} at ({}, {}) m in triangle {}\n", g.name, g.at.x(), g.at.y(), g.triangle);

  // Time a few steps on a copy to estimate the run time.
  Model copy = m;
  Solver solver(copy);
  apply_stage(solver, sc.stages.front(), sc, run.dt, 0.0);
  solver.initialise();
  // The first steps pay for the contact search set-up, first-touch of the arrays and the
  // solver's timed choice between one thread and OpenMP (steps 8-23): untimed, or the
  // estimate came out 4-7x too long on a busy machine (Brazilian disc: 13-22 ms per step
  // estimated, 3.4 ms run). Then at least 40 steps, up to 0.5 s.
  const long total = std::max<long>(1, run.estimated_steps);
  const int warmup = static_cast<int>(std::min<long>(3 * Solver::kProbeSteps + 6, total));
  for (int i = 0; i < warmup; ++i) solver.step();
  int probe = 0;
  const auto t0 = Clock::now();
  double elapsed = 0.0;
  while (probe < total - warmup && probe < 1000 && (probe < 40 || elapsed < 0.5)) {
    solver.step();
    ++probe;
    elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  const double per_step = probe > 0 ? elapsed / probe : 0.0;
  const double wall = per_step * static_cast<double>(run.estimated_steps);
  r += fmt::format("estimate   {:.3g} ms per step ({} threads, {} steps timed) -> about {} of wall time (from the "
                   "first steps: contacts that form later make steps slower)\n",
                   per_step * 1e3, omp_get_max_threads(), probe, human_time(wall));
  const std::size_t mem = estimate_memory_bytes(run), avail = available_memory_bytes();
  r += fmt::format("memory     about {} needed, {} available; output about {}\n", human_bytes(static_cast<double>(mem)),
                   avail ? human_bytes(static_cast<double>(avail)) : std::string("unknown"),
                   human_bytes(static_cast<double>(estimate_output_bytes(run))));
  for (const auto& w : resource_warnings(mem, avail, wall)) r += fmt::format("warning: {}\n", w);
  return r;
}

namespace {

struct GaugeStats {
  double max_disp = 0.0, max_speed = 0.0, time_of_max_speed = 0.0;
};

// What the runner carries from step to step besides the solver's state: saved with it in
// every checkpoint so that a restarted run writes what the uninterrupted one would (issue 8).
struct RunnerState {
  double time = 0.0;                  // s, of the checkpoint
  std::size_t stage = 0;              // stage running; stages.size() once all are done
  std::vector<double> stage_starts;   // s, start of each stage entered
  double stage_end = 0.0;             // s, end of the current stage
  double peak_kinetic = 0.0;          // in the current stage (stop_kinetic_ratio)
  double next_field = 0.0, next_history = 0.0;  // s
  double max_balance_error = 0.0;
  std::size_t history_rows = 0, fields_frames = 0, cracks_frames = 0, contacts_frames = 0;
  double wall_time_before = 0.0;      // s of wall time of the run's earlier parts
  std::vector<GaugeStats> gauges;
};

void write_runner_state(io::CheckpointWriter& w, const RunnerState& s, const PreparedRun& run) {
  const Model& m = run.model;
  w.put("runner/dt", run.dt);
  w.put_int("runner/adaptive_dt", run.scenario.adaptive_dt ? 1 : 0);
  w.put("runner/node_order", mesh::node_order_fingerprint(m.nodes.X));
  w.put_int("runner/spatial_triangle_order", run.scenario.spatial_triangle_order ? 1 : 0);
  w.put("runner/model_size", std::vector<double>{static_cast<double>(m.nodes.size()),
                                                  static_cast<double>(m.triangles.size()),
                                                  static_cast<double>(m.joints.size())});
  w.put_int("runner/stage", static_cast<std::int64_t>(s.stage));
  w.put("runner/stage_starts", s.stage_starts);
  w.put("runner/scalars", std::vector<double>{s.stage_end, s.peak_kinetic, s.next_field, s.next_history,
                                               s.max_balance_error, s.wall_time_before});
  w.put("runner/counts", std::vector<double>{static_cast<double>(s.history_rows), static_cast<double>(s.fields_frames),
                                              static_cast<double>(s.cracks_frames),
                                              static_cast<double>(s.contacts_frames)});
  std::vector<double> g;
  for (const auto& x : s.gauges) g.insert(g.end(), {x.max_disp, x.max_speed, x.time_of_max_speed});
  w.put("runner/gauges", g);
}

// Reads the runner's part of a checkpoint and checks that it belongs to this model, time
// step and scenario (messages say what differs). Throws std::runtime_error.
RunnerState read_runner_state(const io::CheckpointReader& in, const PreparedRun& run) {
  if (!in.has("runner/dt"))
    throw std::runtime_error("this checkpoint has no run state (written by an older dsdem or by the library)");
  const Model& m = run.model;
  const auto size = in.doubles("runner/model_size");
  if (size.size() != 3 || size[0] != static_cast<double>(m.nodes.size()) ||
      size[1] != static_cast<double>(m.triangles.size()) || size[2] != static_cast<double>(m.joints.size()))
    throw std::runtime_error(fmt::format(
        "it belongs to another model ({} nodes, {} triangles, {} joints; this scenario gives {}, {}, {}): use the "
        "scenario, mesh and --set options of the original run",
        size.size() > 0 ? size[0] : 0, size.size() > 1 ? size[1] : 0, size.size() > 2 ? size[2] : 0, m.nodes.size(),
        m.triangles.size(), m.joints.size()));
  // Nodes are numbered by first use since 2026-11 (mesh/node_order.hpp): node arrays in
  // any other order would be read into the wrong nodes.
  if (!in.has("runner/node_order"))
    throw std::runtime_error(
        "it was written by an older dsdem that numbered the nodes as the mesh does; this one numbers them in the "
        "order the elements use them, so its node arrays do not fit: run the scenario again from the start");
  // The triangle numbering moves every node (mesh/triangle_order.hpp); a checkpoint with
  // no record of it is from a dsdem that always kept the file's order.
  const bool spatial = in.has("runner/spatial_triangle_order") && in.integer("runner/spatial_triangle_order") != 0;
  if (spatial != run.scenario.spatial_triangle_order)
    throw std::runtime_error(fmt::format(
        "it was written with mesh.triangle_order = {}{}, this scenario gives {}: continue it with --set "
        "mesh.triangle_order={}",
        io::Scenario::triangle_order_name(spatial),
        in.has("runner/spatial_triangle_order") ? "" : " (dsdem before 2026-11-24)",
        io::Scenario::triangle_order_name(run.scenario.spatial_triangle_order), io::Scenario::triangle_order_name(spatial)));
  if (in.scalar("runner/node_order") != mesh::node_order_fingerprint(m.nodes.X))
    throw std::runtime_error("it belongs to another model (its node positions or their order differ): use the "
                             "scenario, mesh and --set options of the original run");
  const double dt = in.scalar("runner/dt");
  if (dt != run.dt)
    throw std::runtime_error(fmt::format("it was made with dt = {} s, this scenario gives dt = {} s: the time settings "
                                         "and materials must be those of the original run",
                                         dt, run.dt));
  // (A checkpoint from before time.adaptive has no flag: its run may go on either way.)
  if (in.has("runner/adaptive_dt") && (in.integer("runner/adaptive_dt") != 0) != run.scenario.adaptive_dt)
    throw std::runtime_error(fmt::format("it was made with time.adaptive = {}, this scenario gives {}: the time "
                                         "settings must be those of the original run",
                                         !run.scenario.adaptive_dt, run.scenario.adaptive_dt));
  RunnerState s;
  s.time = in.scalar("time");
  s.stage = static_cast<std::size_t>(in.integer("runner/stage"));
  const std::size_t stages = run.scenario.stages.size();
  if (s.stage >= stages)
    throw std::runtime_error(fmt::format(
        "the run in it is complete (all {} stages done at t = {} s): add a stage to the scenario to continue it",
        s.stage, s.time));
  s.stage_starts = in.doubles("runner/stage_starts");
  // Inside stage s.stage: its start is recorded. A complete run's end state (stage = the
  // number of stages done) has not entered the stage added since: run() enters it.
  if (s.stage_starts.size() != s.stage + 1 && s.stage_starts.size() != s.stage)
    throw std::runtime_error("its stage record is inconsistent (damaged file?)");
  const auto sc = in.doubles("runner/scalars");
  const auto counts = in.doubles("runner/counts");
  const auto g = in.doubles("runner/gauges");
  if (sc.size() != 6 || counts.size() != 4) throw std::runtime_error("its run state is incomplete (damaged file?)");
  if (g.size() != 3 * run.gauges.size())
    throw std::runtime_error(fmt::format("it has {} gauges, this scenario {}: the gauges must be those of the original run",
                                         g.size() / 3, run.gauges.size()));
  s.stage_end = sc[0];
  s.peak_kinetic = sc[1];
  s.next_field = sc[2];
  s.next_history = sc[3];
  s.max_balance_error = sc[4];
  s.wall_time_before = sc[5];
  s.history_rows = static_cast<std::size_t>(counts[0]);
  s.fields_frames = static_cast<std::size_t>(counts[1]);
  s.cracks_frames = static_cast<std::size_t>(counts[2]);
  s.contacts_frames = static_cast<std::size_t>(counts[3]);
  s.gauges.resize(run.gauges.size());
  for (std::size_t i = 0; i < s.gauges.size(); ++i) s.gauges[i] = {g[3 * i], g[3 * i + 1], g[3 * i + 2]};
  return s;
}

}  // namespace

RunResult run(PreparedRun& prepared, const RunOptions& options) {
  const auto wall_start = Clock::now();
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const int threads = omp_get_max_threads();
  const fs::path out(options.output_dir);
  // Before step 0: the output directory must exist or be creatable, be writable and have
  // room for the results. Bad output settings are bad input (exit code 2); nothing is written.
  try {
    io::ensure_writable_directory(out);
  } catch (const std::exception& e) {
    throw io::ScenarioError({fmt::format("--output {}: {}", out.string(), e.what())});
  }
  {
    struct statvfs fs_info {};
    if (::statvfs(out.c_str(), &fs_info) == 0) {
      const double free_bytes = static_cast<double>(fs_info.f_bavail) * static_cast<double>(fs_info.f_frsize);
      const double need = static_cast<double>(estimate_output_bytes(prepared, options.write_fields));
      if (free_bytes < need)
        throw io::ScenarioError({fmt::format(
            "--output {}: the file system has {} free but this run will write about {} (fields, history, log): "
            "free some space, choose another directory or write fewer frames (output.field_interval, --no-fields)",
            out.string(), human_bytes(free_bytes), human_bytes(need))});
    }
  }
  // Keep the mesh the run used next to its results.
  if (!prepared.mesh_file.empty()) {
    // Best effort: a mesh that cannot be copied does not stop the run.
    const fs::path copy = out / fs::path(prepared.mesh_file).filename();
    if (!prepared.mesh_text.empty()) {
      try {
        io::write_file_atomically(copy, prepared.mesh_text);
      } catch (const std::exception&) {
      }
    } else {
      std::error_code ec;
      fs::copy_file(prepared.mesh_file, copy, fs::copy_options::overwrite_existing, ec);
    }
  }

  // Restart (issue 8): the checkpoint must come from this model and time step. Resuming in
  // the checkpoint's own directory continues its files; elsewhere new files start at the
  // checkpoint's time.
  std::optional<io::CheckpointReader> checkpoint;
  RunnerState state;
  bool continue_files = false;
  if (!options.restart_from.empty()) {
    const fs::path ckpt(options.restart_from);
    try {
      checkpoint.emplace(ckpt);
      state = read_runner_state(*checkpoint, prepared);
    } catch (const io::ScenarioError&) {
      throw;
    } catch (const std::exception& e) {
      throw io::ScenarioError({fmt::format("--restart {}: {}", ckpt.string(), e.what())});
    }
    std::error_code ec;
    continue_files = fs::equivalent(fs::absolute(ckpt).parent_path(), out, ec);
  }

  // Log: file always, terminal unless quiet.
  auto file_sink =
      std::make_shared<spdlog::sinks::basic_file_sink_mt>((out / "dsdem.log").string(), !continue_files);
  std::vector<spdlog::sink_ptr> sinks{file_sink};
  if (!options.quiet) sinks.push_back(std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  auto log = std::make_shared<spdlog::logger>("dsdem", sinks.begin(), sinks.end());
  log->set_pattern("[%H:%M:%S] %v");
  log->flush_on(spdlog::level::info);

  io::Scenario& sc = prepared.scenario;
  Model& model = prepared.model;
  log->info("dsdem {} ({}), {} threads", DSDEM_VERSION, DSDEM_GIT_COMMIT, threads);
  for (const auto& line : prepared.build_log) log->log(static_cast<spdlog::level::level_enum>(line.level), "{}", line.text);
  log->info("scenario {}: {} nodes, {} triangles, {} joints", sc.file, model.nodes.size(), model.triangles.size(),
            model.joints.size());
  log->info("dt = {:.4g} s ({} x stable {:.4g} s, controlled by {}){}", prepared.dt, sc.dt ? 1.0 : sc.safety,
            prepared.stable.dt, prepared.stable.controlled_by,
            sc.adaptive_dt ? fmt::format("; adaptive: taken again as joints break, up to {:.4g} s",
                                         sc.safety * prepared.fixed_limit.dt)
                           : "");

  Solver solver(model);
  if (sc.adaptive_dt) solver.set_time_step_rule(sc.safety, prepared.fixed_limit.dt);
  // What sets the current step (critical value, before the safety factor).
  auto step_control = [&]() -> StableStep {
    if (!solver.has_time_step_rule()) return prepared.stable;
    const JointStepLimit* joint = solver.time_step_joint();
    return joint ? describe_joint_limit(model, *joint) : prepared.fixed_limit;
  };
  // Stress and strain are needed by the field frames and the checkpoint only: computed
  // there (write_fields; Solver::save) instead of every step, and not kept in between.
  solver.set_stress_on_demand(true);
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
                                         {"contact_damping_dissipated", energy_unit},
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
  std::optional<io::HistoryWriter> history_file;
  if (continue_files)
    history_file.emplace(out / "history.csv", columns, io::HistoryWriter::Resume{state.history_rows});
  else
    history_file.emplace(out / "history.csv", columns);
  io::HistoryWriter& history = *history_file;
  // Frames after the checkpoint (in time or in number) are written again by the resumed run.
  auto open_series = [&](const std::string& name, std::size_t frames) {
    return continue_files ? io::PvdSeries::resume(out / name, state.time, frames) : io::PvdSeries(out / name);
  };
  io::PvdSeries fields = open_series("fields.pvd", state.fields_frames);

  std::vector<double> row(columns.size());
  std::vector<Index> fragment_label;
  const bool has_joints = model.joints.size() > 0;
  std::optional<io::PvdSeries> cracks;
  if (has_joints) cracks.emplace(open_series("cracks.pvd", state.cracks_frames));
  std::optional<io::PvdSeries> contacts;
  if (model.contact.enabled && model.contact.output) contacts.emplace(open_series("contacts.pvd", state.contacts_frames));
  std::vector<Vec2> contact_points, contact_forces;
  std::vector<double> contact_normal_force, contact_overlap;
  std::vector<GaugeStats>& gauge_stats = state.gauges;
  gauge_stats.resize(prepared.gauges.size());
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
    row[k++] = e.contact_damping_dissipated;
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
    solver.update_stress();  // on demand: computed for this frame, released after it
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
    solver.release_stress();  // 48 B per triangle, not held between frames (issue 7)
    fields.add(solver.time(), file);
    if (cracks) {
      const fs::path cfile = cracks->frame_path(cracks->size());
      io::write_cracks_vtu(cfile, model, solver.time());
      cracks->add(solver.time(), cfile);
    }
    if (contacts && solver.contact()) {
      contact_points.clear();
      contact_forces.clear();
      contact_normal_force.clear();
      contact_overlap.clear();
      solver.contact()->for_each_contact([&](const contact::ContactRecord& c) {
        contact_points.push_back(c.point);
        contact_forces.push_back(c.force);
        contact_normal_force.push_back(c.fn);
        contact_overlap.push_back(c.overlap);
      });
      const std::string funit = plane_strain ? "N_per_m" : "N";
      const fs::path pfile = contacts->frame_path(contacts->size());
      io::VtuOptions po;
      po.time_s = solver.time();
      io::write_points_vtu(pfile, contact_points,
                           {io::vector_field("contact_force", funit, contact_forces),
                            io::scalar_field("normal_force", funit, std::span<const double>(contact_normal_force)),
                            io::scalar_field("overlap", "m", std::span<const double>(contact_overlap))},
                           po);
      contacts->add(solver.time(), pfile);
    }
  };

  const bool tty = !options.quiet && isatty(STDERR_FILENO);
  const double end_time = sc.end_time();
  const auto loop_start = Clock::now();
  int stopped_by = 0;
  bool stopped_at_step = false;
  auto last_progress = loop_start;
  auto last_checkpoint = loop_start;
  long steps_at_last_progress = 0, first_step = 0;
  const double wall_before = state.wall_time_before;
  const fs::path checkpoint_path = out / "checkpoint.h5";
  // The history on disk must hold exactly the rows written so far: a resumed run keeps
  // that many rows and appends after them.
  auto save_checkpoint = [&] {  // (Solver::save computes the stress it writes)
    history.flush();
    state.time = solver.time();
    state.history_rows = history.rows_written();
    state.fields_frames = fields.size();
    state.cracks_frames = cracks ? cracks->size() : 0;
    state.contacts_frames = contacts ? contacts->size() : 0;
    state.wall_time_before = wall_before + std::chrono::duration<double>(Clock::now() - wall_start).count();
    io::CheckpointWriter w(checkpoint_path);
    solver.save(w);
    write_runner_state(w, state, prepared);
    w.commit();
    last_checkpoint = Clock::now();
  };
  const bool resumed = checkpoint.has_value();
  const std::size_t resume_stage = state.stage;
  // false: the checkpoint is a complete run's end state and resume_stage a stage added
  // to the scenario since, entered below as a run going on would enter it.
  const bool resume_inside_stage = resumed && state.stage_starts.size() > resume_stage;
  try {
    if (resumed) {
      // Each stage's supports, viscous boundary and earthquake as the original run set
      // them (at their own start times), then the saved state over them.
      for (std::size_t si = 0; si < state.stage_starts.size(); ++si) {
        apply_stage(solver, sc.stages[si], sc, prepared.dt, state.stage_starts[si], &prepared);
        if (si == 0) solver.initialise();
      }
      solver.restore(*checkpoint);
      checkpoint.reset();
      log->info("restarted from {} at step {}, t = {:.6g} s, {} stage {} '{}'", options.restart_from,
                solver.step_count(), solver.time(), resume_inside_stage ? "in" : "at the start of", resume_stage + 1,
                sc.stages[resume_stage].name);
      if (!continue_files) {
        write_fields();
        write_history(static_cast<int>(resume_stage));
      }
    }
    first_step = steps_at_last_progress = solver.step_count();
    for (std::size_t si = state.stage; si < sc.stages.size(); ++si) {
      const io::StageSpec& stage = sc.stages[si];
      if (!(resume_inside_stage && si == resume_stage)) {
        apply_stage(solver, stage, sc, prepared.dt, solver.time(), &prepared);
        state.stage = si;
        state.stage_starts.push_back(solver.time());
        if (si == 0) {
          solver.initialise();
          write_fields();
          write_history(0);
          state.next_field = sc.output.field_interval;
          state.next_history = sc.output.history_interval;
        }
        state.stage_end += stage.duration;
        state.peak_kinetic = 0.0;
        log->info("stage {} '{}': {} s to t = {} s, alpha = {} 1/s, beta = {} s, joints {}", si + 1, stage.name,
                  stage.duration, state.stage_end, stage.damping.alpha, stage.damping.beta,
                  stage.failure ? "may break" : "elastic (no failure)");
      }
      // Stop within half a step of the stage end.
      while (solver.time() < state.stage_end - 0.5 * solver.settings().dt) {
        if (options.stop_signal && *options.stop_signal) break;
        solver.step();
        update_gauge_stats();
        const double t = solver.time();
        if (t >= state.next_history - 0.5 * solver.settings().dt) {
          write_history(static_cast<int>(si));
          state.next_history += sc.output.history_interval;
          state.max_balance_error = std::max(state.max_balance_error, solver.energy().balance_error());
        }
        if (t >= state.next_field - 0.5 * solver.settings().dt) {
          write_fields();
          state.next_field += sc.output.field_interval;
        }
        state.peak_kinetic = std::max(state.peak_kinetic, solver.energy().kinetic);
        if (stage.stop_kinetic_ratio > 0 && solver.energy().kinetic < stage.stop_kinetic_ratio * state.peak_kinetic &&
            t > 0.05 * stage.duration + (state.stage_end - stage.duration)) {
          log->info("stage '{}' at rest at t = {:.4g} s (kinetic energy below {} of its peak)", stage.name, t,
                    stage.stop_kinetic_ratio);
          break;
        }
        const auto now = Clock::now();
        // Checkpoints after this step's output, so that the files and the checkpoint agree.
        if ((sc.output.checkpoint_steps > 0 && solver.step_count() % sc.output.checkpoint_steps == 0) ||
            (sc.output.checkpoint_interval > 0 &&
             std::chrono::duration<double>(now - last_checkpoint).count() >= sc.output.checkpoint_interval))
          save_checkpoint();
        if (options.stop_at_step > 0 && solver.step_count() >= options.stop_at_step) {
          stopped_at_step = true;
          break;
        }
        if (std::chrono::duration<double>(now - last_progress).count() >= sc.output.progress_interval) {
          const double rate = (solver.step_count() - steps_at_last_progress) /
                              std::chrono::duration<double>(now - last_progress).count();
          const double eta = (end_time - t) / solver.settings().dt / rate;
          const std::string line = fmt::format(
              "[{}] t = {:.4g} / {:.4g} s  {:.0f} steps/s  ETA {}  dt {:.4g} s  broken joints {}  contacts {}  energy "
              "balance {:.2e}",
              stage.name, t, end_time, rate, human_time(eta), solver.settings().dt, solver.broken_joints(),
              solver.active_contacts(), solver.energy().balance_error());
          if (tty)
            fmt::print(stderr, "\r{:<100}", line);
          else if (!options.quiet)
            fmt::print(stderr, "{}\n", line);
          file_sink->log(spdlog::details::log_msg("dsdem", spdlog::level::info, line));
          file_sink->flush();  // a direct sink call skips the logger's flush_on: `tail -f` must see it
          last_progress = now;
          steps_at_last_progress = solver.step_count();
        }
      }
      if (options.stop_signal && *options.stop_signal) {
        stopped_by = static_cast<int>(*options.stop_signal);
        if (tty) fmt::print(stderr, "\n");
        log->warn("run stopped by {} at step {}, t = {:.6g} s in stage '{}': writing a checkpoint and the last fields, "
                  "history and summary",
                  signal_name(stopped_by), solver.step_count(), solver.time(), stage.name);
        save_checkpoint();
        break;
      }
      if (stopped_at_step) {
        if (tty) fmt::print(stderr, "\n");
        log->info("stopped at step {} (--stop-at-step), t = {:.6g} s in stage '{}': checkpoint written", solver.step_count(),
                  solver.time(), stage.name);
        save_checkpoint();
        break;
      }
    }
  } catch (const InstabilityError& e) {
    if (tty) fmt::print(stderr, "\n");
    log->error("run stopped: {}", e.what());
    // The diagnosis first (it must survive whatever follows), then the last state.
    const std::string entity = e.kind == "inverted_element" ? "element"
                               : e.id == kNoIndex           ? "model"
                                                            : "node";
    io::Json diag = io::Json::object({{"kind", e.kind},
                                      {"message", std::string(e.what())},
                                      {"entity", entity},
                                      {"id", e.id},
                                      {"position_m", io::Json::array({e.position.x(), e.position.y()})},
                                      {"step", e.step},
                                      {"time_s", e.time},
                                      {"dt_s", solver.settings().dt},
                                      {"stable_dt_s", step_control().dt},
                                      {"stable_dt_controlled_by", step_control().controlled_by}});
    io::write_json_file(out / "diagnosis.json", diag);
    try {
      write_fields();
      write_history(-1);
      history.close();
      if (has_joints) io::write_crack_log_csv(out / "cracks.csv", model);
    } catch (const std::exception& w) {
      log->error("could not write the last state: {}", w.what());
    }
    log->error("diagnosis in {}", (out / "diagnosis.json").string());
    throw;
  }
  if (tty) fmt::print(stderr, "\n");
  // Last state, unless just written.
  if (fields.size() == 0 || std::abs(state.next_field - sc.output.field_interval - solver.time()) > 0.5 * solver.settings().dt)
    write_fields();
  if (history.rows_written() == 0 ||
      std::abs(state.next_history - sc.output.history_interval - solver.time()) > 0.5 * solver.settings().dt)
    write_history(static_cast<int>(std::min(state.stage, sc.stages.size() - 1)));
  const bool completed = stopped_by == 0 && !stopped_at_step;
  if (completed) {
    // The end state, for a later continuation with added stages.
    state.stage = sc.stages.size();
    save_checkpoint();
  }
  history.close();
  const double max_balance_error = std::max(state.max_balance_error, solver.energy().balance_error());

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
  summary["dt_adaptive"] = sc.adaptive_dt;
  summary["triangle_order"] = std::string(io::Scenario::triangle_order_name(sc.spatial_triangle_order));  // to rerun it bit for bit
  summary["dt_last_s"] = solver.settings().dt;
  summary["dt_last_controlled_by"] = step_control().controlled_by;
  summary["end_time_s"] = solver.time();
  summary["threads"] = threads;
  const long steps_run = solver.step_count() - first_step;
  if (threads > 1) summary["steps_on_one_thread"] = solver.serial_steps_chosen();
  summary["wall_time_s"] = wall;
  if (resumed) {
    summary["restarted_from"] = options.restart_from;
    summary["restart_step"] = first_step;
    summary["wall_time_total_s"] = wall_before + wall;
  }
  summary["checkpoint"] = checkpoint_path.string();
  summary["element_steps_per_s"] = model.triangles.size() * static_cast<double>(solver.step_count() - first_step) /
                                   std::max(1e-9, std::chrono::duration<double>(Clock::now() - loop_start).count());
  summary["energy_balance_error"] = max_balance_error;
  summary["completed"] = completed;
  if (stopped_by) summary["stopped_by"] = signal_name(stopped_by);
  if (stopped_at_step) summary["stopped_at_step"] = solver.step_count();
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
  energies["contact_damping_dissipated"] = e.contact_damping_dissipated;
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
  if (!completed)
    log->warn("stopped{}: {} steps in {}; last fields, history and summary in {}; continue with "
              "`dsdem run {} --restart {}`",
              stopped_by ? " by " + signal_name(stopped_by) : " at step " + std::to_string(solver.step_count()),
              solver.step_count(), human_time(wall), out.string(), sc.file, checkpoint_path.string());
  else
    log->info("done: {} steps in {}, energy balance error {:.2e}; results in {}", solver.step_count(), human_time(wall),
            max_balance_error, out.string());
  if (solver.has_time_step_rule() && solver.settings().dt != prepared.dt)
    log->info("time step grew from {:.4g} s to {:.4g} s as joints broke; now set by {}", prepared.dt,
              solver.settings().dt, step_control().controlled_by);
  // The timed thread choice (Solver::probe_parallel) fell back to one thread for a large
  // part of the run: say so, or a slow run on a busy machine is a mystery.
  if (threads > 1 && steps_run > 0 && solver.serial_steps_chosen() > steps_run / 10)
    log->info("{} of the {} steps ({:.0f} %) ran on one thread: timing found the {} threads slower then "
              "(other busy processes on the machine?)",
              solver.serial_steps_chosen(), steps_run, 100.0 * solver.serial_steps_chosen() / steps_run, threads);
  spdlog::drop("dsdem");

  RunResult result;
  result.steps = solver.step_count();
  result.wall_time_s = wall;
  result.energy_balance_error = max_balance_error;
  result.summary_path = (out / "summary.json").string();
  result.stopped_by_signal = stopped_by;
  result.stopped_at_step = stopped_at_step;
  result.checkpoint_path = checkpoint_path.string();
  return result;
}

}  // namespace dsdem::solver
