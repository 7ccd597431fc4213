// Saving and restoring the 3D solver's state: everything a step reads, so a restarted run
// continues bit-identically (docs/theory.md §1 step 9, §14).
#include <fmt/format.h>

#include <algorithm>

#include "solver/checkpoint_arrays.hpp"
#include "solver/continuum3d.hpp"

namespace dsdem::solver {

void Solver3::save(io::CheckpointWriter& out) const {
  const auto& n = model_.nodes;
  out.put_int("dimension", 3);
  out.put("time", time_);
  out.put_int("step", step_);
  const EnergyLedger& e = energy_;
  out.put("energy", std::vector<double>{e.kinetic, e.strain, e.gravity_potential, e.external_work,
                                        e.damping_dissipated, e.plastic_dissipated, e.initial_total, s_start_});
  out.put("nodes/u", flatten_vectors(n.u));
  out.put("nodes/v", flatten_vectors(n.v));
  out.put("nodes/a", flatten_vectors(n.a));
  // Undamped, the solver holds no per-node damping buffers: zeros keep the file's layout.
  const bool damped = !damping_force_.empty();
  const std::vector<Vec3> zeros(damped ? 0 : n.size(), Vec3::Zero());
  out.put("nodes/u_prev", flatten_vectors(damped ? u_prev_ : zeros));
  out.put("nodes/damping_force_prev", flatten_vectors(damped ? damping_force_prev_ : zeros));
  // The laws' state at the end of the last step (the next step's start).
  out.put_int("tetrahedra/law_stride", static_cast<std::int64_t>(law_stride_));
  if (any_law_state_) out.put("tetrahedra/law_state", law_end_);
  std::vector<double> reactions(constraints_.size());
  for (std::size_t k = 0; k < constraints_.size(); ++k) reactions[k] = constraints_[k].reaction_prev;
  out.put("constraints/reaction_prev", reactions);
  std::vector<Vec3> u_ref(boundary_.size()), f_static(boundary_.size());
  for (std::size_t k = 0; k < boundary_.size(); ++k) {
    u_ref[k] = boundary_[k].u_ref;
    f_static[k] = boundary_[k].static_force;
  }
  out.put("boundary/u_ref", flatten_vectors(u_ref));
  out.put("boundary/static_force", flatten_vectors(f_static));
  out.put("boundary/force_prev", flatten_vectors(boundary_force_prev_));
  out.put("earthquake_start", quake_start_);
}

void Solver3::restore(const io::CheckpointReader& in) {
  const auto& n0 = model_.nodes;
  if (!in.has("dimension") || in.integer("dimension") != 3)
    throw std::runtime_error("checkpoint of a plane model ('dimension' is not 3): it belongs to another model");
  const auto stride = in.integer("tetrahedra/law_stride");
  if (stride != static_cast<std::int64_t>(law_stride_))
    throw std::runtime_error(fmt::format("checkpoint 'tetrahedra/law_stride' is {}, this model's laws keep {} values "
                                         "per tetrahedron: it belongs to a model with other laws",
                                         stride, law_stride_));
  // Every size is checked before anything changes: a refused file leaves the solver as it was.
  check_size("nodes/u", in.doubles("nodes/u").size(), 3 * n0.size());
  check_size("constraints/reaction_prev", in.doubles("constraints/reaction_prev").size(), constraints_.size());
  check_size("boundary/u_ref", in.doubles("boundary/u_ref").size(), 3 * boundary_.size());
  if (any_law_state_) check_size("tetrahedra/law_state", in.doubles("tetrahedra/law_state").size(), law_end_.size());
  const auto e = in.doubles("energy");
  check_size("energy", e.size(), 8);

  auto& n = model_.nodes;
  time_ = in.scalar("time");
  kick_from_ = time_;
  step_ = in.integer("step");
  energy_.kinetic = e[0];
  energy_.strain = e[1];
  energy_.gravity_potential = e[2];
  energy_.external_work = e[3];
  energy_.damping_dissipated = e[4];
  energy_.plastic_dissipated = e[5];
  energy_.initial_total = e[6];
  s_start_ = e[7];
  read_vectors(in, "nodes/u", n.u);
  read_vectors(in, "nodes/v", n.v);
  read_vectors(in, "nodes/a", n.a);
  {
    // The last step's damping forces do work in the next (its drift): the buffers are
    // needed when any is non-zero, even if this stage is undamped.
    std::vector<Vec3> u_prev(n.size()), df_prev(n.size());
    read_vectors(in, "nodes/u_prev", u_prev);
    read_vectors(in, "nodes/damping_force_prev", df_prev);
    if (std::any_of(df_prev.begin(), df_prev.end(), [](const Vec3& f) { return !f.isZero(0.0); }))
      allocate_damping_buffers();
    if (!damping_force_.empty()) {
      u_prev_ = std::move(u_prev);
      damping_force_prev_ = std::move(df_prev);
    }
  }
  if (any_law_state_) {
    law_end_ = in.doubles("tetrahedra/law_state");
    law_start_ = law_end_;
  }
  const auto reactions = in.doubles("constraints/reaction_prev");
  for (std::size_t k = 0; k < constraints_.size(); ++k) constraints_[k].reaction_prev = reactions[k];
  std::vector<Vec3> u_ref(boundary_.size()), f_static(boundary_.size());
  read_vectors(in, "boundary/u_ref", u_ref);
  read_vectors(in, "boundary/static_force", f_static);
  read_vectors(in, "boundary/force_prev", boundary_force_prev_);
  for (std::size_t k = 0; k < boundary_.size(); ++k) {
    boundary_[k].u_ref = u_ref[k];
    boundary_[k].static_force = f_static[k];
  }
  quake_start_ = in.scalar("earthquake_start");
}

}  // namespace dsdem::solver
