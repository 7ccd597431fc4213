#include "run/time_step.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace dsdem::run {

void choose_time_step(PreparedRun& run) {
  const io::Scenario& scenario = run.scenario;
  double max_beta = 0.0;
  for (const auto& s : scenario.stages) max_beta = std::max(max_beta, s.damping.beta);
  run.stable = solver::stable_time_step(run.model, max_beta);
  run.fixed_limit = solver::triangle_step_limit(run.model, max_beta);
  if (solver::StableStep c = solver::contact_step_limit(run.model); c.dt < run.fixed_limit.dt)
    run.fixed_limit = std::move(c);
  run.dt = scenario.dt.value_or(scenario.safety * run.stable.dt);
  if (scenario.dt && *scenario.dt > run.stable.dt)
    throw io::ScenarioError({fmt::format("{}: time.dt: {} s exceeds the stable time step {:.4g} s set by {}",
                                         scenario.file, *scenario.dt, run.stable.dt, run.stable.controlled_by)});
}

void install_time_step_rule(solver::Solver& solver, const PreparedRun& run) {
  if (run.scenario.adaptive_dt) solver.set_time_step_rule(run.scenario.safety, run.fixed_limit.dt);
}

std::string time_step_log_line(const PreparedRun& run) {
  const io::Scenario& sc = run.scenario;
  return fmt::format("dt = {:.4g} s ({} x stable {:.4g} s, controlled by {}){}", run.dt, sc.dt ? 1.0 : sc.safety,
                     run.stable.dt, run.stable.controlled_by,
                     sc.adaptive_dt ? fmt::format("; adaptive: taken again as joints break, up to {:.4g} s",
                                                  sc.safety * run.fixed_limit.dt)
                                    : "");
}

solver::StableStep step_control(const solver::Solver& solver, const PreparedRun& run) {
  if (!solver.has_time_step_rule()) return run.stable;
  const solver::JointStepLimit* joint = solver.time_step_joint();
  return joint ? solver::describe_joint_limit(run.model, *joint) : run.fixed_limit;
}

}  // namespace dsdem::run
