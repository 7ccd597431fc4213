#pragma once
// Runs a scenario end to end: mesh, model, stages, output, summary (DESIGN.md §10).
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
};

// Everything known before step 0: the model, its time step and what controls it.
struct PreparedRun {
  io::Scenario scenario;
  Model model;
  std::vector<Gauge> gauges;
  StableStep stable;
  double dt = 0.0;
  long estimated_steps = 0;
  std::string mesh_file;  // the .msh the model came from (meshed from the .geo when one was given)
  // Earthquake records resampled to dt (DESIGN.md §5), when the scenario has them.
  std::optional<seismic::Accelerogram> quake_horizontal, quake_vertical;
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
};

// Runs every stage and writes OUT/{fields.pvd, fields/, history.csv, summary.json, dsdem.log}.
RunResult run(PreparedRun& prepared, const RunOptions& options);

}  // namespace dsdem::solver
