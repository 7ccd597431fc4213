#include "solver/solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "exec/deterministic_sums.hpp"
#include "solver/local_damping.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace dsdem::solver {

Solver::Solver(Model& model)
    : model_(model),
      team_(model.triangles.size() > kParallelThreshold, /*automatic=*/true) {
  const std::size_t ne = model_.triangles.size();
  element_strain_energy_.assign(ne, 0.0);
  set_stress_on_demand(false);  // sizes the triangles' stress and strain
  for (const auto& m : model_.materials) elastic_.push_back({m.lambda(), m.mu()});
  setup_laws();
  joint_buf_.prepare(model_.joints, model_.joint_properties);
  scatter_.build(model_.triangles.conn, model_.joints.nodes, model_.joints.tri_a, model_.joints.tri_b,
                 model_.nodes.size());
  for (auto b : model_.joints.broken) broken_joints_ += b ? 1 : 0;
  if (model_.contact.enabled) {
    contact::ContactSettings cs;
    cs.skin = model_.contact.skin;
    cs.parallel = team_.parallel();
    contact_ = std::make_unique<contact::ContactForces>(cs);
    contact_params_.set_default(model_.contact.defaults);
    for (const auto& p : model_.contact.pairs) contact_params_.set(p.group_a, p.group_b, p.props);
  }
}

void Solver::set_water(WaterSetup w) { water_.set(model_, std::move(w)); }

void Solver::clear_water() { water_.clear(); }

double Solver::water_work_sum() {
  const auto sum = exec::deterministic_sums<1>(
      water_.size(), [&](std::size_t t) { return std::array<double, 1>{water_.work(t)}; }, reduction_scratch_,
      team_.parallel());
  if (!water_.has_water()) water_.clear();  // the forces of the last wet step are booked: done
  return sum[0];
}

void Solver::set_moving_water(sph::Fluid fluid, std::vector<sph::SolidEdge> edges) {
  const auto& n = model_.nodes;
  for (const auto& e : edges)
    if (e.a < 0 || e.b < 0 || static_cast<std::size_t>(e.a) >= n.size() || static_cast<std::size_t>(e.b) >= n.size())
      throw std::invalid_argument("Solver::set_moving_water: an edge names a node the model lacks");
  std::vector<Vec2> x(n.size());
  for (std::size_t i = 0; i < n.size(); ++i) x[i] = n.x(static_cast<Index>(i));
  sph::SolidCoupling coupling(std::move(edges), fluid, x);
  moving_ = std::make_unique<MovingWater>(MovingWater{std::move(fluid), std::move(coupling), {}, {}, {}});
  const std::size_t k = moving_->coupling.nodes().size();
  moving_->force_prev.assign(k, Vec2::Zero());
  moving_->u_prev.resize(k);
  for (std::size_t j = 0; j < k; ++j) moving_->u_prev[j] = n.u[moving_->coupling.nodes()[j]];
  moving_->start = moving_->fluid.energy();
}

void Solver::set_constraints(std::vector<PrescribedDof> dofs) { constraints_ = std::move(dofs); }

void Solver::set_settings(const StepSettings& s) {
  settings_ = s;
  time_step_.set_fixed(s.dt);
  settings_.dt = time_step_.dt();
  if (damping_on()) allocate_damping_buffers();
  // A damped (static) stage brings the moving water to rest with the solid: its particles
  // carry the same mass-proportional damping, so the water follows the banks as they settle.
  if (moving_) moving_->fluid.set_settling_damping(settings_.alpha);
  // The element buffer only feeds this step's scatter: it can go as soon as beta is 0.
  if (!(s.beta > 0.0)) scatter_.keep_shared_damping(false);
}

void Solver::set_mass_damping(double alpha) {
  settings_.alpha = alpha;
  if (damping_on()) allocate_damping_buffers();
  if (moving_) moving_->fluid.set_settling_damping(alpha);
}

void Solver::set_time_step_rule(double safety, double fixed_limit) {
  time_step_.set_rule(model_, safety, fixed_limit, broken_joints_);
  settings_.dt = time_step_.dt();
}

void Solver::allocate_damping_buffers() {
  const std::size_t nn = model_.nodes.size();
  if (damping_force_.empty()) {
    damping_force_.assign(nn, Vec2::Zero());
    damping_force_prev_.assign(nn, Vec2::Zero());
    u_prev_.assign(nn, Vec2::Zero());
  }
  if (settings_.beta > 0.0) scatter_.keep_shared_damping(true);
}

void Solver::release_damping_buffers_if_unused() {
  // After an undamped step the previous damping forces are all +0, so the damping-work
  // term 0.5 (f_prev + f) . du is +0 at every node and leaves the energy ledger unchanged.
  if (damping_on() || !damped()) return;
  std::vector<Vec2>().swap(damping_force_);
  std::vector<Vec2>().swap(damping_force_prev_);
  std::vector<Vec2>().swap(u_prev_);
}

void Solver::initialise() {
  restart_verlet_segment(0.0);  // the steps so far booked; the new accelerations start afresh
  clear_forces();
  add_gravity();
  water_booking_ = false;  // no step taken: the water forces do no work yet
  add_element_and_joint_forces();
  water_booking_ = true;
  add_contact_forces();
  if (moving_) apply_moving_water_forces(false);  // the coupling's forces at the current state
  add_boundary_forces();
  add_damping_forces();
  apply_constraints();
  auto& n = model_.nodes;
  // The forces summed in n.a become the accelerations f/m, in place (as finish_kick()).
  exec::parallel_for(team_, n.size(), [&](std::size_t i) { n.a[i] = n.m[i] > 0.0 ? Vec2(n.a[i] / n.m[i]) : Vec2(Vec2::Zero()); });
  if (damped()) damping_force_prev_ = damping_force_;
  update_energy();
  restart_verlet_segment(settings_.dt);
  settle_verlet_offset();
  energy_.initial_total =
      energy_.mechanical() - energy_.verlet_kinetic_offset + energy_.dissipated() - energy_.work_in();
}

// One step of velocity Verlet, phase by phase (docs/theory.md §1). The execution layer runs a
// node pass (the kick and drift, the velocities) inside the next region over the nodes
// instead of in a region of its own (exec::Team::defer_node_pass); the order of the
// physics is this one.
void Solver::step() {
  begin_step();
  kick_drift_and_restart_forces();  // 1-2
  add_element_and_joint_forces();   // 3-4
  add_contact_forces();             // 5
  add_moving_water_forces();        // 5b
  add_boundary_forces();            // 6
  add_damping_forces();             // 7
  apply_constraints();
  finish_velocities();              // 8
  update_energy();                  // 9: the ledger that histories read
  check_stability();
  end_step();
}

void Solver::begin_step() {
  team_.begin_step();
  time_step_.update(model_, broken_joints_);
  settings_.dt = time_step_.dt();
  if (settings_.dt != verlet_offset_.dt) restart_verlet_segment(settings_.dt);
  if (any_law_state_) commit_law_state();
  const auto& n = model_.nodes;
  // The displacements before the drift that the work of the supports and of the viscous
  // boundary needs (a few nodes; the damping work needs all, then in u_prev_).
  for (auto& d : constraints_) d.u_prev = n.u[d.node][d.dir];
  for (auto& bn : boundary_) bn.u_prev = n.u[bn.node];
  kick_from_ = time_;
  time_ += settings_.dt;
}

void Solver::kick_drift_and_restart_forces() {
  // Each thread kicks the nodes its contact pairs read (the contact phase's last
  // partition), and finishes and sums the same nodes at the step's end.
  if (contact_) team_.set_node_chunks_from(contact_->node_split(), team_.threads(), model_.nodes.size());
  else team_.clear_node_chunks();
  team_.defer_node_pass(exec::NodePass(kick_pass_));
}

void Solver::kick_drift_nodes(std::size_t begin, std::size_t end) {
  const double dt = settings_.dt;
  const bool damped = this->damped();
  const KickDrift k{dt, settings_.gravity, kick_from_ + 0.5 * dt, time_, damped ? u_prev_.data() : nullptr,
                    damped ? damping_force_.data() : nullptr};
  kick_and_drift(model_.nodes, k, constraints_, begin, end);
}

void Solver::finish_velocities() { team_.defer_node_pass(exec::NodePass(finish_pass_)); }

void Solver::finish_velocity_nodes(std::size_t begin, std::size_t end) {
  finish_kick(model_.nodes, settings_.dt, time_, constraints_, begin, end);
}

void Solver::end_step() {
  ++step_;
  if (!setup_memory_released_) release_setup_memory();
  if (team_.end_step(step_) && contact_) contact_->set_parallel(team_.parallel());
}

void Solver::release_setup_memory() {
#if defined(__GLIBC__)
  // The set-up's temporaries (mesh, joint insertion, gather build) and the smaller
  // predecessors of the contact lists grown by the first step are free, but glibc keeps
  // their pages: hand them back, or the run holds them to its end, or the run holds them to its end. Once: no
  // system call per step.
  malloc_trim(0);
#endif
  setup_memory_released_ = true;
}

void Solver::clear_forces() {
  auto& n = model_.nodes;
  const bool damped = this->damped();
  exec::parallel_for(team_, n.size(), [&](std::size_t i) {
    n.a[i].setZero();  // the force sum (Nodes::a)
    if (damped) damping_force_[i].setZero();
  });
}

void Solver::add_gravity() {
  const auto& n = model_.nodes;
  const Vec2 g = settings_.gravity;
  forces_.add_per_node(team_, [&](std::size_t i) { return Vec2(n.m[i] * g); });
}

bool Solver::bonded(Index i, Index j) const {
  const auto& J = model_.joints;
  for (Index jt : scatter_.joints_of(static_cast<std::size_t>(i))) {
    if (jt == kNoIndex) break;
    if (!J.broken[jt] && (J.tri_a[jt] == j || J.tri_b[jt] == j)) return true;
  }
  return false;
}

void Solver::add_contact_forces() {
  if (!contact_) return;
  auto& n = model_.nodes;
  const ContactSetup& cs = model_.contact;
  const contact::ContactInput in{n.X, n.v, n.m, model_.triangles.conn, cs.active, cs.radius,
                                 model_.triangles.group, cs.body, n.u};
  contact_stats_ = contact_->compute(in, contact_params_, settings_.dt,
                                     [this](Index i, Index j) { return bonded(i, j); }, forces_.scatter(),
                                     broken_joints_);  // bonded() changes only when a joint breaks
  energy_.contact_elastic = contact_stats_.elastic_energy;
  energy_.friction_dissipated += contact_stats_.friction_dissipation;
  energy_.contact_damping_dissipated += contact_stats_.damping_dissipation;
}

// The water steps at its own stable step (docs/theory.md §11): sub-cycled when that is shorter than
// the solid's, and, when it is longer, advanced once over as many solid steps as fit in it,
// its force on the nodes held in between (the solid sub-cycling inside the water's step).
void Solver::add_moving_water_forces() {
  if (!moving_) return;
  const auto& n = model_.nodes;
  sph::SolidCoupling& c = moving_->coupling;
  moving_->waiting += settings_.dt;
  if (moving_->waiting + settings_.dt <= moving_->fluid.stable_dt()) {
    apply_moving_water_forces(true);
    return;
  }
  const auto nodes = c.nodes();
  const auto next = c.next_positions();
  for (std::size_t k = 0; k < nodes.size(); ++k) next[k] = n.x(nodes[k]);
  c.advance(moving_->fluid, moving_->waiting);
  moving_->waiting = 0.0;
  apply_moving_water_forces(true);
}

// The coupling's node forces into the sum in its node order; their work as for every
// other load, drift_work on each node's displacement over the step (docs/theory.md §7).
void Solver::apply_moving_water_forces(bool book) {
  const auto& n = model_.nodes;
  const sph::SolidCoupling& c = moving_->coupling;
  const auto nodes = c.nodes();
  const auto f = c.forces();
  double work = 0.0;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const Index i = nodes[k];
    forces_.add_at(i, f[k]);
    if (book) work += drift_work(moving_->force_prev[k], f[k], n.u[i] - moving_->u_prev[k]);
    moving_->force_prev[k] = f[k];
    moving_->u_prev[k] = n.u[i];
  }
  energy_.moving_water_work += work;
}

void Solver::set_viscous_boundary(std::vector<boundary::BoundaryNode> nodes,
                                  const std::vector<PrescribedDof>& previous_constraints) {
  attach_boundary_nodes(nodes, model_.nodes.u, previous_constraints);
  boundary_ = std::move(nodes);
  boundary_force_prev_.assign(boundary_.size(), Vec2::Zero());
  for (std::size_t k = 0; k < boundary_.size(); ++k) boundary_force_prev_[k] = boundary_[k].static_force;
}

void Solver::set_earthquake(const seismic::Accelerogram* horizontal, const seismic::Accelerogram* vertical,
                            double incident_factor, double start_time) {
  quake_h_ = {horizontal, incident_factor};
  quake_v_ = {vertical, incident_factor};
  quake_start_ = start_time;
}

void Solver::add_boundary_forces() {
  if (boundary_.empty()) return;
  auto& n = model_.nodes;
  const double tq = time_ - quake_start_;
  const bool quake = quake_h_.record || quake_v_.record;
  double work = 0.0;
  for (std::size_t k = 0; k < boundary_.size(); ++k) {
    const boundary::BoundaryNode& bn = boundary_[k];
    const Index i = bn.node;
    Vec2 F = bn.static_force + boundary::viscous_spring_force(bn.coef, bn.normal, n.u[i] - bn.u_ref, n.v[i]);
    if (quake && bn.free_field) {
      boundary::FreeFieldState ff;
      if (quake_h_.record) ff += boundary::free_field_column(boundary::IncidentWave::SV, quake_h_, bn.medium, bn.height, bn.H, tq);
      if (quake_v_.record) ff += boundary::free_field_column(boundary::IncidentWave::P, quake_v_, bn.medium, bn.height, bn.H, tq);
      F += boundary::free_field_input_force(bn.coef, bn.area, bn.normal, ff);
    }
    forces_.add_at(i, F);
    // Everything the boundary does (springs, dashpots, input) is booked as external work.
    work += drift_work(boundary_force_prev_[k], F, n.u[i] - bn.u_prev);
    boundary_force_prev_[k] = F;
  }
  energy_.external_work += work;
}

void Solver::add_damping_forces() {
  const double alpha = settings_.alpha;
  const double local = settings_.local_damping;
  const auto& n = model_.nodes;
  if (local > 0.0) {
    // On the force without the damping so far (the stiffness part is in the sum already).
    forces_.add_per_node(team_, [&](std::size_t i) {
      const Vec2 fd = local_damping_force(Vec2(forces_.at(i) - damping_force_[i]), n.v[i], local);
      damping_force_[i] += fd;  // booked with drift_work in update_energy()
      return fd;
    });
  }
  if (alpha <= 0.0) return;
  forces_.add_per_node(team_, [&](std::size_t i) {
    const Vec2 fd = -alpha * n.m[i] * n.v[i];
    damping_force_[i] += fd;  // booked with drift_work in update_energy()
    return fd;
  });
}

void Solver::apply_constraints() {
  add_reactions(model_.nodes, forces_, std::span(constraints_), time_, energy_.external_work);
}

void Solver::update_energy() {
  auto& n = model_.nodes;
  const Vec2 g = settings_.gravity;
  // The node sums and the strain energy in one region, fixed chunks: deterministic. Each
  // sum is accumulated on its own, so leaving the damping work out changes no other sum.
  // A node pass deferred to here (the velocities) runs first on the nodes each thread
  // sums: node-local, so no barrier.
  const exec::NodePass pass = team_.take_node_pass();
  auto prepare = [&](std::size_t begin, std::size_t end) {
    if (pass) pass(begin, end);
  };
  auto strain = [&](std::size_t t) { return std::array<double, 1>{element_strain_energy_[t]}; };
  const std::size_t nt = element_strain_energy_.size();
  if (damped()) {
    const auto [node_sums, strain_sum] = exec::deterministic_sums<3, 1>(
        n.size(), prepare,
        [&](std::size_t i) {
          return std::array<double, 3>{0.5 * n.m[i] * n.v[i].squaredNorm(), -n.m[i] * g.dot(n.u[i]),
                                       drift_work(damping_force_prev_[i], damping_force_[i], n.u[i] - u_prev_[i])};
        },
        nt, strain, reduction_scratch_, team_.parallel(), team_.node_chunks());
    energy_.kinetic = node_sums[0];
    energy_.gravity_potential = node_sums[1];
    energy_.damping_dissipated -= node_sums[2];
    energy_.strain = strain_sum[0];
  } else {
    const auto [node_sums, strain_sum] = exec::deterministic_sums<2, 1>(
        n.size(), prepare,
        [&](std::size_t i) {
          return std::array<double, 2>{0.5 * n.m[i] * n.v[i].squaredNorm(), -n.m[i] * g.dot(n.u[i])};
        },
        nt, strain, reduction_scratch_, team_.parallel(), team_.node_chunks());
    energy_.kinetic = node_sums[0];
    energy_.gravity_potential = node_sums[1];
    energy_.strain = strain_sum[0];
  }
  offset_settled_ = false;  // the accelerations are this step's: energy() settles the offset
  if (any_law_state_) energy_.plastic_dissipated = law_dissipation_sum();
  if (water_.active()) energy_.water_work += water_work_sum();
  if (moving_) {
    const sph::Fluid::Energy e = moving_->fluid.energy();
    energy_.fluid_kinetic = e.kinetic;
    energy_.fluid_potential = e.potential - moving_->start.potential;
    energy_.fluid_compression = e.compression - moving_->start.compression;
    energy_.fluid_excluded = moving_->fluid.excluded_energy();
  }
  std::swap(damping_force_prev_, damping_force_);
  release_damping_buffers_if_unused();
}

double Solver::mass_accel2() const {
  const Nodes& n = model_.nodes;
  double s = 0.0;
  for (std::size_t i = 0; i < n.size(); ++i) s += n.m[i] * n.a[i].squaredNorm();
  return s;
}

// Each step's kinetic energy change is the trapezoidal work of the forces plus
// dt^2/8 (S(n+1) - S(n)), both kicks with that step's dt (docs/theory.md §7): over the open
// segment's steps that sums to dt^2/8 (S - s_start).
void Solver::restart_verlet_segment(double dt) {
  const double s = mass_accel2();
  const double closed = verlet_offset_.closed + 0.125 * verlet_offset_.dt * verlet_offset_.dt * (s - verlet_offset_.s_start);
  verlet_offset_ = {closed, s, dt};
}

void Solver::settle_verlet_offset() const {
  const VerletOffset& o = verlet_offset_;
  energy_.verlet_kinetic_offset = o.closed + 0.125 * o.dt * o.dt * (mass_accel2() - o.s_start);
  offset_settled_ = true;
}

Vec2 Solver::reaction_on(const std::vector<Index>& nodes) const {
  Vec2 r = Vec2::Zero();
  for (const auto& d : constraints_)
    if (std::binary_search(nodes.begin(), nodes.end(), d.node)) r[d.dir] += d.reaction_prev;
  return r;
}

void Solver::check_stability() {
  if (moving_ && !moving_->fluid.sound()) throw_water_unsound();
  const auto& n = model_.nodes;
  const auto& tri = model_.triangles;
  if (!std::isfinite(energy_.kinetic) || !std::isfinite(energy_.strain)) {
    for (std::size_t i = 0; i < n.size(); ++i)
      if (!std::isfinite(n.v[i].squaredNorm()) || !std::isfinite(n.u[i].squaredNorm()))
        throw InstabilityError(fmt::format("non-finite velocity at node {} ({:.6g}, {:.6g}) m, step {}, t = {:.6g} s",
                                           i, n.X[i].x(), n.X[i].y(), step_ + 1, time_),
                               "non_finite", static_cast<Index>(i), n.X[i], step_ + 1, time_);
    throw InstabilityError(fmt::format("non-finite energy at step {}, t = {:.6g} s", step_ + 1, time_), "non_finite",
                           kNoIndex, Vec2::Zero(), step_ + 1, time_);
  }
  if (inverted_) {  // the element loop saw a det F <= 0: find it (same det F as the kernel's) and name it
    for (std::size_t t = 0; t < tri.size(); ++t) {
      const auto& c = tri.conn[t];
      const double detF = fem::deformation_gradient(n.X[c[0]] + n.u[c[0]], n.X[c[1]] + n.u[c[1]], n.X[c[2]] + n.u[c[2]],
                                                    tri.Dm_inv[t]).determinant();
      if (!(detF > 0.0)) {
        const Vec2 p = (n.x(c[0]) + n.x(c[1]) + n.x(c[2])) / 3.0;
        throw InstabilityError(
            fmt::format("inverted element {} (det F = {:.3g}) at ({:.6g}, {:.6g}) m, step {}, t = {:.6g} s: the time "
                        "step is too large or the element is crushed",
                        t, detF, p.x(), p.y(), step_ + 1, time_),
            "inverted_element", static_cast<Index>(t), p, step_ + 1, time_);
      }
    }
  }
  // Energy created from nothing: mechanical + dissipated energy above the start plus the
  // work put in, by more than a tenth of the largest energy in play, and growing by at
  // least 15 % a step for kEnergyGrowthSteps steps in a row. A numerical instability grows
  // exponentially like that; a constant offset (a velocity imposed suddenly at t = 0,
  // whose impulse is no work) or a slow drift does not. The kinetic energy here is the
  // full step's, without the Verlet offset: velocity Verlet conserves its modified energy
  // even while a linear mode grows unstably, so that energy would hide the growth.
  constexpr double kEnergyGrowthRatio = 0.1;
  constexpr double kEnergyGrowthRate = 1.15;
  constexpr int kEnergyGrowthSteps = 5;
  const double created = energy_.mechanical() - energy_.initial_total + energy_.dissipated() - energy_.work_in();
  const double in_play = std::max({std::abs(energy_.kinetic), std::abs(energy_.strain), std::abs(energy_.gravity_potential),
                                   std::abs(energy_.joint_elastic), std::abs(energy_.contact_elastic),
                                   std::abs(energy_.external_work), std::abs(energy_.water_work), std::abs(energy_.moving_water_work),
                                   std::abs(energy_.dissipated()),
                                   std::abs(energy_.initial_total)});
  const bool growing = created > kEnergyGrowthRatio * in_play && created > kEnergyGrowthRate * created_prev_ &&
                       created_prev_ > 0.0;
  energy_growth_steps_ = growing ? energy_growth_steps_ + 1 : 0;
  created_prev_ = created;
  if (energy_growth_steps_ >= kEnergyGrowthSteps) {
    // Where it shows: the node with the largest kinetic energy.
    std::size_t worst = 0;
    double worst_ke = -1.0;
    for (std::size_t i = 0; i < n.size(); ++i) {
      const double ke = n.m[i] * n.v[i].squaredNorm();
      if (ke > worst_ke) worst_ke = ke, worst = i;
    }
    const Vec2 p = n.size() ? n.x(static_cast<Index>(worst)) : Vec2::Zero();
    throw InstabilityError(
        fmt::format("energy growing beyond the work put in: {:.4g} J created (work in {:.4g}, start {:.4g}, kinetic {:.4g}) "
                    "for {} steps; fastest node {} at ({:.6g}, {:.6g}) m, step {}, t = {:.6g} s: the time step is too large "
                    "for a stiffness the stable-step estimate missed (lower time.safety)",
                    created, energy_.external_work, energy_.initial_total, energy_.kinetic, kEnergyGrowthSteps, worst,
                    p.x(), p.y(), step_ + 1, time_),
        "energy_growth", static_cast<Index>(worst), p, step_ + 1, time_);
  }
}

// The moving water left its weakly compressible range (sph::Fluid::sound): checked before
// the solid, whose elements the water's forces crush next.
void Solver::throw_water_unsound() const {
  const sph::Fluid& f = moving_->fluid;
  const sph::FluidParticles& w = f.fluid();
  const std::size_t i = std::min(f.first_unsound_particle(), w.size() - 1);
  const double speed = std::hypot(w.vx[i], w.vy[i]), c0 = f.parameters().c0, rho0 = f.parameters().rho0;
  // With particles taken out of range (sph::Fluid::excluded): how many went before, how many
  // left the range at this step (all of them go or none), and what the limit allows.
  const std::string excluded =
      f.parameters().excluded_limit > 0.0
          ? fmt::format("; {} of the water's particles out of range at this step, {} taken out before it, "
                        "reservoir.sph.excluded_limit = {:.4g} allows {} of its {} (a particle not finite is never "
                        "taken out)",
                        f.unsound_count(), f.excluded().size(), f.parameters().excluded_limit, f.excluded_capacity(),
                        f.initial_size())
          : std::string();
  throw InstabilityError(
      fmt::format("the moving water left its weakly compressible range: particle {} at ({:.6g}, {:.6g}) m moves at "
                  "{:.4g} m/s (c0 = {:.4g} m/s) with density {:.5g} kg/m^3 (rho0 = {:.5g}, at most {:.0f} % off), step "
                  "{}, t = {:.6g} s{}: water squeezed faster than it can flow out (a gap closing between solids), or a "
                  "sound speed too low for the flow",
                  w.id[i], w.x[i], w.y[i], speed, c0, w.rho[i], rho0, 100.0 * sph::Fluid::kSoundRange, step_ + 1, time_,
                  excluded),
      "water_unsound", static_cast<Index>(w.id[i]), Vec2(w.x[i], w.y[i]), step_ + 1, time_);
}

}  // namespace dsdem::solver
