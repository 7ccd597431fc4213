#include "run/outputs.hpp"
#include "run/water.hpp"
#include "run/water_watch.hpp"

#include <algorithm>
#include <limits>

#include <fmt/format.h>

#include "io/crack_output.hpp"
#include "io/vtu_writer.hpp"
#include "solver/fragments.hpp"

namespace dsdem::run {

namespace fs = std::filesystem;

ReactionGroups reaction_groups(const io::Scenario& sc, const Model& model) {
  ReactionGroups groups;
  for (const auto& stage : sc.stages)
    for (const auto& b : stage.boundaries) {
      if (b.type == io::BoundaryType::Free) continue;
      if (std::any_of(groups.begin(), groups.end(), [&](const auto& r) { return r.first == b.group; })) continue;
      groups.emplace_back(b.group, &model.groups[model.find_group(b.group)].nodes);
    }
  return groups;
}

std::vector<io::HistoryColumn> history_columns(const PreparedRun& prepared, const ReactionGroups& reactions) {
  const bool plane_strain = !prepared.model.plane_stress;
  const std::string energy_unit = plane_strain ? "J_per_m" : "J";
  std::vector<io::HistoryColumn> columns{{"time", "s"},
                                         {"step", ""},
                                         {"stage", ""},
                                         {"kinetic", energy_unit},
                                         {"strain", energy_unit},
                                         {"gravity_potential", energy_unit},
                                         {"external_work", energy_unit},
                                         {"damping_dissipated", energy_unit},
                                         {"joint_elastic", energy_unit},
                                         {"fracture_dissipated", energy_unit},
                                         {"energy_balance_error", ""},
                                         {"contact_elastic", energy_unit},
                                         {"friction_dissipated", energy_unit},
                                         {"contact_damping_dissipated", energy_unit},
                                         {"plastic_dissipated", energy_unit},
                                         {"verlet_kinetic_offset", energy_unit},
                                         {"broken_joints", ""},
                                         {"fragments", ""},
                                         {"contacts", ""}};
  if (has_water(prepared.scenario)) columns.push_back({"water_work", energy_unit});
  const std::string force_unit = plane_strain ? "N_per_m" : "N";
  if (prepared.moving_water) {
    columns.push_back({"moving_water_work", energy_unit});
    for (auto& c : WaterWatch::columns(prepared.scenario.reservoir.sph, energy_unit, force_unit)) columns.push_back(c);
  }
  for (const auto& [name, nodes] : reactions)
    for (const char* c : {"x", "y"}) columns.push_back({fmt::format("{}_reaction_{}", name, c), force_unit});
  for (const auto& g : prepared.gauges)
    for (const auto& [q, unit] : std::vector<std::pair<std::string, std::string>>{
             {"displacement", "m"}, {"velocity", "m_per_s"}, {"acceleration", "m_per_s2"}})
      for (const char* c : {"x", "y"}) columns.push_back({fmt::format("{}_{}_{}", g.name, q, c), unit});
  return columns;
}

namespace {

}  // namespace

// Frames after the checkpoint (in time or in number) are written again by the resumed run.
io::PvdSeries open_series(const fs::path& out, const std::string& name, const RunnerState* resume_from,
                          std::size_t frames) {
  return resume_from ? io::PvdSeries::resume(out / name, resume_from->time, frames) : io::PvdSeries(out / name);
}

RunOutputs::RunOutputs(const PreparedRun& prepared, solver::Solver& solver, const fs::path& out, bool write_fields,
                       const RunnerState* resume_from, const RunnerState* measured_from)
    : prepared_(prepared),
      model_(prepared.model),
      solver_(solver),
      out_(out),
      write_fields_(write_fields),
      has_joints_(prepared.model.joints.size() > 0),
      has_water_(has_water(prepared.scenario)),
      energy_unit_(prepared.model.plane_stress ? "J" : "J_per_m"),
      force_unit_(prepared.model.plane_stress ? "N" : "N_per_m"),
      reactions_(reaction_groups(prepared.scenario, prepared.model)) {
  auto columns = history_columns(prepared, reactions_);
  row_.resize(columns.size());
  if (resume_from)
    history_.emplace(out / "history.csv", std::move(columns), io::HistoryWriter::Resume{resume_from->history_rows});
  else
    history_.emplace(out / "history.csv", std::move(columns));
  fields_.emplace(open_series(out, "fields.pvd", resume_from, resume_from ? resume_from->fields_frames : 0));
  if (prepared.shore) {
    slide_watch_.emplace(*prepared.shore);
    if (measured_from) slide_watch_->restore(measured_from->slide_impact);
  }
  if (prepared.moving_water && solver.moving_water()) {
    water_watch_.emplace(prepared.scenario, *prepared.moving_water, prepared.model,
                         prepared.shore ? wave_direction(*prepared.shore) : 0);
    water_columns_ = WaterWatch::columns(prepared.scenario.reservoir.sph, energy_unit_, force_unit_).size();
    water_frames_.emplace(open_series(out, "water.pvd", resume_from, resume_from ? resume_from->water_frames : 0));
    if (measured_from) water_watch_->restore(measured_from->water_watch);
  }
  if (has_joints_) cracks_.emplace(open_series(out, "cracks.pvd", resume_from, resume_from ? resume_from->cracks_frames : 0));
  if (model_.contact.enabled && model_.contact.output)
    contacts_.emplace(open_series(out, "contacts.pvd", resume_from, resume_from ? resume_from->contacts_frames : 0));
}

void RunOutputs::write_history(int stage_index) {
  const auto& e = solver_.energy();
  std::size_t k = 0;
  row_[k++] = solver_.time();
  row_[k++] = static_cast<double>(solver_.step_count());
  row_[k++] = stage_index;
  row_[k++] = e.kinetic;
  row_[k++] = e.strain;
  row_[k++] = e.gravity_potential;
  row_[k++] = e.external_work;
  row_[k++] = e.damping_dissipated;
  row_[k++] = e.joint_elastic;
  row_[k++] = e.fracture_dissipated;
  row_[k++] = e.balance_error();
  row_[k++] = e.contact_elastic;
  row_[k++] = e.friction_dissipated;
  row_[k++] = e.contact_damping_dissipated;
  row_[k++] = e.plastic_dissipated;
  row_[k++] = e.verlet_kinetic_offset;
  row_[k++] = static_cast<double>(solver_.broken_joints());
  row_[k++] = solver::count_fragments(model_, fragment_label_);
  row_[k++] = static_cast<double>(solver_.active_contacts());
  if (has_water_) row_[k++] = e.water_work;
  if (water_watch_) {
    row_[k++] = e.moving_water_work;
    const double front = prepared_.shore ? slide_front(model_, *prepared_.shore) : std::numeric_limits<double>::quiet_NaN();
    // Water alone (no slide can enter it): the water at step 0, after its settle, is the water at
    // rest the still level and the readings at rest are taken from (docs/theory.md §12).
    const bool entered = slide_watch_ ? slide_watch_->impact().has_value() : water_watch_->observed();
    water_watch_->observe(*solver_.moving_water(), solver_.time(), std::span<double>(row_).subspan(k, water_columns_), front,
                          entered, model_);
    k += water_columns_;
  }
  for (const auto& [name, nodes] : reactions_) {
    const Vec2 r = solver_.reaction_on(*nodes);
    row_[k++] = r.x();
    row_[k++] = r.y();
  }
  for (const auto& g : prepared_.gauges) {
    const Vec2 u = solver::gauge_value(model_, g, model_.nodes.u), v = solver::gauge_value(model_, g, model_.nodes.v),
               a = solver::gauge_value(model_, g, model_.nodes.a);
    for (const Vec2& q : {u, v, a}) {
      row_[k++] = q.x();
      row_[k++] = q.y();
    }
  }
  history_->append(row_);
  if (slide_watch_) slide_watch_->observe(model_, solver_.time());
}

void RunOutputs::update_gauge_stats(std::vector<GaugeStats>& stats) const {
  update_gauge_peaks(stats, prepared_.gauges, model_, solver_.time());
}

void RunOutputs::write_fields() {
  if (!write_fields_) return;
  solver_.update_stress();  // on demand: computed for this frame, released after it
  const fs::path file = fields_->frame_path(fields_->size());
  io::VtuOptions vo;
  vo.time_s = solver_.time();
  // The fragment each triangle belongs to (as counted in the history), so that piece
  // sizes can be measured from the frames.
  io::FieldSet cell_extra;
  if (has_joints_) {
    solver::count_fragments(model_, fragment_label_);
    cell_extra.push_back(io::scalar_field("fragment", "", std::span<const std::int32_t>(fragment_label_)));
  }
  if (has_water_) {  // at the centroid; the stress field is the effective stress (docs/theory.md §8)
    pore_pressure_.resize(model_.triangles.size());
    for (std::size_t t = 0; t < pore_pressure_.size(); ++t) {
      const auto& c = model_.triangles.conn[t];
      pore_pressure_[t] = solver_.water().pressure(
          (model_.nodes.x(c[0]) + model_.nodes.x(c[1]) + model_.nodes.x(c[2])) / 3.0, model_.triangles.material[t]);
    }
    cell_extra.push_back(io::scalar_field("pore_pressure", "Pa", std::span<const double>(pore_pressure_)));
  }
  io::write_triangles_vtu(file, model_.nodes, model_.triangles, model_.materials, {}, cell_extra, vo);
  solver_.release_stress();  // not held between frames: 48 B per triangle
  fields_->add(solver_.time(), file);
  if (cracks_) {
    const fs::path cfile = cracks_->frame_path(cracks_->size());
    io::write_cracks_vtu(cfile, model_, solver_.time());
    cracks_->add(solver_.time(), cfile);
  }
  if (contacts_ && solver_.contact()) write_contact_frame();
  if (water_frames_) write_water_frame();
}

// The water particles: velocity, pressure, density (docs/theory.md §11).
void RunOutputs::write_water_frame() {
  const sph::FluidParticles& f = solver_.moving_water()->fluid();
  water_points_.resize(f.size());
  water_velocity_.resize(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    water_points_[i] = Vec2(f.x[i], f.y[i]);
    water_velocity_[i] = Vec2(f.vx[i], f.vy[i]);
  }
  const fs::path file = water_frames_->frame_path(water_frames_->size());
  io::VtuOptions o;
  o.time_s = solver_.time();
  io::write_points_vtu(file, water_points_,
                       {io::vector_field("velocity", "m_per_s", water_velocity_),
                        io::scalar_field("pressure", "Pa", std::span<const double>(f.p)),
                        io::scalar_field("density", "kg_per_m3", std::span<const double>(f.rho)),
                        io::scalar_field("particle_id", "", std::span<const std::int32_t>(f.id))},
                       o);
  water_frames_->add(solver_.time(), file);
}

void RunOutputs::write_contact_frame() {
  contact_points_.clear();
  contact_forces_.clear();
  contact_normal_force_.clear();
  contact_overlap_.clear();
  solver_.contact()->for_each_contact([&](const contact::ContactRecord& c) {
    contact_points_.push_back(c.point);
    contact_forces_.push_back(c.force);
    contact_normal_force_.push_back(c.fn);
    contact_overlap_.push_back(c.overlap);
  });
  const fs::path pfile = contacts_->frame_path(contacts_->size());
  io::VtuOptions po;
  po.time_s = solver_.time();
  io::write_points_vtu(pfile, contact_points_,
                       {io::vector_field("contact_force", force_unit_, contact_forces_),
                        io::scalar_field("normal_force", force_unit_, std::span<const double>(contact_normal_force_)),
                        io::scalar_field("overlap", "m", std::span<const double>(contact_overlap_))},
                       po);
  contacts_->add(solver_.time(), pfile);
}

int RunOutputs::fragments() { return solver::count_fragments(model_, fragment_label_); }

void RunOutputs::write_crack_log() const {
  if (has_joints_) io::write_crack_log_csv(out_ / "cracks.csv", model_);
}

void RunOutputs::record_counts(RunnerState& s) {
  history_->flush();
  s.history_rows = history_->rows_written();
  s.fields_frames = fields_->size();
  s.cracks_frames = cracks_ ? cracks_->size() : 0;
  s.contacts_frames = contacts_ ? contacts_->size() : 0;
  if (water_watch_) {
    s.water_frames = water_frames_->size();
    s.water_watch = water_watch_->state();
  }
  s.slide_impact = slide_impact();
}

}  // namespace dsdem::run
