#include "run/runner.hpp"

#include <omp.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "dsdem_version.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "io/json_file.hpp"
#include "run/outputs.hpp"
#include "run/outputs3d.hpp"
#include "run/run3d.hpp"
#include "run/restart.hpp"
#include "run/stage.hpp"
#include "run/summary.hpp"
#include "run/text.hpp"
#include "run/time_step.hpp"

namespace dsdem::run {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The --set overrides as a shell would take them back: " --set 'key=value'" each, a single
// quote inside written '\''.
std::string shell_sets(const std::vector<std::string>& overrides) {
  std::string out;
  for (const std::string& o : overrides) {
    out += " --set '";
    for (const char c : o) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    out += "'";
  }
  return out;
}

// Water faster than a tenth of its sound speed is no longer weakly compressible (docs/theory.md
// §11: c0 >= 10 v_max): said after the run with the flow's speed (1 % of the water faster) and
// when, the setting that keeps it within, and the fastest particle apart.
void warn_of_fast_water(spdlog::logger& log, const WaterWatch& water, double c0) {
  const WaterWatch::Peak &v = water.flow_speed(), &top = water.max_speed();
  if (!v.seen || !(v.value > 0.1 * c0)) return;
  log.warn("1 % of the water moved faster than {:.3g} m/s (t = {:.4g} s), more than c0 / 10 = {:.3g} m/s: there its "
           "weak compressibility errs by more than about 1 % in density; reservoir.sph.expected_speed: {:.3g} (or "
           "sound_speed: {:.3g}) keeps it within, at {:.2g} times the water's steps (the fastest particle: {:.3g} m/s "
           "at x = {:.6g} m, t = {:.4g} s; summary.json moving_water.flow_speed, max_speed)",
           v.value, v.t, 0.1 * c0, v.value, 10.0 * v.value, 10.0 * v.value / c0, top.value, top.x, top.t);
}

// Before step 0: the output directory must exist or be creatable, be writable and have
// room for the results. Bad output settings are bad input (exit code 2); nothing is written.
template <class Prepared>
void check_output_dir(const fs::path& out, const Prepared& prepared, bool write_fields) {
  try {
    io::ensure_writable_directory(out);
  } catch (const std::exception& e) {
    throw io::ScenarioError({fmt::format("--output {}: {}", out.string(), e.what())});
  }
  struct statvfs fs_info {};
  if (::statvfs(out.c_str(), &fs_info) != 0) return;
  const double free_bytes = static_cast<double>(fs_info.f_bavail) * static_cast<double>(fs_info.f_frsize);
  const double need = static_cast<double>(estimate_output_bytes(prepared, write_fields));
  if (free_bytes < need)
    throw io::ScenarioError({fmt::format(
        "--output {}: the file system has {} free but this run will write about {} (fields, history, log): "
        "free some space, choose another directory or write fewer frames (output.field_interval, --no-fields)",
        out.string(), human_bytes(free_bytes), human_bytes(need))});
}

// Keeps the mesh the run used next to its results. Best effort: a mesh that cannot be
// copied does not stop the run.
void keep_mesh(const fs::path& out, const PreparedRun& prepared) {
  if (prepared.mesh_file.empty()) return;
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

// The prepared run, solver and outputs of each dimension: the runner is the same.
template <int D>
struct RunParts;
template <>
struct RunParts<2> {
  using Prepared = PreparedRun;
  using SolverT = solver::Solver;
  using Outputs = RunOutputs;
};
template <>
struct RunParts<3> {
  using Prepared = PreparedRun3;
  using SolverT = solver::Solver3;
  using Outputs = RunOutputs3;
};

// The solver set up for a stage that starts at start_time (run/stage.hpp, run/run3d.hpp).
void set_up_stage(solver::Solver& s, const io::StageSpec& stage, PreparedRun& p, double start_time) {
  apply_stage(s, stage, p.scenario, p.dt, start_time, &p);
}
void set_up_stage(solver::Solver3& s, const io::StageSpec& stage, PreparedRun3& p, double start_time) {
  apply_stage_3d(s, stage, p, p.gravity, start_time);
}

// One run: its solver, outputs, log and the state a checkpoint keeps, from the set-up
// through the stage loop to the summary.
template <int D>
class Runner {
 public:
  using Prepared = typename RunParts<D>::Prepared;
  using SolverT = typename RunParts<D>::SolverT;
  using Outputs = typename RunParts<D>::Outputs;
  Runner(Prepared& prepared, const RunOptions& options);
  RunResult run();

 private:
  void open_restart();
  void open_log();
  void start_solver();
  void start_moving_water();
  void resume();
  void run_stages();
  void enter_stage(std::size_t si);
  void run_stage(std::size_t si);
  bool step(const io::StageSpec& stage, std::size_t si);
  void write_due_outputs(std::size_t si, double t);
  void log_excluded_water();
  bool at_rest(const io::StageSpec& stage, double t) const;
  bool checkpoint_due(Clock::time_point now) const;
  void report_progress(const io::StageSpec& stage, double t, Clock::time_point now);
  bool stopped_early(const io::StageSpec& stage);
  void save_checkpoint();
  void on_instability(const solver::InstabilityError& e);
  RunResult finish();
  void warn_about_water(const RunFacts& facts);
  void write_last_state();
  void log_end(bool completed, double wall, double max_balance_error);
  // `dsdem run SCENARIO --set ... --restart CHECKPOINT`: the run continued as it was set up.
  std::string continue_command() const {
    return "dsdem run " + sc_.file + shell_sets(sc_.overrides) + " --restart " + checkpoint_path_.string();
  }

  Prepared& prepared_;
  const RunOptions& options_;
  const io::Scenario& sc_;
  const Clock::time_point wall_start_;
  int threads_ = 1;
  const fs::path out_;
  const fs::path checkpoint_path_;
  std::optional<io::CheckpointReader> checkpoint_;
  RunnerState state_;
  bool continue_files_ = false;
  bool resumed_ = false;
  std::size_t resume_stage_ = 0;
  // false: the checkpoint is a complete run's end state and resume_stage_ a stage added
  // to the scenario since, entered as a run going on would enter it.
  bool resume_inside_stage_ = false;
  std::shared_ptr<spdlog::sinks::basic_file_sink_mt> file_sink_;
  std::shared_ptr<spdlog::logger> log_;
  std::optional<SolverT> solver_;
  std::optional<Outputs> outputs_;
  bool tty_ = false;
  Clock::time_point loop_start_, last_progress_, last_checkpoint_;
  long steps_at_last_progress_ = 0, first_step_ = 0;
  double wall_before_ = 0.0;
  int stopped_by_ = 0;
  bool stopped_at_step_ = false;
  std::size_t excluded_logged_ = 0;  // water particles taken out so far whose exclusion was logged
};

template <int D>
Runner<D>::Runner(Prepared& prepared, const RunOptions& options)
    : prepared_(prepared),
      options_(options),
      sc_(prepared.scenario),
      wall_start_(Clock::now()),
      out_(options.output_dir),
      checkpoint_path_(out_ / "checkpoint.h5") {
  if (options.threads > 0) omp_set_num_threads(options.threads);
  threads_ = omp_get_max_threads();
}

template <int D>
RunResult Runner<D>::run() {
  check_output_dir(out_, prepared_, options_.write_fields);
  if constexpr (D == 2) keep_mesh(out_, prepared_);
  open_restart();
  open_log();
  start_solver();
  try {
    if (resumed_) resume();
    first_step_ = steps_at_last_progress_ = solver_->step_count();
    run_stages();
  } catch (const solver::InstabilityError& e) {
    on_instability(e);
    throw;
  }
  return finish();
}

// The checkpoint must come from this model and time step. Resuming in the checkpoint's
// own directory continues its files; elsewhere new files start at the checkpoint's time.
template <int D>
void Runner<D>::open_restart() {
  if (options_.restart_from.empty()) return;
  const fs::path ckpt(options_.restart_from);
  try {
    checkpoint_.emplace(ckpt);
    state_ = read_runner_state(*checkpoint_, prepared_);
  } catch (const io::ScenarioError&) {
    throw;
  } catch (const std::exception& e) {
    throw io::ScenarioError({fmt::format("--restart {}: {}", ckpt.string(), e.what())});
  }
  std::error_code ec;
  continue_files_ = fs::equivalent(fs::absolute(ckpt).parent_path(), out_, ec);
}

// Log: file always, terminal unless quiet.
template <int D>
void Runner<D>::open_log() {
  file_sink_ = std::make_shared<spdlog::sinks::basic_file_sink_mt>((out_ / "dsdem.log").string(), !continue_files_);
  std::vector<spdlog::sink_ptr> sinks{file_sink_};
  if (!options_.quiet) sinks.push_back(std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  log_ = std::make_shared<spdlog::logger>("dsdem", sinks.begin(), sinks.end());
  log_->set_pattern("[%H:%M:%S] %v");
  log_->flush_on(spdlog::level::info);

  const auto& model = prepared_.model;
  log_->info("dsdem {} ({}), {} threads", DSDEM_VERSION, DSDEM_GIT_COMMIT, threads_);
  if constexpr (D == 2) {
    for (const auto& line : prepared_.build_log)
      log_->log(static_cast<spdlog::level::level_enum>(line.level), "{}", line.text);
    log_->info("scenario {}: {} nodes, {} triangles, {} joints", sc_.file, model.nodes.size(), model.triangles.size(),
               model.joints.size());
  } else {
    log_->info("scenario {}: 3D continuum, {} nodes, {} tetrahedra", sc_.file, model.nodes.size(),
               model.tetrahedra.size());
  }
  log_->info("{}", time_step_log_line(prepared_));
}

template <int D>
void Runner<D>::start_solver() {
  solver_.emplace(prepared_.model);
  if constexpr (D == 2) {
    install_time_step_rule(*solver_, prepared_);
    // Stress and strain are needed by the field frames and the checkpoint only: computed
    // there (write_fields; Solver::save) instead of every step, and not kept in between.
    solver_->set_stress_on_demand(true);
    if (prepared_.moving_water) start_moving_water();
  }
  try {
    outputs_.emplace(prepared_, *solver_, out_, options_.write_fields, continue_files_ ? &state_ : nullptr,
                     checkpoint_ ? &state_ : nullptr);
  } catch (const io::HistoryResumeError& e) {  // the restart does not fit, as a checkpoint of another model
    throw io::ScenarioError({fmt::format("--restart {}: {}", options_.restart_from, e.what())});
  }
  state_.gauges.resize(prepared_.gauges.size());
  tty_ = !options_.quiet && isatty(STDERR_FILENO);
  loop_start_ = last_progress_ = last_checkpoint_ = Clock::now();
  wall_before_ = state_.wall_time_before;
  resumed_ = checkpoint_.has_value();
  resume_stage_ = state_.stage;
  resume_inside_stage_ = resumed_ && state_.stage_starts.size() > resume_stage_;
}

// The reservoir's water on the solver; settled first unless a checkpoint will set its state.
template <int D>
void Runner<D>::start_moving_water() {
  const MovingWaterLayout& w = *prepared_.moving_water;
  // A small body of water is not worth a thread team: its loops are shorter than a
  // barrier, and a partner thread descheduled on a busy machine stalls every one of them.
  constexpr std::size_t kParallelWaterParticles = 20000;
  const bool parallel = threads_ > 1 && w.fluid.size() + w.walls.size() >= kParallelWaterParticles;
  sph::Fluid fluid(w.parameters, w.fluid, w.walls, parallel);
  if (!checkpoint_ && sc_.reservoir.sph.settle > 0.0) {
    const double v = settle_moving_water(fluid, sc_.reservoir.sph.settle, w.depth);
    const double scale = std::sqrt(sc_.gravity.norm() * w.depth);
    log_->info("reservoir water settled for {} s ({} steps): largest speed {:.3g} m/s = {:.2g} sqrt(g H)",
               sc_.reservoir.sph.settle, fluid.steps(), v, v / scale);
  }
  solver_->set_moving_water(std::move(fluid), w.edges);
  if (!checkpoint_) log_excluded_water();  // from the settle
}

// Each stage's supports, viscous boundary and earthquake as the original run set them (at
// their own start times), then the saved state over them.
template <int D>
void Runner<D>::resume() {
  SolverT& solver = *solver_;
  for (std::size_t si = 0; si < state_.stage_starts.size(); ++si) {
    set_up_stage(solver, sc_.stages[si], prepared_, state_.stage_starts[si]);
    if (si == 0) solver.initialise();
  }
  solver.restore(*checkpoint_);
  checkpoint_.reset();
  if constexpr (D == 2)
    if (const sph::Fluid* fluid = solver.moving_water()) excluded_logged_ = fluid->excluded().size();  // logged before
  log_->info("restarted from {} at step {}, t = {:.6g} s, {} stage {} '{}'", options_.restart_from, solver.step_count(),
             solver.time(), resume_inside_stage_ ? "in" : "at the start of", resume_stage_ + 1,
             sc_.stages[resume_stage_].name);
  if (!continue_files_) {
    outputs_->write_fields();
    outputs_->write_history(static_cast<int>(resume_stage_));
  }
}

template <int D>
void Runner<D>::run_stages() {
  for (std::size_t si = state_.stage; si < sc_.stages.size(); ++si) {
    run_stage(si);
    if (stopped_early(sc_.stages[si])) break;
  }
}

template <int D>
void Runner<D>::enter_stage(std::size_t si) {
  SolverT& solver = *solver_;
  const io::StageSpec& stage = sc_.stages[si];
  set_up_stage(solver, stage, prepared_, solver.time());
  state_.stage = si;
  state_.stage_starts.push_back(solver.time());
  if (si == 0) {
    solver.initialise();
    outputs_->write_fields();
    outputs_->write_history(0);
    state_.next_field = sc_.output.field_interval;
    state_.next_history = sc_.output.history_interval;
  }
  state_.stage_end += stage.duration;
  state_.peak_kinetic = 0.0;
  if constexpr (D == 2)
    log_->info("stage {} '{}': {} s to t = {} s, alpha = {} 1/s, beta = {} s, joints {}", si + 1, stage.name,
               stage.duration, state_.stage_end, stage.damping.alpha, stage.damping.beta,
               stage.failure ? "may break" : "elastic (no failure)");
  else
    log_->info("stage {} '{}': {} s to t = {} s, alpha = {} 1/s, beta = {} s{}", si + 1, stage.name, stage.duration,
               state_.stage_end, stage.damping.alpha, stage.damping.beta, stage.earthquake ? ", earthquake" : "");
}

template <int D>
void Runner<D>::run_stage(std::size_t si) {
  if (!(resume_inside_stage_ && si == resume_stage_)) enter_stage(si);
  const io::StageSpec& stage = sc_.stages[si];
  // Stop within half a step of the stage end.
  while (solver_->time() < state_.stage_end - 0.5 * solver_->dt()) {
    if (options_.stop_signal && *options_.stop_signal) break;
    if (!step(stage, si)) break;
  }
}

// One step and what follows it. False: the stage ends here (at rest, or --stop-at-step).
template <int D>
bool Runner<D>::step(const io::StageSpec& stage, std::size_t si) {
  SolverT& solver = *solver_;
  solver.step();
  outputs_->update_gauge_stats(state_.gauges);
  const double t = solver.time();
  write_due_outputs(si, t);
  state_.peak_kinetic = std::max(state_.peak_kinetic, solver.kinetic_energy());
  if (at_rest(stage, t)) {
    log_->info("stage '{}' at rest at t = {:.4g} s (kinetic energy below {} of its peak)", stage.name, t,
               stage.stop_kinetic_ratio);
    return false;
  }
  const auto now = Clock::now();
  // Checkpoints after this step's output, so that the files and the checkpoint agree.
  if (checkpoint_due(now)) save_checkpoint();
  if (options_.stop_at_step > 0 && solver.step_count() >= options_.stop_at_step) {
    stopped_at_step_ = true;
    return false;
  }
  if (std::chrono::duration<double>(now - last_progress_).count() >= sc_.output.progress_interval)
    report_progress(stage, t, now);
  return true;
}

template <int D>
void Runner<D>::write_due_outputs(std::size_t si, double t) {
  const SolverT& solver = *solver_;
  if (t >= state_.next_history - 0.5 * solver.dt()) {
    outputs_->write_history(static_cast<int>(si));
    log_excluded_water();
    state_.next_history += sc_.output.history_interval;
    state_.max_balance_error = std::max(state_.max_balance_error, solver.energy().balance_error());
  }
  if (t >= state_.next_field - 0.5 * solver.dt()) {
    outputs_->write_fields();
    state_.next_field += sc_.output.field_interval;
  }
}

// The stage's kinetic energy fell below stop_kinetic_ratio of its peak (after its first 5 %).
template <int D>
bool Runner<D>::at_rest(const io::StageSpec& stage, double t) const {
  return stage.stop_kinetic_ratio > 0 && solver_->kinetic_energy() < stage.stop_kinetic_ratio * state_.peak_kinetic &&
         t > 0.05 * stage.duration + (state_.stage_end - stage.duration);
}

template <int D>
bool Runner<D>::checkpoint_due(Clock::time_point now) const {
  const auto& o = sc_.output;
  return (o.checkpoint_steps > 0 && solver_->step_count() % o.checkpoint_steps == 0) ||
         (o.checkpoint_interval > 0 &&
          std::chrono::duration<double>(now - last_checkpoint_).count() >= o.checkpoint_interval);
}

template <int D>
void Runner<D>::report_progress(const io::StageSpec& stage, double t, Clock::time_point now) {
  const SolverT& solver = *solver_;
  const double rate =
      (solver.step_count() - steps_at_last_progress_) / std::chrono::duration<double>(now - last_progress_).count();
  const double eta = (sc_.end_time() - t) / solver.dt() / rate;
  std::string line;
  if constexpr (D == 2)
    line = fmt::format(
        "[{}] t = {:.4g} / {:.4g} s  {:.0f} steps/s  ETA {}  dt {:.4g} s  broken joints {}  contacts {}  energy "
        "balance {:.2e}",
        stage.name, t, sc_.end_time(), rate, human_time(eta), solver.dt(), solver.broken_joints(),
        solver.active_contacts(), solver.energy().balance_error());
  else
    line = fmt::format("[{}] t = {:.4g} / {:.4g} s  {:.0f} steps/s  ETA {}  dt {:.4g} s  energy balance {:.2e}",
                       stage.name, t, sc_.end_time(), rate, human_time(eta), solver.dt(),
                       solver.energy().balance_error());
  if (tty_)
    fmt::print(stderr, "\r{:<100}", line);
  else if (!options_.quiet)
    fmt::print(stderr, "{}\n", line);
  file_sink_->log(spdlog::details::log_msg("dsdem", spdlog::level::info, line));
  file_sink_->flush();  // a direct sink call skips the logger's flush_on: `tail -f` must see it
  last_progress_ = now;
  steps_at_last_progress_ = solver.step_count();
}

// A signal or --stop-at-step ended the stage: a checkpoint to continue from.
template <int D>
bool Runner<D>::stopped_early(const io::StageSpec& stage) {
  const SolverT& solver = *solver_;
  if (options_.stop_signal && *options_.stop_signal) {
    stopped_by_ = static_cast<int>(*options_.stop_signal);
    if (tty_) fmt::print(stderr, "\n");
    log_->warn("run stopped by {} at step {}, t = {:.6g} s in stage '{}': writing a checkpoint and the last fields, "
               "history and summary",
               signal_name(stopped_by_), solver.step_count(), solver.time(), stage.name);
    save_checkpoint();
    return true;
  }
  if (stopped_at_step_) {
    if (tty_) fmt::print(stderr, "\n");
    log_->info("stopped at step {} (--stop-at-step), t = {:.6g} s in stage '{}': checkpoint written",
               solver.step_count(), solver.time(), stage.name);
    save_checkpoint();
    return true;
  }
  return false;
}

// The history on disk holds exactly the rows counted in the checkpoint: a resumed run
// keeps that many rows and appends after them. (Solver::save computes the stress it writes.)
template <int D>
void Runner<D>::save_checkpoint() {
  log_excluded_water();  // before the checkpoint marks them as logged for a restart
  outputs_->record_counts(state_);
  state_.time = solver_->time();
  state_.wall_time_before = wall_before_ + seconds_since(wall_start_);
  io::CheckpointWriter w(checkpoint_path_);
  solver_->save(w);
  write_runner_state(w, state_, prepared_);
  w.commit();
  last_checkpoint_ = Clock::now();
}

// Each water particle taken out of the water since the last call (sph::Fluid::excluded), the
// first twenty one by one.
template <int D>
void Runner<D>::log_excluded_water() {
  if constexpr (D == 3) return;  // no water in 3D yet
  else {
    const sph::Fluid* fluid = solver_->moving_water();
    if (!fluid) return;
    constexpr std::size_t kOneByOne = 20;
    const auto excluded = fluid->excluded();
    const double c0 = fluid->parameters().c0, limit = fluid->parameters().excluded_limit;
    const double settle = sc_.reservoir.sph.settle;  // the water's clock ran through its settle before step 0
    const std::size_t allowed = fluid->excluded_capacity();
    for (; excluded_logged_ < std::min(excluded.size(), kOneByOne); ++excluded_logged_) {
      const sph::Fluid::ExcludedParticle& x = excluded[excluded_logged_];
      const std::string when = x.time < settle ? fmt::format("in the settle, {:.6g} s before step 0", settle - x.time)
                                               : fmt::format("at t = {:.6g} s", x.time - settle);
      log_->warn("water particle {} taken out of the water {} at ({:.6g}, {:.6g}) m: {:.4g} m/s (c0 = {:.4g} m/s), "
                 "density {:.5g} kg/m^3; {} of the {} reservoir.sph.excluded_limit = {:.4g} allows (summary.json "
                 "moving_water.excluded)",
                 x.id, when, x.x, x.y, x.speed, c0, x.density, excluded_logged_ + 1, allowed, limit);
    }
    if (excluded.size() > excluded_logged_) {
      log_->warn("{} more water particles taken out of the water by t = {:.6g} s, {} of the {} allowed (summary.json "
                 "moving_water.excluded)",
                 excluded.size() - excluded_logged_, excluded.back().time - settle, excluded.size(), allowed);
      excluded_logged_ = excluded.size();
    }
  }
}

// The diagnosis first (it must survive whatever follows), then the last state.
template <int D>
void Runner<D>::on_instability(const solver::InstabilityError& e) {
  if (tty_) fmt::print(stderr, "\n");
  log_excluded_water();
  log_->error("run stopped: {}", e.what());
  if constexpr (D == 2)
    io::write_json_file(out_ / "diagnosis.json", make_diagnosis(e, *solver_, prepared_));
  else
    io::write_json_file(out_ / "diagnosis.json", make_diagnosis_3d(e, *solver_, prepared_));
  try {
    outputs_->write_fields();
    outputs_->write_history(-1);
    outputs_->close_history();
    if constexpr (D == 2) outputs_->write_crack_log();
  } catch (const std::exception& w) {
    log_->error("could not write the last state: {}", w.what());
  }
  log_->error("diagnosis in {}", (out_ / "diagnosis.json").string());
}

// The last state, unless just written.
template <int D>
void Runner<D>::write_last_state() {
  const SolverT& solver = *solver_;
  const double half_step = 0.5 * solver.dt();
  if (outputs_->field_frames() == 0 ||
      std::abs(state_.next_field - sc_.output.field_interval - solver.time()) > half_step)
    outputs_->write_fields();
  if (outputs_->history_rows() == 0 ||
      std::abs(state_.next_history - sc_.output.history_interval - solver.time()) > half_step)
    outputs_->write_history(static_cast<int>(std::min(state_.stage, sc_.stages.size() - 1)));
}

// What the moving water's measurements say the user should know (plane runs).
template <int D>
void Runner<D>::warn_about_water(const RunFacts& facts) {
  if (facts.water && facts.water->escaped_particles() > 0)
    log_->warn("{} water particles left the model's box: the reservoir leaks through a gap in the solid or over its "
               "edge (summary.json moving_water.escaped_particles)",
               facts.water->escaped_particles());
  if (facts.water && facts.water->particles_inside_solid() > 0)
    log_->warn("up to {} water particles were inside the solid's triangles at a history row: water that got through "
               "a wall, at corners of the wall layout or squeezed into closing gaps (summary.json "
               "moving_water.particles_inside_solid)",
               facts.water->particles_inside_solid());
  if (facts.water && facts.water->above_freeboard_particles() > 0)
    log_->warn("{} water particles rose above {} m, the top of the coupled bedrock faces (the level plus "
               "reservoir.sph.freeboard): there the rock carries no wall and the water may run through it; raise the "
               "freeboard (summary.json moving_water.above_freeboard_particles)",
               facts.water->above_freeboard_particles(), facts.water->coupled_top());
  if (facts.water)
    for (const auto& r : facts.water->runup())
      if (facts.water->at_last_row(r.peak))
        log_->warn("the run-up on '{}' was highest at the run's last row (t = {:.6g} s): the water may still have been "
                   "rising there, and a wave that has not reached the bank yet leaves only the water at rest; a longer "
                   "run would tell (summary.json moving_water.runup.{})",
                   r.name, r.peak.t, r.name);
  if (facts.water && prepared_.moving_water) warn_of_fast_water(*log_, *facts.water, prepared_.moving_water->parameters.c0);
}

template <int D>
RunResult Runner<D>::finish() {
  const SolverT& solver = *solver_;
  if (tty_) fmt::print(stderr, "\n");
  write_last_state();
  log_excluded_water();
  const bool completed = stopped_by_ == 0 && !stopped_at_step_;
  if (completed) {
    // The end state, for a later continuation with added stages.
    state_.stage = sc_.stages.size();
    save_checkpoint();
  }
  outputs_->close_history();
  const double max_balance_error = std::max(state_.max_balance_error, solver.energy().balance_error());

  const double wall = seconds_since(wall_start_);
  RunFacts facts;
  facts.threads = threads_;
  facts.wall_time_s = wall;
  facts.loop_time_s = seconds_since(loop_start_);
  facts.wall_time_before_s = wall_before_;
  facts.first_step = first_step_;
  if (resumed_) facts.restarted_from = options_.restart_from;
  facts.checkpoint = checkpoint_path_.string();
  facts.max_balance_error = max_balance_error;
  facts.completed = completed;
  facts.stopped_by = stopped_by_;
  facts.stopped_at_step = stopped_at_step_;
  nlohmann::ordered_json summary;
  if constexpr (D == 2) {
    facts.fragments = outputs_->fragments();
    facts.energy_unit = outputs_->energy_unit();
    facts.water = outputs_->water_watch();
    warn_about_water(facts);
    facts.slide_impact = outputs_->slide_impact();
    summary = make_summary(prepared_, solver, state_.gauges, facts);
    outputs_->write_crack_log();
  } else {
    summary = make_summary_3d(prepared_, solver, *outputs_, state_.gauges, facts);
  }
  io::write_json_file(out_ / "summary.json", summary);
  log_end(completed, wall, max_balance_error);
  spdlog::drop("dsdem");

  RunResult result;
  result.steps = solver.step_count();
  result.wall_time_s = wall;
  result.energy_balance_error = max_balance_error;
  result.summary_path = (out_ / "summary.json").string();
  result.stopped_by_signal = stopped_by_;
  result.stopped_at_step = stopped_at_step_;
  result.checkpoint_path = checkpoint_path_.string();
  result.continue_command = continue_command();
  return result;
}

template <int D>
void Runner<D>::log_end(bool completed, double wall, double max_balance_error) {
  const SolverT& solver = *solver_;
  if (!completed)
    log_->warn("stopped{}: {} steps in {}; last fields, history and summary in {}; continue with `{}`",
               stopped_by_ ? " by " + signal_name(stopped_by_) : " at step " + std::to_string(solver.step_count()),
               solver.step_count(), human_time(wall), out_.string(), continue_command());
  else
    log_->info("done: {} steps in {}, energy balance error {:.2e}; results in {}", solver.step_count(),
               human_time(wall), max_balance_error, out_.string());
  if constexpr (D == 3) return;  // a fixed step and the solver's own thread timing
  else {
    if (solver.has_time_step_rule() && solver.settings().dt != prepared_.dt)
      log_->info("time step grew from {:.4g} s to {:.4g} s as joints broke; now set by {}", prepared_.dt,
                 solver.settings().dt, step_control(solver, prepared_).controlled_by);
    // The timed thread choice (Solver::probe_parallel) fell back to one thread for a large
    // part of the run: say so, or a slow run on a busy machine is a mystery.
    const long steps_run = solver.step_count() - first_step_;
    if (threads_ > 1 && steps_run > 0 && solver.serial_steps_chosen() > steps_run / 10)
      log_->info("{} of the {} steps ({:.0f} %) ran on one thread: timing found the {} threads slower then "
                 "(other busy processes on the machine?)",
                 solver.serial_steps_chosen(), steps_run, 100.0 * solver.serial_steps_chosen() / steps_run, threads_);
  }
}

}  // namespace

RunResult run(PreparedRun& prepared, const RunOptions& options) { return Runner<2>(prepared, options).run(); }

RunResult run_3d(PreparedRun3& prepared, const RunOptions& options) { return Runner<3>(prepared, options).run(); }

}  // namespace dsdem::run
