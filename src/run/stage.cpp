#include "run/stage.hpp"
#include "run/water.hpp"

#include <vector>

namespace dsdem::run {

void apply_stage(solver::Solver& solver, const io::StageSpec& stage, const io::Scenario& sc, double dt,
                 double start_time, const PreparedRun* prepared) {
  solver::StepSettings s;
  s.gravity = sc.gravity;
  s.alpha = stage.damping.alpha;
  s.beta = stage.damping.beta;
  s.local_damping = stage.damping.local;
  s.dt = dt;
  s.failure = stage.failure;
  solver.set_settings(s);
  const std::vector<solver::PrescribedDof> previous = solver.constraints();
  solver.set_constraints(solver::build_constraints(solver.model(), stage.boundaries, start_time));
  solver.set_viscous_boundary(boundary::build_viscous_boundary(solver.model(), stage.boundaries), previous);
  if (stage.earthquake && prepared)
    solver.set_earthquake(prepared->quake_horizontal ? &*prepared->quake_horizontal : nullptr,
                          prepared->quake_vertical ? &*prepared->quake_vertical : nullptr,
                          sc.earthquake.incident_factor, start_time);
  else
    solver.set_earthquake(nullptr, nullptr, 0.5, 0.0);
  if (stage.water.present) {
    solver::WaterSetup w = water_setup(stage.water, solver.model(), sc.gravity);
    if (prepared && prepared->moving_water) {  // the moving water loads the faces over its span itself
      w.moving_x_min = prepared->moving_water->x_min;
      w.moving_x_max = prepared->moving_water->x_max;
    }
    solver.set_water(std::move(w));
  } else {
    solver.clear_water();
  }
}

}  // namespace dsdem::run
