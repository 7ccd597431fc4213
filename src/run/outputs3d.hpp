#pragma once
// What a 3D run writes as it goes (docs/user-guide.md, "Three dimensions"): history.csv rows
// (time, step, stage, energies in J, the largest displacement and speed) and the field
// frames (VTU tetrahedra in a PVD series), resumable from a checkpoint as the plane run's.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

#include "io/history_writer.hpp"
#include "io/pvd.hpp"
#include "run/restart.hpp"
#include "run/run3d.hpp"

namespace dsdem::run {

class RunOutputs3 {
 public:
  // Opens history.csv and fields.pvd in `out`; with `resume_from` (a restart in the
  // checkpoint's own folder) they keep the rows and frames up to the checkpoint. With
  // `measured_from` (any restart) the peak displacement carries on from the checkpoint.
  RunOutputs3(const PreparedRun3& prepared, solver::Solver3& solver, const std::filesystem::path& out,
              bool write_fields, const RunnerState* resume_from, const RunnerState* measured_from);
  void write_history(int stage_index);
  void write_fields();
  // Gauge peaks after a step.
  void update_gauge_stats(std::vector<GaugeStats>& stats) const;
  // Rows, frames and the peak so far into `s` (the history flushed first), for a checkpoint.
  void record_counts(RunnerState& s);
  void close_history() { history_->close(); }
  std::size_t history_rows() const { return history_->rows_written(); }
  std::size_t field_frames() const { return fields_->size(); }
  // The largest displacement at a history row so far, m, and its node (kNoIndex: none yet).
  double max_displacement() const { return max_displacement_; }
  Index max_displacement_node() const { return max_displacement_node_; }

 private:
  const PreparedRun3& prepared_;
  const Model3& model_;
  solver::Solver3& solver_;
  bool write_fields_ = true;
  std::optional<io::HistoryWriter> history_;
  std::optional<io::PvdSeries> fields_;
  std::vector<double> row_;
  double max_displacement_ = 0.0;
  Index max_displacement_node_ = kNoIndex;
};

}  // namespace dsdem::run
