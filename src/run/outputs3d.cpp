#include "run/outputs3d.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <utility>

#include "io/vtu_writer.hpp"
#include "run/outputs.hpp"

namespace dsdem::run {

namespace fs = std::filesystem;

namespace {

// history.csv's columns, in the order write_history fills them.
std::vector<io::HistoryColumn> history_columns_3d(const PreparedRun3& prepared) {
  std::vector<io::HistoryColumn> columns{{"time", "s"},
          {"step", ""},
          {"stage", ""},
          {"kinetic_energy", "J"},
          {"strain_energy", "J"},
          {"gravity_potential", "J"},
          {"external_work", "J"},
          {"damping_dissipated", "J"},
          {"plastic_dissipated", "J"},
          {"energy_balance_error", ""},
          {"max_displacement", "m"},
          {"max_speed", "m_per_s"}};
  for (const auto& g : prepared.gauges)
    for (const auto& [q, unit] : std::vector<std::pair<std::string, std::string>>{
             {"displacement", "m"}, {"velocity", "m_per_s"}, {"acceleration", "m_per_s2"}})
      for (const char* c : {"x", "y", "z"}) columns.push_back({fmt::format("{}_{}_{}", g.name, q, c), unit});
  return columns;
}

}  // namespace

RunOutputs3::RunOutputs3(const PreparedRun3& prepared, solver::Solver3& solver, const fs::path& out, bool write_fields,
                         const RunnerState* resume_from, const RunnerState* measured_from)
    : prepared_(prepared), model_(prepared.model), solver_(solver), write_fields_(write_fields) {
  auto columns = history_columns_3d(prepared);
  row_.resize(columns.size());
  if (resume_from)
    history_.emplace(out / "history.csv", std::move(columns), io::HistoryWriter::Resume{resume_from->history_rows});
  else
    history_.emplace(out / "history.csv", std::move(columns));
  fields_.emplace(open_series(out, "fields.pvd", resume_from, resume_from ? resume_from->fields_frames : 0));
  if (measured_from && measured_from->peak_displacement.size() == 2) {
    max_displacement_ = measured_from->peak_displacement[0];
    max_displacement_node_ = static_cast<Index>(measured_from->peak_displacement[1]);
  }
}

void RunOutputs3::write_history(int stage_index) {
  const auto& e = solver_.energy();
  const auto& n = model_.nodes;
  double umax = 0.0, vmax = 0.0;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const double u = n.u[i].norm();
    if (u > umax) umax = u;
    if (u > max_displacement_) {
      max_displacement_ = u;
      max_displacement_node_ = static_cast<Index>(i);
    }
    vmax = std::max(vmax, n.v[i].norm());
  }
  std::size_t k = 0;
  for (const double x : {solver_.time(), static_cast<double>(solver_.step_count()), static_cast<double>(stage_index),
                         e.kinetic, e.strain, e.gravity_potential, e.external_work, e.damping_dissipated,
                         e.plastic_dissipated, e.balance_error(), umax, vmax})
    row_[k++] = x;
  for (const auto& g : prepared_.gauges)
    for (const auto* field : {&n.u, &n.v, &n.a}) {
      const Vec3 q = solver::gauge_value(model_, g, *field);
      for (int d = 0; d < 3; ++d) row_[k++] = q[d];
    }
  history_->append(row_);
}

void RunOutputs3::update_gauge_stats(std::vector<GaugeStats>& stats) const {
  update_gauge_peaks(stats, prepared_.gauges, model_, solver_.time());
}

void RunOutputs3::write_fields() {
  if (!write_fields_) return;
  solver_.update_stress();
  const fs::path file = fields_->frame_path(fields_->size());
  io::write_tetrahedra_vtu(file, model_.nodes, model_.tetrahedra, model_.materials, {}, {},
                           {.time_s = solver_.time()});
  fields_->add(solver_.time(), file);
}

void RunOutputs3::record_counts(RunnerState& s) {
  history_->flush();
  s.history_rows = history_->rows_written();
  s.fields_frames = fields_->size();
  s.cracks_frames = 0;
  s.contacts_frames = 0;
  s.peak_displacement = {max_displacement_, static_cast<double>(max_displacement_node_)};
}

}  // namespace dsdem::run
