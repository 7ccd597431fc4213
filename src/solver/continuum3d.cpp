#include "solver/continuum3d.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "exec/deterministic_sums.hpp"
#include "law/registry.hpp"
#include "solver/integrator.hpp"
#include "solver/local_damping.hpp"
#include "solver/solver.hpp"

namespace dsdem::solver {

namespace {
constexpr std::size_t kNodeChunk = 4096;  // nodes per chunk of the node loops
}  // namespace

// On OpenMP above kParallelThreshold tetrahedra, checked by timing now and then (exec::Team):
// on a busy machine one thread can be many times faster; the bits are the same either way.
Solver3::Solver3(Model3& model)
    : model_(model), team_(model.tetrahedra.size() > kParallelThreshold, /*automatic=*/true) {
  const Tetrahedra& tet = model_.tetrahedra;
  const std::size_t nt = tet.size(), nn = model_.nodes.size();
  setup_laws();
  tet_force_.resize(nt);
  tet_energy_.assign(nt, 0.0);
  tet_damping_.clear();
  // Each node's (tetrahedron, corner) entries in tetrahedron order.
  node_tet_start_.assign(nn + 1, 0);
  for (const auto& c : tet.conn)
    for (const Index v : c) ++node_tet_start_[static_cast<std::size_t>(v) + 1];
  for (std::size_t i = 0; i < nn; ++i) node_tet_start_[i + 1] += node_tet_start_[i];
  node_tets_.resize(4 * nt);
  std::vector<Index> fill(node_tet_start_.begin(), node_tet_start_.end() - 1);
  for (std::size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) node_tets_[static_cast<std::size_t>(fill[tet.conn[t][k]]++)] = static_cast<Index>(4 * t + k);
}

void Solver3::setup_laws() {
  const auto& tet = model_.tetrahedra;
  laws_.assign(model_.materials.size(), {});
  for (std::size_t m = 0; m < model_.materials.size(); ++m) {
    const Material& mat = model_.materials[m];
    const law::LawDecl& decl = law::material_laws().get(mat.model);
    const fem::ElasticConstants elastic{mat.lambda(), mat.mu()};
    if (!decl.state.empty() && mat.params.size() != decl.params.size())
      throw std::invalid_argument(fmt::format("material '{}' ({}): {} parameters, expected {}", mat.name, mat.model,
                                              mat.params.size(), decl.params.size()));
    try {
      laws_[m].kernel = fem::make_bulk_law(decl, mat.params, elastic, false);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("material '{}': {}", mat.name, e.what()));
    }
    if (!laws_[m].kernel.runs_in_3d())
      throw std::invalid_argument(fmt::format("material '{}': the law '{}' runs in plane strain only, not on "
                                              "tetrahedra", mat.name, mat.model));
    laws_[m].dissipation = laws_[m].kernel.dissipation_3d();
    law_stride_ = std::max(law_stride_, laws_[m].kernel.state_size_3d());
  }
  any_law_state_ = law_stride_ > 0;
  law_start_.assign(law_stride_ * tet.size(), 0.0);
  law_end_.assign(law_stride_ * tet.size(), 0.0);
}

double Solver3::stable_time_step() const {
  const auto& n = model_.nodes;
  const auto& tet = model_.tetrahedra;
  double dt = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < tet.size(); ++t) {
    const auto& c = tet.conn[t];
    const double cp = model_.materials[static_cast<std::size_t>(tet.material[t])].cp();
    dt = std::min(dt, fem::tet_critical_time_step(n.x(c[0]), n.x(c[1]), n.x(c[2]), n.x(c[3]), cp, settings_.beta));
  }
  return dt;
}

void Solver3::set_settings(const StepSettings3& s) {
  if (!(s.dt >= 0.0) || !(s.safety > 0.0 && s.safety <= kMaxSafety3D))
    throw std::invalid_argument(
        fmt::format("Solver3: dt {} s and safety {} (dt >= 0, 0 < safety <= {})", s.dt, s.safety, kMaxSafety3D));
  settings_ = s;
  dt_ = s.dt > 0.0 ? s.dt : s.safety * stable_time_step();
  if (damping_on()) allocate_damping_buffers();
  if (s.beta > 0.0) tet_damping_.resize(model_.tetrahedra.size());
}

void Solver3::set_mass_damping(double alpha) {
  settings_.alpha = alpha;
  if (damping_on()) allocate_damping_buffers();
}

// Once on, the buffers stay: the last damped step's forces still do work in the next.
void Solver3::allocate_damping_buffers() {
  if (!damping_force_.empty()) return;
  const std::size_t nn = model_.nodes.size();
  damping_force_.assign(nn, Vec3::Zero());
  damping_force_prev_.assign(nn, Vec3::Zero());
  u_prev_ = model_.nodes.u;
}

std::size_t Solver3::node_chunks() const { return (model_.nodes.size() + kNodeChunk - 1) / kNodeChunk; }

void Solver3::initialise() {
  auto& n = model_.nodes;
  if (!(dt_ > 0.0)) set_settings(settings_);
  // The force sum at the current state: gravity, the tetrahedra, damping, the reactions.
  exec::parallel_for(team_, n.size(), [&](std::size_t i) { n.a[i] = n.m[i] * settings_.gravity; });
  for (auto& d : constraints_) d.u_prev = n.u[d.node][d.dir];
  if (any_law_state_) std::copy(law_end_.begin(), law_end_.end(), law_start_.begin());
  const double external = energy_.external_work;
  for (auto& bn : boundary_) bn.u_prev = n.u[bn.node];
  add_element_forces();
  add_boundary_forces();
  add_damping_forces();
  apply_constraints();
  energy_.external_work = external;  // no step taken: the supports have done no work yet
  exec::parallel_for(team_, n.size(),
                     [&](std::size_t i) { n.a[i] = n.m[i] > 0.0 ? Vec3(n.a[i] / n.m[i]) : Vec3(Vec3::Zero()); });
  // The damping forces at the current state become the first step's previous ones; no
  // step taken, so they have done no work.
  if (!u_prev_.empty()) u_prev_ = n.u;
  const double damping = energy_.damping_dissipated;
  update_energy();
  energy_.damping_dissipated = damping;
  double s = 0.0;
  for (std::size_t i = 0; i < n.size(); ++i) s += n.m[i] * n.a[i].squaredNorm();
  s_start_ = s;
  energy_.verlet_kinetic_offset = 0.0;
  energy_.initial_total = energy_.mechanical() + energy_.dissipated() - energy_.work_in();
}

// One step, phase by phase (docs/theory.md §1).
void Solver3::step() {
  begin_step();
  kick_drift_and_restart_forces();  // 1-2
  add_element_forces();             // 3
  add_boundary_forces();            // 6
  add_damping_forces();             // 7
  apply_constraints();
  finish_velocities();              // 8
  update_energy();
  check_stability();
  ++step_;
  team_.end_step(step_);
}

void Solver3::begin_step() {
  team_.begin_step();
  if (any_law_state_) std::swap(law_start_, law_end_);  // the last step's end state starts this one
  const auto& n = model_.nodes;
  for (auto& d : constraints_) d.u_prev = n.u[d.node][d.dir];
  for (auto& bn : boundary_) bn.u_prev = n.u[bn.node];
  kick_from_ = time_;
  time_ += dt_;
}

void Solver3::kick_drift_and_restart_forces() {
  const bool damped = !damping_force_.empty();
  const KickDriftD<3> k{dt_, settings_.gravity, kick_from_ + 0.5 * dt_, time_, damped ? u_prev_.data() : nullptr,
                        damped ? damping_force_.data() : nullptr};
  auto& n = model_.nodes;
  const std::size_t nn = n.size();
  exec::parallel_for(team_, node_chunks(), [&](std::size_t c) {
    kick_and_drift<3>(n, k, {}, c * kNodeChunk, std::min(nn, (c + 1) * kNodeChunk));
  });
  prescribe_drift(n, k, constraints_, 0, nn);
}

fem::TetResponse Solver3::respond(std::size_t t, bool cauchy, std::array<Vec3, 4>& damping, double* end) const {
  const auto& n = model_.nodes;
  const auto& tet = model_.tetrahedra;
  const auto& c = tet.conn[t];
  fem::TetInput in;
  for (int k = 0; k < 4; ++k) in.x[k] = n.X[c[k]] + n.u[c[k]];
  in.Dm_inv = tet.Dm_inv[t];
  in.volume0 = tet.volume0[t];
  in.S0 = tet.initial_stress(t);
  in.cauchy = cauchy;
  if (settings_.beta > 0.0) {
    for (int k = 0; k < 4; ++k) in.v[k] = n.v[c[k]];
    in.beta = settings_.beta;
  }
  fem::TetResponse r;
  const MaterialLaw& law = laws_[static_cast<std::size_t>(tet.material[t])];
  const double* start = any_law_state_ ? &law_start_[law_stride_ * t] : nullptr;
  fem::tet_response(law.kernel, in, start, end, r, damping);
  return r;
}

void Solver3::add_element_forces() {
  const std::size_t nt = model_.tetrahedra.size();
  const bool damping = settings_.beta > 0.0;
  std::atomic<bool> inverted{false};  // written only by a thread that finds one: no contention
  exec::parallel_for(team_, nt, [&](std::size_t t) {
    std::array<Vec3, 4> df;
    double* end = any_law_state_ ? &law_end_[law_stride_ * t] : nullptr;
    const fem::TetResponse r = respond(t, false, df, end);
    tet_force_[t] = r.force;
    if (damping) tet_damping_[t] = df;
    tet_energy_[t] = r.strain_energy;
    if (!(r.detF > 0.0)) inverted.store(true, std::memory_order_relaxed);
  });
  inverted_ = inverted.load();
  // Each node gathers its corners' forces in tetrahedron order.
  auto& sum = forces_.scatter();
  const Vec3* f = tet_force_.front().data();
  const Vec3* fd = damping ? tet_damping_.front().data() : nullptr;
  Vec3* damp = damping ? damping_force_.data() : nullptr;
  exec::parallel_for(team_, model_.nodes.size(), [&](std::size_t i) {
    Vec3 s = Vec3::Zero(), sd = Vec3::Zero();
    for (Index e = node_tet_start_[i]; e < node_tet_start_[i + 1]; ++e) {
      s += f[node_tets_[static_cast<std::size_t>(e)]];
      if (fd) sd += fd[node_tets_[static_cast<std::size_t>(e)]];
    }
    sum[i] += s;
    if (fd) {
      sum[i] += sd;
      damp[i] += sd;  // booked with drift_work in update_energy()
    }
  });
}

void Solver3::set_viscous_boundary(std::vector<boundary::BoundaryNode3> nodes,
                                   const std::vector<PrescribedDof>& previous_constraints) {
  attach_boundary_nodes(nodes, model_.nodes.u, previous_constraints);
  boundary_ = std::move(nodes);
  boundary_force_prev_.resize(boundary_.size());
  for (std::size_t k = 0; k < boundary_.size(); ++k) boundary_force_prev_[k] = boundary_[k].static_force;
}

void Solver3::set_earthquake(const seismic::Accelerogram* x, const seismic::Accelerogram* y,
                             const seismic::Accelerogram* z, double incident_factor, double start_time) {
  quake_ = {boundary::IncidentMotion{x, incident_factor}, boundary::IncidentMotion{y, incident_factor},
            boundary::IncidentMotion{z, incident_factor}};
  quake_start_ = start_time;
}

void Solver3::add_boundary_forces() {
  if (boundary_.empty()) return;
  auto& n = model_.nodes;
  const double tq = time_ - quake_start_;
  double work = 0.0;
  for (std::size_t k = 0; k < boundary_.size(); ++k) {
    const boundary::BoundaryNode3& bn = boundary_[k];
    const Index i = bn.node;
    Vec3 F = bn.static_force + boundary::viscous_spring_force_3d(bn.coef, bn.normal, Vec3(n.u[i] - bn.u_ref), n.v[i]);
    if (bn.free_field) {
      boundary::FreeFieldState3 ff;
      bool any = false;
      for (int d = 0; d < 3; ++d) {
        if (!quake_[static_cast<std::size_t>(d)].record) continue;
        const auto wave = d < 2 ? boundary::IncidentWave::SV : boundary::IncidentWave::P;
        ff += boundary::free_field_column_3d(wave, d, quake_[static_cast<std::size_t>(d)], bn.medium, bn.height, bn.H, tq);
        any = true;
      }
      if (any) F += boundary::free_field_input_force(bn.coef, bn.area, bn.normal, ff);
    }
    forces_.add_at(i, F);
    // Everything the boundary does (springs, dashpots, input) is booked as external work.
    work += drift_work(boundary_force_prev_[k], F, Vec3(n.u[i] - bn.u_prev));
    boundary_force_prev_[k] = F;
  }
  energy_.external_work += work;
}

void Solver3::add_damping_forces() {
  const double alpha = settings_.alpha;
  const double local = settings_.local_damping;
  const auto& n = model_.nodes;
  if (local > 0.0) {
    // On the force without the damping so far (the stiffness part is in the sum already).
    forces_.add_per_node(team_, [&](std::size_t i) {
      const Vec3 fd = local_damping_force(Vec3(forces_.at(i) - damping_force_[i]), n.v[i], local);
      damping_force_[i] += fd;  // booked with drift_work in update_energy()
      return fd;
    });
  }
  if (alpha <= 0.0) return;
  forces_.add_per_node(team_, [&](std::size_t i) {
    const Vec3 fd = -alpha * n.m[i] * n.v[i];
    damping_force_[i] += fd;
    return fd;
  });
}

void Solver3::apply_constraints() {
  add_reactions(model_.nodes, forces_, std::span(constraints_), time_, energy_.external_work);
}

void Solver3::finish_velocities() {
  auto& n = model_.nodes;
  const std::size_t nn = n.size();
  exec::parallel_for(team_, node_chunks(), [&](std::size_t c) {
    finish_kick<3>(n, dt_, time_, {}, c * kNodeChunk, std::min(nn, (c + 1) * kNodeChunk));
  });
  prescribe_velocity_end(n, time_, constraints_, 0, nn);
}

void Solver3::update_energy() {
  const auto& n = model_.nodes;
  const Vec3 g = settings_.gravity;
  const bool damped = !damping_force_.empty();
  const auto node_sums = exec::deterministic_sums<3>(
      n.size(),
      [&](std::size_t i) {
        return std::array<double, 3>{
            0.5 * n.m[i] * n.v[i].squaredNorm(), -n.m[i] * g.dot(n.u[i]),
            damped ? drift_work(damping_force_prev_[i], damping_force_[i], n.u[i] - u_prev_[i]) : 0.0};
      },
      scratch_, team_.parallel());
  energy_.kinetic = node_sums[0];
  energy_.gravity_potential = node_sums[1];
  energy_.damping_dissipated -= node_sums[2];
  const auto& tet = model_.tetrahedra;
  const auto tet_sums = exec::deterministic_sums<2>(
      tet.size(),
      [&](std::size_t t) {
        const int k = any_law_state_ ? laws_[static_cast<std::size_t>(tet.material[t])].dissipation : -1;
        return std::array<double, 2>{tet_energy_[t], k >= 0 ? tet.volume0[t] * law_end_[law_stride_ * t + k] : 0.0};
      },
      scratch_, team_.parallel());
  energy_.strain = tet_sums[0];
  energy_.plastic_dissipated = tet_sums[1];
  if (damped) std::swap(damping_force_prev_, damping_force_);
}

const EnergyLedger& Solver3::energy() const {
  // Velocity Verlet's kinetic offset dt^2/8 (S - S(0)), S = sum m |a|^2 (docs/theory.md §7).
  const auto& n = model_.nodes;
  double s = 0.0;
  for (std::size_t i = 0; i < n.size(); ++i) s += n.m[i] * n.a[i].squaredNorm();
  energy_.verlet_kinetic_offset = dt_ * dt_ / 8.0 * (s - s_start_);
  return energy_;
}

void Solver3::check_stability() const {
  const auto& n = model_.nodes;
  if (inverted_) {
    const auto& tet = model_.tetrahedra;
    for (std::size_t t = 0; t < tet.size(); ++t) {
      const auto& c = tet.conn[t];
      const Mat3 F = fem::deformation_gradient(n.x(c[0]), n.x(c[1]), n.x(c[2]), n.x(c[3]), tet.Dm_inv[t]);
      if (F.determinant() > 0.0) continue;
      const Vec3 p = (n.x(c[0]) + n.x(c[1]) + n.x(c[2]) + n.x(c[3])) / 4.0;
      throw InstabilityError::in_3d(fmt::format("tetrahedron {} inverted (det F = {:.3g}) at t = {:.6g} s, step {}, at "
                                         "({:.6g}, {:.6g}, {:.6g}) m: the step is too large or the mesh too distorted",
                                         t, F.determinant(), time_, step_, p.x(), p.y(), p.z()),
                             "inverted_element", static_cast<Index>(t), p, step_, time_);
    }
  }
  if (!std::isfinite(energy_.kinetic) || !std::isfinite(energy_.strain))
    throw InstabilityError::in_3d(fmt::format("the state is no longer finite at t = {:.6g} s, step {}", time_, step_),
                           "non_finite", kNoIndex, Vec3(Vec3::Zero()), step_, time_);
}

Vec3 Solver3::reaction_on(std::span<const Index> nodes) const {
  Vec3 r = Vec3::Zero();
  for (const auto& d : constraints_)
    if (std::binary_search(nodes.begin(), nodes.end(), d.node)) r[d.dir] += d.reaction_prev;
  return r;
}

void Solver3::update_stress() {
  auto& tet = model_.tetrahedra;
  tet.stress.resize(tet.size());
  tet.strain.resize(tet.size());
  std::vector<double> end(std::max<std::size_t>(law_stride_, 1));
  for (std::size_t t = 0; t < tet.size(); ++t) {
    std::array<Vec3, 4> df;
    const fem::TetResponse r = respond(t, true, df, end.data());
    tet.stress[t] = r.cauchy;
    tet.strain[t] = r.green;
  }
}

std::size_t Solver3::memory_bytes() const {
  auto b = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  const auto& n = model_.nodes;
  const auto& t = model_.tetrahedra;
  return b(n.X) + b(n.u) + b(n.v) + b(n.a) + b(n.m) + b(n.origin) + b(t.conn) + b(t.group) + b(t.material) +
         b(t.Dm_inv) + b(t.volume0) + b(t.stress) + b(t.strain) + b(t.stress0) + b(law_start_) + b(law_end_) +
         b(tet_force_) + b(tet_damping_) + b(tet_energy_) + b(node_tet_start_) + b(node_tets_) + b(damping_force_) +
         b(damping_force_prev_) + b(u_prev_) + b(scratch_) + b(constraints_);
}

}  // namespace dsdem::solver
