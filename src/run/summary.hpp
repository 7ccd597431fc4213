#pragma once
// OUT/summary.json, the record of a run (docs/user-guide.md), and OUT/diagnosis.json, what
// made a run unstable. Keys carry their units; ordered as written here.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "run/prepare.hpp"
#include "run/restart.hpp"
#include "run/run3d.hpp"
#include "run/water_watch.hpp"
#include "solver/solver.hpp"

namespace dsdem::run {

// What the summary needs besides the model, the solver and the gauges' peaks.
struct RunFacts {
  int threads = 1;
  double wall_time_s = 0.0;        // of this part of the run
  double loop_time_s = 0.0;        // of its step loop
  double wall_time_before_s = 0.0; // of the parts before a restart
  long first_step = 0;             // the step this part started from
  std::string restarted_from;      // the checkpoint, empty when run from the start
  std::string checkpoint;
  int fragments = 0;
  std::string energy_unit;
  double max_balance_error = 0.0;
  bool completed = false;
  int stopped_by = 0;              // signal number
  bool stopped_at_step = false;
  std::optional<SlideAtImpact> slide_impact;  // the slide's entry into the reservoir, if seen
  const WaterWatch* water = nullptr;          // the moving water's measurements, if any
};

nlohmann::ordered_json make_summary(const PreparedRun& prepared, const solver::Solver& solver,
                                    const std::vector<GaugeStats>& gauges, const RunFacts& facts);

nlohmann::ordered_json make_diagnosis(const solver::InstabilityError& e, const solver::Solver& solver,
                                      const PreparedRun& prepared);

// The same for a 3D run (run/run3d.cpp): the plane run's keys where they mean the same,
// "dimension": 3, energies in J, the largest displacement at a history row.
class RunOutputs3;
nlohmann::ordered_json make_summary_3d(const PreparedRun3& prepared, const solver::Solver3& solver,
                                       const RunOutputs3& outputs, const std::vector<GaugeStats>& gauges,
                                       const RunFacts& facts);
nlohmann::ordered_json make_diagnosis_3d(const solver::InstabilityError& e, const solver::Solver3& solver,
                                         const PreparedRun3& prepared);

// OUT/summary.json of a finished or stopped run, keys in file order. Throws
// std::runtime_error naming the file.
nlohmann::ordered_json read_summary(const std::filesystem::path& out_dir);

}  // namespace dsdem::run
