#pragma once
// Everything a run needs before step 0: the model, its gauges, time step and earthquake
// records, validated against the scenario (docs/user-guide.md).
#include <optional>
#include <string>
#include <vector>

#include "io/scenario.hpp"
#include "run/moving_water.hpp"
#include "run/slide_impact.hpp"
#include "model/model.hpp"
#include "seismic/accelerogram.hpp"
#include "solver/gauges.hpp"
#include "solver/solver.hpp"

namespace dsdem::run {

// Everything known before step 0: the model, its time step and what controls it.
struct PreparedRun {
  io::Scenario scenario;
  Model model;
  std::vector<solver::Gauge> gauges;
  solver::StableStep stable;
  double dt = 0.0;  // the first step, s
  // With scenario.adaptive_dt: the triangles' and contact springs' limit (the joints'
  // follow them as they break, Solver::set_time_step_rule), s.
  solver::StableStep fixed_limit;
  long estimated_steps = 0;
  std::string mesh_file;  // the .msh the model came from (meshed from the .geo when one was given)
  // The .msh's bytes when prepare_run() meshed it into work_dir (empty otherwise): run()
  // writes them next to the results, so the caller may remove work_dir right after
  // preparing and a run killed later (SIGKILL, a job's time limit) leaves no scratch behind.
  std::string mesh_text;
  // Earthquake records resampled to dt (docs/theory.md §5), when the scenario has them; an
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
  // The reservoir's bank where the slide may enter it (scenario.reservoir).
  std::optional<Shore> shore;
  // The reservoir as moving water (scenario.reservoir.sph), laid out before step 0.
  std::optional<MovingWaterLayout> moving_water;
};

// Loads or generates one earthquake component and resamples it to dt.
seismic::Accelerogram load_motion(const io::MotionSpec& spec, double dt);

// Loads the mesh, builds and validates the model against the scenario (throws
// io::ScenarioError with file, line and key for every mismatch).
PreparedRun prepare_run(const io::Scenario& scenario, const std::string& work_dir);

}  // namespace dsdem::run
