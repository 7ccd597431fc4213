#pragma once
// What a run writes as it goes (docs/user-guide.md): history.csv rows (time, energies, counts,
// reactions on driven groups, gauges), the field, crack and contact frame series, and the
// gauges' peaks for the summary.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/history_writer.hpp"
#include "io/pvd.hpp"
#include "run/prepare.hpp"
#include "run/restart.hpp"
#include "run/water_watch.hpp"
#include "solver/solver.hpp"

namespace dsdem::run {

// Groups that carry a prescribed motion in some stage (loading plates, supports), each
// once, in the order the stages name them: their reactions go into the history.
using ReactionGroups = std::vector<std::pair<std::string, const std::vector<Index>*>>;
ReactionGroups reaction_groups(const io::Scenario& sc, const Model& model);

// history.csv's columns, in the order RunOutputs::write_history fills them.
std::vector<io::HistoryColumn> history_columns(const PreparedRun& prepared, const ReactionGroups& reactions);

// A frame series in `out`: new, or with `resume_from` (a restart in the checkpoint's own
// folder) the first `frames` frames up to the checkpoint's time kept.
io::PvdSeries open_series(const std::filesystem::path& out, const std::string& name, const RunnerState* resume_from,
                          std::size_t frames);

class RunOutputs {
 public:
  // Opens history.csv and the frame series in `out`. With `resume_from` (a restart in the
  // checkpoint's own folder) the files keep the rows and frames up to the checkpoint. With
  // `measured_from` (any restart) the run's measurements carry on from the checkpoint: the
  // slide's entry into the water and the water's records (its still level, peaks, gauges),
  // which a restart in another folder needs as much (the wave is measured from that level).
  RunOutputs(const PreparedRun& prepared, solver::Solver& solver, const std::filesystem::path& out,
             bool write_fields, const RunnerState* resume_from, const RunnerState* measured_from);

  void write_history(int stage_index);
  // A field frame (with the fragment of each triangle), a crack frame and a contact frame.
  void write_fields();
  // Gauge peaks after a step.
  void update_gauge_stats(std::vector<GaugeStats>& stats) const;
  // cracks.csv, the log of every broken joint, when the model has joints.
  void write_crack_log() const;
  // Rows and frames so far into `s` (the history flushed first), for a checkpoint.
  void record_counts(RunnerState& s);
  void close_history() { history_->close(); }

  std::size_t history_rows() const { return history_->rows_written(); }
  std::size_t field_frames() const { return fields_->size(); }
  int fragments();  // solver::count_fragments with this object's scratch
  // The slide's entry into the reservoir, once seen at a history row (docs/theory.md §12).
  std::optional<SlideAtImpact> slide_impact() const { return slide_watch_ ? slide_watch_->impact() : std::nullopt; }
  const std::string& energy_unit() const { return energy_unit_; }
  // The moving water's measurements (with reservoir.sph).
  const WaterWatch* water_watch() const { return water_watch_ ? &*water_watch_ : nullptr; }

 private:
  void write_contact_frame();
  void write_water_frame();

  const PreparedRun& prepared_;
  const Model& model_;
  solver::Solver& solver_;
  std::filesystem::path out_;
  bool write_fields_ = true;
  bool has_joints_ = false;
  bool has_water_ = false;
  std::optional<SlideImpactWatch> slide_watch_;  // with a reservoir  // some stage has water: a water_work column and a pore-pressure field
  std::string energy_unit_, force_unit_;
  ReactionGroups reactions_;
  std::optional<io::HistoryWriter> history_;
  std::optional<io::PvdSeries> fields_, cracks_, contacts_, water_frames_;
  std::optional<WaterWatch> water_watch_;
  std::size_t water_columns_ = 0;
  std::vector<Vec2> water_points_, water_velocity_;
  std::vector<double> row_;
  std::vector<Index> fragment_label_;
  std::vector<double> pore_pressure_;  // Pa per triangle, for a frame
  std::vector<Vec2> contact_points_, contact_forces_;
  std::vector<double> contact_normal_force_, contact_overlap_;
};

}  // namespace dsdem::run
