#pragma once
// Runs a scenario end to end: mesh, model, stages, output, summary (DESIGN.md §10).
#include <csignal>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "io/scenario.hpp"
#include "model/model.hpp"
#include "seismic/accelerogram.hpp"
#include "solver/gauges.hpp"
#include "solver/solver.hpp"

namespace dsdem::solver {

struct RunOptions {
  std::string output_dir = "out";
  int threads = 0;          // 0 = all cores
  bool quiet = false;       // no progress lines on the terminal
  bool write_fields = true;
  // Set (to the signal number) by a SIGINT/SIGTERM handler: the run stops at the end of
  // the current step and writes its last fields, history and summary.
  const volatile std::sig_atomic_t* stop_signal = nullptr;
  // Continue from this checkpoint (OUT/checkpoint.h5 of an earlier run of the same
  // scenario). In the checkpoint's own directory the run continues its files; elsewhere
  // new files start at the checkpoint's time.
  std::string restart_from;
  // Stop cleanly after this step with a checkpoint (0: run to the end), e.g. to split a
  // long run into batch jobs.
  long stop_at_step = 0;
};

// Everything known before step 0: the model, its time step and what controls it.
struct PreparedRun {
  io::Scenario scenario;
  Model model;
  std::vector<Gauge> gauges;
  StableStep stable;
  double dt = 0.0;  // the first step, s
  // With scenario.adaptive_dt: the triangles' and contact springs' limit (the joints'
  // follow them as they break, Solver::set_time_step_rule), s.
  StableStep fixed_limit;
  long estimated_steps = 0;
  std::string mesh_file;  // the .msh the model came from (meshed from the .geo when one was given)
  // The .msh's bytes when prepare_run() meshed it into work_dir (empty otherwise): run()
  // writes them next to the results, so the caller may remove work_dir right after
  // preparing and a run killed later (SIGKILL, a job's time limit) leaves no scratch behind.
  std::string mesh_text;
  // Earthquake records resampled to dt (DESIGN.md §5), when the scenario has them; an
  // adaptive step only grows from dt, and the free field interpolates them at each step.
  std::optional<seismic::Accelerogram> quake_horizontal, quake_vertical;
  // What meshing and model building logged (penalty joint stiffnesses, contact
  // stiffness, ...): it happens before run() opens dsdem.log, so run() replays these
  // there and check_report() prints them. level: spdlog's level number.
  struct LogLine {
    int level = 2;
    std::string text;
  };
  std::vector<LogLine> build_log;
};

// Loads or generates one earthquake component and resamples it to dt.
seismic::Accelerogram load_motion(const io::MotionSpec& spec, double dt);

// Loads the mesh, builds and validates the model against the scenario (throws
// io::ScenarioError with file, line and key for every mismatch).
PreparedRun prepare_run(const io::Scenario& scenario, const std::string& work_dir);

// Prints the model summary, dt and its control, and an estimate of the run time
// measured on a few steps. Returns the text.
std::string check_report(PreparedRun& run);

struct RunResult {
  long steps = 0;
  double wall_time_s = 0.0;
  double energy_balance_error = 0.0;
  std::string summary_path;
  int stopped_by_signal = 0;  // the signal that stopped the run early, 0 if it ran to the end
  bool stopped_at_step = false;  // RunOptions::stop_at_step reached
  std::string checkpoint_path;   // the last checkpoint written
};

// Bytes of memory a run of this model needs (data structures per node, element, joint,
// plus contact buffers), and the bytes of output it will write. Estimates, for `check`.
std::size_t estimate_memory_bytes(const PreparedRun& run);
std::size_t estimate_output_bytes(const PreparedRun& run, bool write_fields = true);

// Warnings `check` prints when the run needs more memory than the machine has available
// (MemAvailable in /proc/meminfo) or longer than 24 h of wall time. Empty when fine.
std::vector<std::string> resource_warnings(std::size_t memory_bytes, std::size_t available_bytes,
                                           double wall_seconds);
// MemAvailable from /proc/meminfo in bytes; 0 when unknown.
std::size_t available_memory_bytes();

// Runs every stage and writes OUT/{fields.pvd, fields/, history.csv, summary.json, dsdem.log}.
RunResult run(PreparedRun& prepared, const RunOptions& options);

}  // namespace dsdem::solver
