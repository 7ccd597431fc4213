#pragma once
// A scenario on a volume mesh (docs/theory.md §14): the 3D continuum prepared, checked and run
// through its stages with fields (VTU tetrahedra and PVD), history.csv and summary.json.
#include <optional>
#include <string>

#include "io/scenario.hpp"
#include "mesh/raw_mesh.hpp"
#include "model/model3d.hpp"
#include "run/runner.hpp"
#include "seismic/accelerogram.hpp"
#include "solver/continuum3d.hpp"
#include "solver/gauges.hpp"

namespace dsdem::run {

struct PreparedRun3 {
  io::Scenario scenario;
  Model3 model;
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);  // m/s^2
  std::vector<solver::Gauge3> gauges;  // output.gauges, located in the tetrahedra
  double stable_dt = 0.0;  // s: the smallest altitude over cp (docs/theory.md §2)
  Index controlling_tetrahedron = kNoIndex;  // the tetrahedron with that smallest step
  double dt = 0.0;         // s: the step of the run
  long estimated_steps = 0;
  std::string mesh_file;
  // The earthquake's components resampled to dt: SV along x and y (the horizontal record
  // split along its azimuth) and P along z.
  std::optional<seismic::Accelerogram> quake_x, quake_y, quake_z;
};

// Builds and validates the 3D model against the scenario: every key a 3D model does not
// take yet (joints, contact, water, gauges by coordinates, plane-strain keys) and every 2D
// form (gravity or a scattering centre of two components) refused with file, line and key
// (io::ScenarioError, all problems at once).
PreparedRun3 prepare_run_3d(const io::Scenario& scenario, const RawMesh3& mesh);

// `dsdem check` of a 3D scenario: the model, its materials, dt and what controls it, the
// stages and the estimated cost.
std::string check_report_3d(const PreparedRun3& prepared);

// Sets the solver up for one stage (docs/theory.md §6, §14): the step with the stage's
// Rayleigh and local damping under `gravity`, its supports prescribed from start_time, its
// viscous-spring boundary (the supports of the stage before kept as loads) and its
// earthquake from start_time.
void apply_stage_3d(solver::Solver3& s, const io::StageSpec& stage, const PreparedRun3& p, const Vec3& gravity,
                    double start_time);

// Runs every stage and writes OUT/{fields.pvd, fields/, history.csv, summary.json,
// checkpoint.h5, dsdem.log} (run/runner.hpp: the plane run's runner, checkpoints and
// restart). A run that goes unstable writes its last fields and history and
// OUT/diagnosis.json, and throws solver::InstabilityError.
RunResult run_3d(PreparedRun3& prepared, const RunOptions& options);

// The parts of the runner that differ from the plane run's.
std::string time_step_log_line(const PreparedRun3& prepared);
std::size_t estimate_output_bytes(const PreparedRun3& prepared, bool write_fields = true);

}  // namespace dsdem::run
