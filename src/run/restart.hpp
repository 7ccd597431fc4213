#pragma once
// The runner's part of a checkpoint: what it carries from step to step besides the
// solver's state, so that a restarted run writes what the uninterrupted one would.
#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

#include "io/checkpoint.hpp"
#include "solver/gauges.hpp"
#include "run/prepare.hpp"
#include "run/run3d.hpp"

namespace dsdem::run {

// Peaks of one gauge for the summary.
struct GaugeStats {
  double max_disp = 0.0, max_speed = 0.0, time_of_max_speed = 0.0;
};

// Each gauge's peaks after a step at `time`: a plane model's gauges or a 3D one's
// (solver/gauges.hpp: gauge_value interpolates in the element that holds the gauge).
template <class ModelT, class GaugeT>
void update_gauge_peaks(std::vector<GaugeStats>& stats, const std::vector<GaugeT>& gauges, const ModelT& model,
                        double time) {
  for (std::size_t gi = 0; gi < gauges.size(); ++gi) {
    const double d = solver::gauge_value(model, gauges[gi], model.nodes.u).norm();
    const double s = solver::gauge_value(model, gauges[gi], model.nodes.v).norm();
    stats[gi].max_disp = std::max(stats[gi].max_disp, d);
    if (s > stats[gi].max_speed) {
      stats[gi].max_speed = s;
      stats[gi].time_of_max_speed = time;
    }
  }
}

struct RunnerState {
  double time = 0.0;                  // s, of the checkpoint
  std::size_t stage = 0;              // stage running; stages.size() once all are done
  std::vector<double> stage_starts;   // s, start of each stage entered
  double stage_end = 0.0;             // s, end of the current stage
  double peak_kinetic = 0.0;          // in the current stage (stop_kinetic_ratio)
  double next_field = 0.0, next_history = 0.0;  // s
  double max_balance_error = 0.0;
  std::size_t history_rows = 0, fields_frames = 0, cracks_frames = 0, contacts_frames = 0;
  double wall_time_before = 0.0;      // s of wall time of the run's earlier parts
  std::vector<GaugeStats> gauges;
  std::optional<SlideAtImpact> slide_impact;  // once the slide has entered the reservoir
  // With moving water: its frames so far and its measurements' state (WaterWatch::state).
  std::size_t water_frames = 0;
  std::vector<double> water_watch;
  // A 3D run's largest displacement at a history row so far (m) and its node.
  std::vector<double> peak_displacement;
};

// A plane run (PreparedRun) or a 3D one (PreparedRun3).
template <class Prepared>
void write_runner_state(io::CheckpointWriter& w, const RunnerState& s, const Prepared& run);

// Reads the runner's part of a checkpoint and checks that it belongs to this model, time
// step and scenario (messages say what differs). Throws std::runtime_error.
template <class Prepared>
RunnerState read_runner_state(const io::CheckpointReader& in, const Prepared& run);

}  // namespace dsdem::run
