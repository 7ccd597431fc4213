#pragma once
// A stage's settings handed to the solver (the stages of docs/theory.md §6).
#include "io/scenario.hpp"
#include "run/prepare.hpp"
#include "solver/solver.hpp"

namespace dsdem::run {

// Settings, supports, viscous boundary and earthquake of a stage that starts at
// `start_time` (prescribed motions and the earthquake's time zero are the stage start).
// Without `prepared` the stage runs without its earthquake.
void apply_stage(solver::Solver& solver, const io::StageSpec& stage, const io::Scenario& sc, double dt,
                 double start_time, const PreparedRun* prepared = nullptr);

}  // namespace dsdem::run
