// Saving and restoring the solver's state: everything a step reads, so a restarted run
// continues bit-identically (docs/theory.md §1 step 9; docs/user-guide.md).
#include <fmt/format.h>

#include "solver/checkpoint_arrays.hpp"
#include "solver/solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

namespace dsdem::solver {

namespace {

// Values saved per joint end point (JointPointState); a field added there must be added here.
constexpr int kJointStateWidth = 6;
static_assert(sizeof(JointPointState) == kJointStateWidth * sizeof(double),
              "JointPointState changed: update the checkpoint's joint state");

std::vector<double> vec2s(const std::vector<Vec2>& v) { return flatten_vectors(v); }
std::vector<double> vec3s(const std::vector<Vec3>& v) { return flatten_vectors(v); }
void read_vec2s(const io::CheckpointReader& in, const std::string& name, std::vector<Vec2>& v) { read_vectors(in, name, v); }
void read_vec3s(const io::CheckpointReader& in, const std::string& name, std::vector<Vec3>& v) { read_vectors(in, name, v); }

// Law state (law/registry.hpp): one array per declared variable, under its own name, and
// their count. Nothing at all without state, so such files keep their old layout.
void save_state(io::CheckpointWriter& out, const std::string& prefix, const StateArrays& state) {
  if (state.empty()) return;
  out.put_int(prefix + "count", static_cast<std::int64_t>(state.columns()));
  for (std::size_t k = 0; k < state.columns(); ++k) out.put(prefix + state.names[k], state.values[k]);
}

void restore_state(const io::CheckpointReader& in, const std::string& prefix, StateArrays& state) {
  const std::int64_t saved = in.has(prefix + "count") ? in.integer(prefix + "count") : 0;
  if (saved != static_cast<std::int64_t>(state.columns()))
    throw std::runtime_error(fmt::format("checkpoint has {} law state arrays under '{}', the model's laws declare {}: "
                                         "it belongs to another model",
                                         saved, prefix, state.columns()));
  for (std::size_t k = 0; k < state.columns(); ++k) {
    const std::string name = prefix + state.names[k];
    if (!in.has(name))
      throw std::runtime_error(fmt::format("checkpoint has no '{}': it belongs to a model with other laws", name));
    const auto values = in.doubles(name);
    check_size(name, values.size(), state.values[k].size());
    std::copy(values.begin(), values.end(), state.values[k].begin());  // the arrays stay where they are
  }
}

// Moving (SPH) water: the particle arrays by name (sph/particles.hpp), and the fluid's
// parameters, which a restart must share for the same bits.
using FluidArray = std::vector<double> sph::FluidParticles::*;
using BoundaryArray = std::vector<double> sph::BoundaryParticles::*;
constexpr std::pair<const char*, FluidArray> kFluidArrays[] = {
    {"x", &sph::FluidParticles::x},       {"y", &sph::FluidParticles::y},   {"vx", &sph::FluidParticles::vx},
    {"vy", &sph::FluidParticles::vy},     {"rho", &sph::FluidParticles::rho}, {"p", &sph::FluidParticles::p},
    {"vol", &sph::FluidParticles::vol},   {"ax", &sph::FluidParticles::ax}, {"ay", &sph::FluidParticles::ay},
    {"drho", &sph::FluidParticles::drho}, {"gx", &sph::FluidParticles::gx}, {"gy", &sph::FluidParticles::gy}};
constexpr std::pair<const char*, BoundaryArray> kBoundaryArrays[] = {
    {"x", &sph::BoundaryParticles::x},       {"y", &sph::BoundaryParticles::y},
    {"vx", &sph::BoundaryParticles::vx},     {"vy", &sph::BoundaryParticles::vy},
    {"rho", &sph::BoundaryParticles::rho},   {"p", &sph::BoundaryParticles::p},
    {"drho", &sph::BoundaryParticles::drho}, {"nx", &sph::BoundaryParticles::nx},
    {"ny", &sph::BoundaryParticles::ny},     {"wall_distance", &sph::BoundaryParticles::wall_distance},
    {"s", &sph::BoundaryParticles::s}};

std::vector<double> fluid_parameters(const sph::FluidParameters& p) {
  return {p.rho0, p.dp, p.h_over_dp, p.c0, p.alpha, p.delta, static_cast<double>(p.diffusion), p.gravity.x(),
          p.gravity.y(), p.cfl, static_cast<double>(p.resort_interval), static_cast<double>(p.boundary)};
}
constexpr const char* kFluidParameterNames[] = {"rho0", "dp", "h_over_dp", "c0", "alpha", "delta", "diffusion",
                                                "gravity x", "gravity y", "cfl", "resort_interval", "boundary"};

template <class T>
std::vector<std::int64_t> int64s(const std::vector<T>& v) {
  return std::vector<std::int64_t>(v.begin(), v.end());
}

std::vector<double> read_doubles(const io::CheckpointReader& in, const std::string& name, std::size_t n) {
  if (!in.has(name)) throw std::runtime_error(fmt::format("checkpoint has no '{}': it belongs to another set-up", name));
  auto d = in.doubles(name);
  check_size(name, d.size(), n);
  return d;
}

}  // namespace

// The checkpoint in parts, each a group of the file's entries.
void Solver::save(io::CheckpointWriter& out) const {
  out.put("time", time_);
  out.put_int("step", step_);
  out.put_int("broken_joints", broken_joints_);
  const EnergyLedger& e = energy_;
  const std::vector<double> energies{e.kinetic, e.strain, e.gravity_potential, e.joint_elastic, e.contact_elastic,
                                     e.external_work, e.damping_dissipated, e.fracture_dissipated,
                                     e.friction_dissipated, e.initial_total, e.contact_damping_dissipated,
                                     verlet_offset_.closed, verlet_offset_.s_start, verlet_offset_.dt};
  out.put("energy", energies);
  if (water_.size() > 0) {  // the water's work so far and its last forces (their work's first half)
    out.put("water/work", energy_.water_work);
    std::vector<Vec2> f;
    f.reserve(3 * water_.size());
    for (const auto& t : water_.previous_forces()) f.insert(f.end(), t.begin(), t.end());
    out.put("water/force_prev", vec2s(f));
  }
  save_nodes(out);
  save_triangles(out);
  save_joints(out);
  save_supports(out);
  if (contact_) save_contact(out);
  if (moving_) save_moving_water(out);
}

void Solver::save_nodes(io::CheckpointWriter& out) const {
  const Nodes& n = model_.nodes;
  out.put("nodes/u", vec2s(n.u));
  out.put("nodes/v", vec2s(n.v));
  out.put("nodes/a", vec2s(n.a));
  // Undamped, the solver holds no per-node damping buffers: the file keeps its layout
  // with zeros (u_prev is rewritten by the next step's drift before any use).
  const std::vector<Vec2> zeros(damped() ? 0 : n.size(), Vec2::Zero());
  out.put("nodes/u_prev", vec2s(damped() ? u_prev_ : zeros));
  out.put("nodes/damping_force_prev", vec2s(damped() ? damping_force_prev_ : zeros));
}

void Solver::save_triangles(io::CheckpointWriter& out) const {
  const Triangles& tri = model_.triangles;
  // Stress and strain of the current state: the steps' own when they write them, else
  // computed here (the values update_stress() gives; the model holds no arrays then).
  if (stress_on_demand_) {
    std::vector<Vec3> stress, strain;
    compute_stress(stress, strain);
    out.put("triangles/stress", vec3s(stress));
    out.put("triangles/strain", vec3s(strain));
  } else {
    out.put("triangles/stress", vec3s(tri.stress));
    out.put("triangles/strain", vec3s(tri.strain));
  }
  // Initial stresses: zeros when the model holds none (the file layout stays the same).
  out.put("triangles/stress0", vec3s(tri.stress0.empty() ? std::vector<Vec3>(tri.size(), Vec3::Zero()) : tri.stress0));
  save_state(out, "triangles/state/", tri.state);
  // The laws' state at the last step's start (stress on demand, the next step).
  if (any_law_state_) out.put("triangles/plastic_start", law_start_);
}

void Solver::save_joints(io::CheckpointWriter& out) const {
  const Joints& J = model_.joints;
  // Joints (checkpoint version 2): per end point dn_max, s_max, damage, dn, ds, ss and
  // the mode it failed in; per joint broken; the break records.
  std::vector<double> js(J.size() * 2 * kJointStateWidth);
  std::vector<std::int64_t> modes(J.size() * 2), broken(J.size());
  for (std::size_t j = 0; j < J.size(); ++j) {
    for (int k = 0; k < 2; ++k) {
      const JointPointState& p = J.state[j][k];
      const double vals[kJointStateWidth] = {p.dn_max, p.s_max, p.damage, p.dn, p.ds, p.ss};
      for (int q = 0; q < kJointStateWidth; ++q) js[(j * 2 + k) * kJointStateWidth + q] = vals[q];
      modes[j * 2 + k] = static_cast<std::int64_t>(J.end_mode[j][k]);
    }
    broken[j] = J.broken[j] ? 1 : 0;
  }
  std::vector<std::int64_t> break_joint(J.breaks.size());
  std::vector<double> break_data(J.breaks.size() * 3);
  for (std::size_t b = 0; b < J.breaks.size(); ++b) {
    const BreakRecord& r = J.breaks[b];
    break_joint[b] = r.joint;
    break_data[3 * b] = r.time;
    break_data[3 * b + 1] = r.position.x();
    break_data[3 * b + 2] = r.position.y();
  }
  out.put("joints/state", js);
  out.put("joints/end_mode", modes);
  out.put("joints/broken", broken);
  out.put("joints/breaks/joint", break_joint);
  out.put("joints/breaks/data", break_data);
  save_state(out, "joints/law_state/", J.law_state);
}

void Solver::save_supports(io::CheckpointWriter& out) const {
  std::vector<double> reactions(constraints_.size());
  for (std::size_t k = 0; k < constraints_.size(); ++k) reactions[k] = constraints_[k].reaction_prev;
  out.put("constraints/reaction_prev", reactions);
  std::vector<Vec2> u_ref(boundary_.size()), f_static(boundary_.size());
  for (std::size_t k = 0; k < boundary_.size(); ++k) {
    u_ref[k] = boundary_[k].u_ref;
    f_static[k] = boundary_[k].static_force;
  }
  out.put("boundary/u_ref", vec2s(u_ref));
  out.put("boundary/static_force", vec2s(f_static));
  out.put("boundary/force_prev", vec2s(boundary_force_prev_));
  out.put("earthquake_start", quake_start_);
  // The energy-growth watch (check_stability) so a restarted run flags the same step.
  out.put_int("stability/energy_growth_steps", energy_growth_steps_);
  out.put("stability/created_prev", created_prev_);
}

void Solver::save_contact(io::CheckpointWriter& out) const {
  const auto& entries = contact_->history().entries();
  std::vector<std::int64_t> keys(entries.size() * 3);
  std::vector<double> ft(entries.size() * 2);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    keys[3 * k] = entries[k].key.i;
    keys[3 * k + 1] = entries[k].key.j;
    keys[3 * k + 2] = entries[k].key.feature;
    ft[2 * k] = entries[k].ft.x();
    ft[2 * k + 1] = entries[k].ft.y();
  }
  out.put("contact/keys", keys);
  out.put("contact/ft", ft);
  out.put("contact/last_elastic_energy", contact_->last_elastic_energy());
  out.put("contact/skin", contact_->skin());
  // The last step's dashpot forces: the next step books the second half of their work.
  const std::vector<contact::DashpotRecord> dashpots = contact_->dashpot_records();
  std::vector<std::int64_t> dkeys(dashpots.size() * 3);
  std::vector<double> dvals(dashpots.size() * 9);
  for (std::size_t k = 0; k < dashpots.size(); ++k) {
    const contact::DashpotRecord& r = dashpots[k];
    dkeys[3 * k] = r.key.i;
    dkeys[3 * k + 1] = r.key.j;
    dkeys[3 * k + 2] = r.key.feature;
    const double vals[9] = {r.Ni[0], r.Ni[1], r.Ni[2], r.Nj[0], r.Nj[1], r.Nj[2], r.normal.x(), r.normal.y(), r.dashpot_force};
    std::copy(vals, vals + 9, dvals.begin() + static_cast<std::ptrdiff_t>(9 * k));
  }
  out.put("contact/dashpot_keys", dkeys);
  out.put("contact/dashpot_records", dvals);
}

// Moving water: everything its next step reads (sph::Fluid::State, sph::SolidCoupling::State)
// and the solver's side of the coupling (the last forces and displacements whose work the
// next step completes, the water's energy when it was set, the work so far).
void Solver::save_moving_water(io::CheckpointWriter& out) const {
  const sph::Fluid::State f = moving_->fluid.state();
  const sph::SolidCoupling::State c = moving_->coupling.state();
  // The particle count the water was built with: the arrays hold it less the excluded.
  out.put("water_sph/counts", std::vector<std::int64_t>{static_cast<std::int64_t>(moving_->fluid.initial_size()),
                                                         static_cast<std::int64_t>(f.boundary.size()),
                                                         static_cast<std::int64_t>(c.x_last.size())});
  out.put("water_sph/parameters", fluid_parameters(moving_->fluid.parameters()));
  for (const auto& [name, a] : kFluidArrays) out.put(std::string("water_sph/fluid/") + name, f.fluid.*a);
  out.put("water_sph/fluid/id", int64s(f.fluid.id));
  for (const auto& [name, a] : kBoundaryArrays) out.put(std::string("water_sph/boundary/") + name, f.boundary.*a);
  out.put("water_sph/boundary/edge", int64s(f.boundary.edge));
  out.put("water_sph/masses", std::vector<double>{f.fluid.mass, f.boundary.mass});
  out.put("water_sph/clock", std::vector<double>{f.time, f.v_max, f.a_max, f.damping_rate});
  out.put("water_sph/boundary_work", f.boundary_work);
  out.put("water_sph/steps", std::vector<std::int64_t>{f.steps, f.record ? 1 : 0});
  out.put("water_sph/recorded_force_x", f.rec_fx);
  out.put("water_sph/recorded_force_y", f.rec_fy);
  out.put("water_sph/coupling/x_last", vec2s(c.x_last));
  out.put("water_sph/coupling/x_next", vec2s(c.x_next));
  out.put("water_sph/coupling/force", vec2s(c.force));
  out.put("water_sph/coupling/particle_sum", std::vector<double>{c.particle_sum.x(), c.particle_sum.y()});
  out.put("water_sph/force_prev", vec2s(moving_->force_prev));
  out.put("water_sph/u_prev", vec2s(moving_->u_prev));
  const sph::Fluid::Energy& e0 = moving_->start;
  out.put("water_sph/start_energy", std::vector<double>{e0.kinetic, e0.potential, e0.compression});
  out.put("water_sph/work", energy_.moving_water_work);
  out.put("water_sph/waiting", moving_->waiting);
  std::vector<std::int64_t> ids;
  std::vector<double> records;
  for (const sph::Fluid::ExcludedParticle& x : f.excluded) {
    ids.push_back(x.id);
    records.insert(records.end(), {x.time, x.x, x.y, x.speed, x.density, x.energy});
  }
  out.put("water_sph/excluded/id", ids);
  out.put("water_sph/excluded/records", records);
}

void Solver::restore(const io::CheckpointReader& in) {
  check_moving_water(in);
  time_ = in.scalar("time");
  step_ = in.integer("step");
  broken_joints_ = in.integer("broken_joints");
  const auto e = in.doubles("energy");
  // 10 values before contact damping had a term of its own (it was in friction then), 11
  // before the Verlet kinetic offset, 13 while it was booked every step (the offset and S
  // at the saved state). 14: the Verlet offset's closed segments, S at the open segment's
  // start and its dt (Solver::VerletOffset).
  if (e.size() != 10 && e.size() != 11 && e.size() != 13) check_size("energy", e.size(), 14);
  energy_ = {e[0], e[1], e[2], e[3], e[4], e[5], e[6], e[7], e[8], e[9], e.size() > 10 ? e[10] : 0.0};
  if (in.has("water/work")) {
    energy_.water_work = in.scalar("water/work");
    const auto f = in.doubles("water/force_prev");
    check_size("water/force_prev", f.size(), 6 * model_.triangles.size());
    std::vector<std::array<Vec2, 3>> prev(model_.triangles.size());
    for (std::size_t t = 0; t < prev.size(); ++t)
      for (int k = 0; k < 3; ++k) prev[t][k] = Vec2(f[6 * t + 2 * k], f[6 * t + 2 * k + 1]);
    water_.restore_previous_forces(std::move(prev));
  }
  restore_nodes(in);
  restore_triangles(in);
  restore_joints(in);
  restore_supports(in);
  if (contact_) restore_contact(in);
  if (moving_) restore_moving_water(in);
  // The restored joints set the step (the rule's walk starts over: a checkpoint of an
  // earlier state may have fewer joints broken than this solver has seen).
  time_step_.restart(model_, broken_joints_);
  settings_.dt = time_step_.dt();
  if (e.size() == 14) {
    verlet_offset_ = {e[11], e[12], e[13]};
  } else {  // an older file: the open segment starts at the restored state
    verlet_offset_ = {e.size() > 11 ? e[11] : 0.0, mass_accel2(), settings_.dt};
  }
  offset_settled_ = false;
}

void Solver::restore_nodes(const io::CheckpointReader& in) {
  Nodes& n = model_.nodes;
  read_vec2s(in, "nodes/u", n.u);
  read_vec2s(in, "nodes/v", n.v);
  read_vec2s(in, "nodes/a", n.a);
  {
    // The previous step's damping forces matter (the damping work of the next step) when
    // any is non-zero: then the buffers are needed even if this stage is undamped.
    std::vector<Vec2> u_prev(n.size()), df_prev(n.size());
    read_vec2s(in, "nodes/u_prev", u_prev);
    read_vec2s(in, "nodes/damping_force_prev", df_prev);
    const bool any = std::any_of(df_prev.begin(), df_prev.end(), [](const Vec2& f) { return f.x() != 0.0 || f.y() != 0.0; });
    if (any) allocate_damping_buffers();
    if (damped()) {
      u_prev_ = std::move(u_prev);
      damping_force_prev_ = std::move(df_prev);
    }
  }
}

void Solver::restore_triangles(const io::CheckpointReader& in) {
  Triangles& tri = model_.triangles;
  if (stress_on_demand_) {  // recomputed from the restored state when needed: only checked
    check_size("triangles/stress", in.doubles("triangles/stress").size(), 3 * tri.size());
    check_size("triangles/strain", in.doubles("triangles/strain").size(), 3 * tri.size());
  } else {
    read_vec3s(in, "triangles/stress", tri.stress);
    read_vec3s(in, "triangles/strain", tri.strain);
  }
  {
    std::vector<Vec3> s0(tri.size(), Vec3::Zero());
    read_vec3s(in, "triangles/stress0", s0);
    // Anything but +0 (even -0) is kept, so the kernel sees exactly the saved values.
    const bool any = std::any_of(s0.begin(), s0.end(), [](const Vec3& s) {
      return std::signbit(s[0]) || std::signbit(s[1]) || std::signbit(s[2]) || s[0] != 0.0 || s[1] != 0.0 || s[2] != 0.0;
    });
    if (any || !tri.stress0.empty()) tri.stress0 = std::move(s0);
  }
  restore_state(in, "triangles/state/", tri.state);
  if (any_law_state_) {
    const auto start = in.doubles("triangles/plastic_start");
    check_size("triangles/plastic_start", start.size(), law_start_.size());
    std::copy(start.begin(), start.end(), law_start_.begin());
    energy_.plastic_dissipated = law_dissipation_sum();
  }
}

void Solver::restore_joints(const io::CheckpointReader& in) {
  Joints& J = model_.joints;
  const auto js = in.doubles("joints/state");
  const auto modes = in.integers("joints/end_mode");
  const auto broken = in.integers("joints/broken");
  const auto break_joint = in.integers("joints/breaks/joint");
  const auto break_data = in.doubles("joints/breaks/data");
  check_size("joints/state", js.size(), 2 * kJointStateWidth * J.size());
  check_size("joints/end_mode", modes.size(), 2 * J.size());
  check_size("joints/broken", broken.size(), J.size());
  check_size("joints/breaks/data", break_data.size(), 3 * break_joint.size());
  for (std::size_t j = 0; j < J.size(); ++j) {
    for (int k = 0; k < 2; ++k) {
      JointPointState& p = J.state[j][k];
      const double* v = &js[(j * 2 + k) * kJointStateWidth];
      p = {v[0], v[1], v[2], v[3], v[4], v[5]};
      J.end_mode[j][k] = static_cast<BreakMode>(modes[j * 2 + k]);
    }
    J.broken[j] = broken[j] ? 1 : 0;
    // A broken joint's force slot is never written again: it must hold zeros.
    if (J.broken[j]) joint_buf_.force[j] = {Vec2::Zero(), Vec2::Zero()};
  }
  restore_state(in, "joints/law_state/", J.law_state);
  J.breaks.clear();  // keeps the capacity reserved for every joint
  for (std::size_t b = 0; b < break_joint.size(); ++b) {
    if (break_joint[b] < 0 || static_cast<std::size_t>(break_joint[b]) >= J.size())
      throw std::runtime_error(fmt::format("checkpoint 'joints/breaks/joint' names joint {}, the model has {}: it belongs to another model",
                                           break_joint[b], J.size()));
    J.breaks.push_back({static_cast<Index>(break_joint[b]), break_data[3 * b],
                        Vec2(break_data[3 * b + 1], break_data[3 * b + 2])});
  }
}

void Solver::restore_supports(const io::CheckpointReader& in) {
  const auto reactions = in.doubles("constraints/reaction_prev");
  check_size("constraints/reaction_prev", reactions.size(), constraints_.size());
  for (std::size_t k = 0; k < constraints_.size(); ++k) constraints_[k].reaction_prev = reactions[k];
  std::vector<Vec2> u_ref(boundary_.size()), f_static(boundary_.size());
  read_vec2s(in, "boundary/u_ref", u_ref);
  read_vec2s(in, "boundary/static_force", f_static);
  read_vec2s(in, "boundary/force_prev", boundary_force_prev_);
  for (std::size_t k = 0; k < boundary_.size(); ++k) {
    boundary_[k].u_ref = u_ref[k];
    boundary_[k].static_force = f_static[k];
  }
  quake_start_ = in.scalar("earthquake_start");
  if (in.has("stability/energy_growth_steps")) {
    energy_growth_steps_ = static_cast<int>(in.integer("stability/energy_growth_steps"));
    created_prev_ = in.scalar("stability/created_prev");
  }
}

void Solver::restore_contact(const io::CheckpointReader& in) {
  const Triangles& tri = model_.triangles;
  const auto keys = in.integers("contact/keys");
  const auto ft = in.doubles("contact/ft");
  std::vector<contact::ContactHistory::Entry> entries(keys.size() / 3);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    entries[k].key = {static_cast<Index>(keys[3 * k]), static_cast<Index>(keys[3 * k + 1]),
                      static_cast<std::uint8_t>(keys[3 * k + 2])};
    entries[k].ft = Vec2(ft[2 * k], ft[2 * k + 1]);
  }
  std::vector<contact::DashpotRecord> dashpots;
  if (in.has("contact/dashpot_keys")) {
    const auto dkeys = in.integers("contact/dashpot_keys");
    const auto dvals = in.doubles("contact/dashpot_records");
    check_size("contact/dashpot_records", dvals.size(), 3 * dkeys.size());
    dashpots.resize(dkeys.size() / 3);
    for (std::size_t k = 0; k < dashpots.size(); ++k) {
      contact::DashpotRecord& r = dashpots[k];
      const auto i = dkeys[3 * k], j = dkeys[3 * k + 1];
      if (i < 0 || j < 0 || static_cast<std::size_t>(std::max(i, j)) >= tri.size())
        throw std::runtime_error(fmt::format("checkpoint 'contact/dashpot_keys' names triangles {} and {}, the model has "
                                             "{}: it belongs to another model", i, j, tri.size()));
      r.key = {static_cast<Index>(i), static_cast<Index>(j), static_cast<std::uint8_t>(dkeys[3 * k + 2])};
      const double* v = &dvals[9 * k];
      r.Ni = Vec3(v[0], v[1], v[2]);
      r.Nj = Vec3(v[3], v[4], v[5]);
      r.normal = Vec2(v[6], v[7]);
      r.dashpot_force = v[8];
    }
  }
  contact_->restore(entries, in.scalar("contact/last_elastic_energy"), in.scalar("contact/skin"), std::move(dashpots));
}


// The moving water in the file and in this solver must be the same set-up: checked before
// anything is restored, so a refused file leaves the solver as it was.
void Solver::check_moving_water(const io::CheckpointReader& in) const {
  const bool in_file = in.has("water_sph/counts");
  if (in_file && !moving_)
    throw std::runtime_error("checkpoint has moving (SPH) water ('water_sph/counts'), this solver has none: it belongs "
                             "to another set-up");
  if (!in_file && moving_)
    throw std::runtime_error("checkpoint has no 'water_sph/counts': it was written without moving (SPH) water, this "
                             "solver has it");
  if (!moving_) return;
  const auto counts = in.integers("water_sph/counts");
  if (counts.size() != 3) check_size("water_sph/counts", counts.size(), 3);
  const std::int64_t want[3] = {static_cast<std::int64_t>(moving_->fluid.initial_size()),
                                static_cast<std::int64_t>(moving_->fluid.boundary().size()),
                                static_cast<std::int64_t>(moving_->coupling.nodes().size())};
  const char* what[3] = {"fluid particles", "boundary particles", "coupled nodes"};
  for (int k = 0; k < 3; ++k)
    if (counts[k] != want[k])
      throw std::runtime_error(fmt::format("checkpoint 'water_sph/counts' has {} {}, this solver's moving water {}: "
                                           "it belongs to another set-up",
                                           counts[k], what[k], want[k]));
  const auto steps = in.integers("water_sph/steps");
  check_size("water_sph/steps", steps.size(), 2);
  if (steps[1] == 0)  // the coupling reads the recorded forces of every sub-step
    throw std::runtime_error("checkpoint 'water_sph/steps': the water's boundary forces were not recorded, as a coupled "
                             "run records them: it belongs to another set-up");
  const auto saved = in.doubles("water_sph/parameters");
  const auto now = fluid_parameters(moving_->fluid.parameters());
  check_size("water_sph/parameters", saved.size(), now.size());
  for (std::size_t k = 0; k < now.size(); ++k)
    if (std::memcmp(&saved[k], &now[k], sizeof(double)) != 0)
      throw std::runtime_error(fmt::format("checkpoint 'water_sph/parameters' has {} = {}, this solver's moving water "
                                           "{}: it belongs to another set-up",
                                           kFluidParameterNames[k], saved[k], now[k]));
  // The particles the run took out of the water must fit this run's limit (a run stopped at
  // its limit continues with a higher one).
  if (in.has("water_sph/excluded/id")) {
    const sph::Fluid& f = moving_->fluid;
    const std::size_t taken = in.integers("water_sph/excluded/id").size();
    if (taken > f.excluded_capacity())
      throw std::runtime_error(fmt::format(
          "checkpoint 'water_sph/excluded/id': {} water particles were taken out of the water, "
          "reservoir.sph.excluded_limit = {:.4g} allows {} of its {}: set it to at least {:.4g} to continue",
          taken, f.parameters().excluded_limit, f.excluded_capacity(), f.initial_size(),
          (static_cast<double>(taken) + 0.5) / static_cast<double>(f.initial_size())));
  }
}

void Solver::restore_moving_water(const io::CheckpointReader& in) {
  const std::size_t nb = moving_->fluid.boundary().size();
  const std::size_t nn = moving_->coupling.nodes().size();
  sph::Fluid::State f;
  // The particles taken out of the water so far (none in a file from before they could be).
  if (in.has("water_sph/excluded/id")) {
    const auto ids = in.integers("water_sph/excluded/id");
    const auto records = read_doubles(in, "water_sph/excluded/records", 6 * ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const double* r = records.data() + 6 * k;
      f.excluded.push_back({static_cast<std::int32_t>(ids[k]), r[0], r[1], r[2], r[3], r[4], r[5]});
    }
  }
  if (f.excluded.size() > moving_->fluid.initial_size())
    throw std::runtime_error(fmt::format("checkpoint 'water_sph/excluded/id' has {} particles, the water {}",
                                         f.excluded.size(), moving_->fluid.initial_size()));
  const std::size_t nf = moving_->fluid.initial_size() - f.excluded.size();
  for (const auto& [name, a] : kFluidArrays) f.fluid.*a = read_doubles(in, std::string("water_sph/fluid/") + name, nf);
  {
    const auto id = in.integers("water_sph/fluid/id");
    check_size("water_sph/fluid/id", id.size(), nf);
    f.fluid.id.assign(id.begin(), id.end());
  }
  for (const auto& [name, a] : kBoundaryArrays)
    f.boundary.*a = read_doubles(in, std::string("water_sph/boundary/") + name, nb);
  {
    const auto edge = in.integers("water_sph/boundary/edge");
    check_size("water_sph/boundary/edge", edge.size(), nb);
    f.boundary.edge.assign(edge.begin(), edge.end());
    if (!std::equal(edge.begin(), edge.end(), moving_->fluid.boundary().edge.begin()))
      throw std::runtime_error("checkpoint 'water_sph/boundary/edge': the boundary particles ride other edges than "
                               "this solver's moving water: it belongs to another set-up");
  }
  const auto masses = read_doubles(in, "water_sph/masses", 2);
  f.fluid.mass = masses[0];
  f.boundary.mass = masses[1];
  const auto clock = read_doubles(in, "water_sph/clock", 4);
  f.time = clock[0];
  f.v_max = clock[1];
  f.a_max = clock[2];
  f.damping_rate = clock[3];
  // A checkpoint from before the walls' work was booked: it counts from the restart.
  f.boundary_work = in.has("water_sph/boundary_work") ? in.scalar("water_sph/boundary_work") : 0.0;
  const auto steps = in.integers("water_sph/steps");
  check_size("water_sph/steps", steps.size(), 2);
  f.steps = static_cast<long>(steps[0]);
  f.record = steps[1] != 0;
  f.rec_fx = read_doubles(in, "water_sph/recorded_force_x", nb);
  f.rec_fy = read_doubles(in, "water_sph/recorded_force_y", nb);
  sph::SolidCoupling::State c;
  c.x_last.resize(nn);
  c.x_next.resize(nn);
  c.force.resize(nn);
  read_vec2s(in, "water_sph/coupling/x_last", c.x_last);
  read_vec2s(in, "water_sph/coupling/x_next", c.x_next);
  read_vec2s(in, "water_sph/coupling/force", c.force);
  const auto sum = read_doubles(in, "water_sph/coupling/particle_sum", 2);
  c.particle_sum = Vec2(sum[0], sum[1]);
  read_vec2s(in, "water_sph/force_prev", moving_->force_prev);
  read_vec2s(in, "water_sph/u_prev", moving_->u_prev);
  const auto e0 = read_doubles(in, "water_sph/start_energy", 3);
  moving_->start = {e0[0], e0[1], e0[2]};
  energy_.moving_water_work = in.scalar("water_sph/work");
  moving_->waiting = in.scalar("water_sph/waiting");
  moving_->fluid.restore(f);
  moving_->coupling.restore(c);
  // The water's energy in the ledger, as the last step's update_energy() left it.
  const sph::Fluid::Energy e = moving_->fluid.energy();
  energy_.fluid_kinetic = e.kinetic;
  energy_.fluid_potential = e.potential - moving_->start.potential;
  energy_.fluid_compression = e.compression - moving_->start.compression;
  energy_.fluid_excluded = moving_->fluid.excluded_energy();
}

}  // namespace dsdem::solver
