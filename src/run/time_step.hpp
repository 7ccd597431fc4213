#pragma once
// Where the runner takes its time step from: the prepared first step and its limits, the
// solver's rule that follows the joints as they break, and what controls the step now.
// Kept together so that the owner of the time step can be changed in one place.
#include <string>

#include "run/prepare.hpp"
#include "solver/solver.hpp"

namespace dsdem::run {

// run.stable, run.fixed_limit and run.dt from the model and the scenario's time settings
// (throws io::ScenarioError when time.dt exceeds the stable step).
void choose_time_step(PreparedRun& run);

// Hands the adaptive rule (time.adaptive) to the solver.
void install_time_step_rule(solver::Solver& solver, const PreparedRun& run);

// The log's line on the time step: its value, what controls it and how it may grow.
std::string time_step_log_line(const PreparedRun& run);

// What sets the current step (critical value, before the safety factor).
solver::StableStep step_control(const solver::Solver& solver, const PreparedRun& run);

}  // namespace dsdem::run
