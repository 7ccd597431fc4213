#include "solver/solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#ifdef _OPENMP
#include <omp.h>
#endif

static_assert(sizeof(std::array<dsdem::Vec2, 3>) == 3 * sizeof(dsdem::Vec2) &&
                  sizeof(std::array<dsdem::Vec2, 4>) == 4 * sizeof(dsdem::Vec2),
              "per-element / per-joint force arrays are read as flat Vec2 arrays in the gather");

#include "solver/parallel.hpp"
#include "model/work_split.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace dsdem::solver {

namespace {
std::ptrdiff_t ssize(std::size_t n) { return static_cast<std::ptrdiff_t>(n); }
// A prescribed dof on a node of the range [begin, end) (one thread's nodes).
bool on_nodes(const PrescribedDof& d, std::size_t begin, std::size_t end) {
  return static_cast<std::size_t>(d.node) >= begin && static_cast<std::size_t>(d.node) < end;
}
}  // namespace


StableStep triangle_step_limit(const Model& model, double beta) {
  StableStep best;
  best.dt = std::numeric_limits<double>::infinity();
  const auto& tri = model.triangles;
  for (std::size_t t = 0; t < tri.size(); ++t) {
    const auto& c = tri.conn[t];
    const Vec2 x0 = model.nodes.x(c[0]), x1 = model.nodes.x(c[1]), x2 = model.nodes.x(c[2]);
    const double h = fem::characteristic_length(x0, x1, x2);
    const Material& mat = model.materials[tri.material[t]];
    const double cp = mat.cp();
    const double dt = fem::critical_time_step(h, cp, beta);
    if (dt < best.dt) {
      best.dt = dt;
      best.element = static_cast<Index>(t);
      best.position = (x0 + x1 + x2) / 3.0;
      const std::string group = tri.group[t] >= 0 ? model.groups[tri.group[t]].name : "?";
      best.controlled_by = fmt::format("triangle {} (group {}, material {}) at ({:.4g}, {:.4g}) m: h = {:.4g} m, cp = {:.5g} m/s",
                                       t, group, mat.name, best.position.x(), best.position.y(), h, cp);
    }
  }
  return best;
}

std::vector<JointStepLimit> joint_step_limits(const Model& model, bool intact_only) {
  // Joints: 2 sqrt(m/k) of the two node masses across each end (DESIGN.md §6).
  const auto& J = model.joints;
  std::vector<JointStepLimit> limits;
  for (std::size_t j = 0; j < J.size(); ++j) {
    if (intact_only && J.broken[j]) continue;
    const JointProperties& p = model.joint_properties[J.property[j]];
    const double k = joint_end_stiffness(p, J.length0[j], J.stiffness_scale[j]) * model.thickness;
    JointStepLimit l{std::numeric_limits<double>::infinity(), static_cast<Index>(j), 0};
    for (int e = 0; e < 2; ++e) {
      const double dt = joint_stable_dt(model.nodes.m[J.nodes[j][e]], model.nodes.m[J.nodes[j][2 + e]], k);
      if (dt < l.dt) l.dt = dt, l.end = e;
    }
    limits.push_back(l);
  }
  std::sort(limits.begin(), limits.end(), [](const JointStepLimit& a, const JointStepLimit& b) {
    return a.dt < b.dt || (a.dt == b.dt && a.joint < b.joint);
  });
  return limits;
}

StableStep describe_joint_limit(const Model& model, const JointStepLimit& limit) {
  const auto& J = model.joints;
  const Index j = limit.joint;
  const Index a = J.nodes[j][limit.end], b = J.nodes[j][2 + limit.end];
  const JointProperties& p = model.joint_properties[J.property[j]];
  const double k = joint_end_stiffness(p, J.length0[j], J.stiffness_scale[j]) * model.thickness;
  StableStep s;
  s.dt = limit.dt;
  s.element = j;
  s.position = model.nodes.x(a);
  s.controlled_by = fmt::format("joint {} ({}) at ({:.4g}, {:.4g}) m: k = {:.4g} N/m per end, node masses {:.4g} and {:.4g} kg",
                                j, p.name, s.position.x(), s.position.y(), k, model.nodes.m[a], model.nodes.m[b]);
  return s;
}

StableStep contact_step_limit(const Model& model) {
  // Contact springs: 2 sqrt(m/k) with the reduced mass of two of the lightest nodes.
  StableStep best;
  best.dt = std::numeric_limits<double>::infinity();
  if (!model.contact.enabled || !(model.contact.max_kn > 0.0)) return best;
  const auto& tri = model.triangles;
  for (std::size_t t = 0; t < tri.size(); ++t) {
    if (!model.contact.active[t]) continue;
    double m = std::numeric_limits<double>::infinity();
    for (Index nd : tri.conn[t]) m = std::min(m, model.nodes.m[nd]);
    const double dt = 2.0 * std::sqrt(0.5 * m / model.contact.max_kn);
    if (dt < best.dt) {
      best.dt = dt;
      best.element = static_cast<Index>(t);
      best.position = model.nodes.x(tri.conn[t][0]);
      best.controlled_by = fmt::format("contact at triangle {} ({:.4g}, {:.4g}) m: kn = {:.4g} Pa, node mass {:.4g} kg",
                                       t, best.position.x(), best.position.y(), model.contact.max_kn, m);
    }
  }
  return best;
}

StableStep stable_time_step(const Model& model, double beta) {
  StableStep best = triangle_step_limit(model, beta);
  const std::vector<JointStepLimit> joints = joint_step_limits(model);
  if (!joints.empty() && joints.front().dt < best.dt) best = describe_joint_limit(model, joints.front());
  StableStep contact = contact_step_limit(model);
  if (contact.dt < best.dt) best = std::move(contact);
  return best;
}

void Solver::set_time_step_rule(double safety, double fixed_limit) {
  if (!(safety > 0.0 && safety <= 1.0) || !(fixed_limit > 0.0))
    throw std::invalid_argument(fmt::format("time-step rule: safety {} must be in (0, 1] and the fixed limit {} s > 0",
                                            safety, fixed_limit));
  step_rule_safety_ = safety;
  step_rule_fixed_ = fixed_limit;
  joint_limits_ = joint_step_limits(model_, false);  // all: a restore may mend some
  joint_limit_first_ = 0;
  step_rule_broken_ = -1;
  apply_time_step_rule();
}

void Solver::apply_time_step_rule() {
  // Joints only break: the first intact joint in ascending order never moves back.
  const auto& broken = model_.joints.broken;
  while (joint_limit_first_ < joint_limits_.size() && broken[joint_limits_[joint_limit_first_].joint])
    ++joint_limit_first_;
  const double joint = joint_limit_first_ < joint_limits_.size() ? joint_limits_[joint_limit_first_].dt
                                                                 : std::numeric_limits<double>::infinity();
  // The same operands as the runner's first dt (safety x stable_time_step): while no
  // joint has broken, the same step bit for bit.
  settings_.dt = step_rule_safety_ * std::min(step_rule_fixed_, joint);
  step_rule_broken_ = broken_joints_;
}

const JointStepLimit* Solver::time_step_joint() const {
  if (!has_time_step_rule() || joint_limit_first_ >= joint_limits_.size()) return nullptr;
  const JointStepLimit& l = joint_limits_[joint_limit_first_];
  return l.dt < step_rule_fixed_ ? &l : nullptr;
}

Solver::Solver(Model& model) : model_(model), parallel_(model.triangles.size() > kParallelThreshold) {
#ifdef _OPENMP
  auto_parallel_ = parallel_ && omp_get_max_threads() > 1;
#endif
  const std::size_t ne = model_.triangles.size();
  element_strain_energy_.assign(ne, 0.0);
  set_stress_on_demand(false);  // sizes the triangles' stress and strain
  for (const auto& m : model_.materials) elastic_.push_back({m.lambda(), m.mu()});
  build_gather();
  for (auto b : model_.joints.broken) broken_joints_ += b ? 1 : 0;
  if (model_.contact.enabled) {
    contact::ContactSettings cs;
    cs.skin = model_.contact.skin;
    cs.parallel = parallel_;
    contact_ = std::make_unique<contact::ContactForces>(cs);
    contact_params_.set_default(model_.contact.defaults);
    for (const auto& p : model_.contact.pairs) contact_params_.set(p.group_a, p.group_b, p.props);
  }
}

void Solver::build_gather() {
  const auto& tri = model_.triangles;
  const auto& J = model_.joints;
  const std::size_t nn = model_.nodes.size(), ne = tri.size(), nj = J.size();
  joint_buf_.prepare(model_.joints, model_.joint_properties);
  // Joints per triangle, in joint order. A triangle with more than 3 joints (not made by
  // joint insertion: one joint per edge) is left shared; its slots keep the first 3.
  triangle_joints_.assign(ne, {kNoIndex, kNoIndex, kNoIndex});
  own_corners_.assign(ne, 0);
  for (std::size_t j = 0; j < nj; ++j)
    for (Index t : {J.tri_a[j], J.tri_b[j]}) {
      auto& slots = triangle_joints_[t];
      auto free = std::find(slots.begin(), slots.end(), kNoIndex);
      if (free == slots.end()) own_corners_[t] = kSharedTriangle;
      else *free = static_cast<Index>(j);
    }
  // Own triangles: each of their nodes in this triangle only (a count per node, 0..2).
  {
    std::vector<std::uint8_t> count(nn, 0);
    for (const auto& c : tri.conn)
      for (Index i : c) count[i] = static_cast<std::uint8_t>(std::min(count[i] + 1, 2));
    for (std::size_t t = 0; t < ne; ++t)
      for (Index i : tri.conn[t])
        if (count[i] != 1) own_corners_[t] = kSharedTriangle;
  }
  // Corners of each own triangle's joints: end e of joint j is node nodes[j][e] on face a
  // and nodes[j][2 + e] on face b.
  for (std::size_t t = 0; t < ne; ++t) {
    if (own_corners_[t] == kSharedTriangle) continue;
    std::uint16_t code = 0;
    for (int s = 0; s < 3; ++s) {
      const Index j = triangle_joints_[t][s];
      if (j == kNoIndex) break;
      const bool face_b = J.tri_b[j] == static_cast<Index>(t);
      unsigned bits = face_b ? 16u : 0u;
      for (int e = 0; e < 2; ++e) {
        const Index node = J.nodes[j][2 * face_b + e];
        const auto& c = tri.conn[t];
        const auto k = std::find(c.begin(), c.end(), node) - c.begin();
        if (k == 3) throw std::logic_error(fmt::format("joint {} does not use the nodes of its triangle {}", j, t));
        bits |= static_cast<unsigned>(k) << (2 * e);
      }
      code = static_cast<std::uint16_t>(code | (bits << (5 * s)));
    }
    own_corners_[t] = code;
  }
  own_prefix_.assign(ne + 1, 0);
  for (std::size_t t = 0; t < ne; ++t) own_prefix_[t + 1] = own_prefix_[t] + (own_corners_[t] != kSharedTriangle ? 1 : 0);
  // Shared triangles, and the nodes gathered by incidence: those of shared triangles and
  // those of no triangle at all (their sums stay as the gather leaves them).
  shared_triangles_.clear();
  std::vector<std::uint8_t> gathered(nn, 1);
  for (std::size_t t = 0; t < ne; ++t) {
    if (own_corners_[t] == kSharedTriangle) shared_triangles_.push_back(static_cast<Index>(t));
    else for (Index i : tri.conn[t]) gathered[i] = 0;
  }
  gathered_nodes_.clear();
  for (std::size_t i = 0; i < nn; ++i)
    if (gathered[i]) gathered_nodes_.push_back(static_cast<Index>(i));
  std::vector<std::uint8_t>().swap(gathered);
  shared_force_.assign(shared_triangles_.size(), {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()});
  auto slot_of = [this](Index node) {  // position in gathered_nodes_, or -1
    const auto it = std::lower_bound(gathered_nodes_.begin(), gathered_nodes_.end(), node);
    return it != gathered_nodes_.end() && *it == node ? static_cast<Index>(it - gathered_nodes_.begin()) : kNoIndex;
  };
  // CSR over the gathered nodes, entries in ascending triangle / joint order.
  const std::size_t ng = gathered_nodes_.size();
  gather_offset_.assign(ng + 1, 0);
  for (Index t : shared_triangles_)
    for (Index i : tri.conn[t]) ++gather_offset_[slot_of(i) + 1];
  for (std::size_t g = 0; g < ng; ++g) gather_offset_[g + 1] += gather_offset_[g];
  gather_entry_.assign(gather_offset_[ng], 0);
  std::vector<Index> fill(gather_offset_.begin(), gather_offset_.end() - 1);
  for (std::size_t s = 0; s < shared_triangles_.size(); ++s)
    for (int k = 0; k < 3; ++k)
      gather_entry_[fill[slot_of(tri.conn[shared_triangles_[s]][k])]++] = static_cast<Index>(3 * s + k);
  gather_joint_offset_.assign(ng + 1, 0);
  for (const auto& nd : J.nodes)
    for (Index i : nd)
      if (const Index g = slot_of(i); g != kNoIndex) ++gather_joint_offset_[g + 1];
  for (std::size_t g = 0; g < ng; ++g) gather_joint_offset_[g + 1] += gather_joint_offset_[g];
  gather_joint_entry_.assign(gather_joint_offset_[ng], 0);
  fill.assign(gather_joint_offset_.begin(), gather_joint_offset_.end() - 1);
  for (std::size_t j = 0; j < nj; ++j)
    // Entry 2 (2 j + e) + side: force slot 2 j + e (end e), side 1 = face b (negated).
    for (int k = 0; k < 4; ++k)
      if (const Index g = slot_of(J.nodes[j][k]); g != kNoIndex)
        gather_joint_entry_[fill[g]++] = static_cast<Index>(2 * (2 * j + k % 2) + k / 2);
  // Every (joint, node) once: by its own triangle's slot or by a gathered node.
  std::size_t covered = gather_joint_entry_.size();
  for (std::size_t t = 0; t < ne; ++t)
    if (own_corners_[t] != kSharedTriangle)
      for (Index j : triangle_joints_[t]) covered += j != kNoIndex ? 2 : 0;
  if (covered != 4 * nj)
    throw std::logic_error(fmt::format("joint nodes outside their triangles: {} of {} joint-node pairs reached", covered, 4 * nj));
}

void Solver::set_constraints(std::vector<PrescribedDof> dofs) { constraints_ = std::move(dofs); }

void Solver::set_settings(const StepSettings& s) {
  settings_ = s;
  if (has_time_step_rule()) apply_time_step_rule();
  if (s.alpha > 0.0 || s.beta > 0.0) allocate_damping_buffers();
  // The element buffer only feeds this step's gather: it can go as soon as beta is 0.
  if (!(s.beta > 0.0)) std::vector<std::array<Vec2, 3>>().swap(shared_damping_force_);
}

void Solver::allocate_damping_buffers() {
  const std::size_t nn = model_.nodes.size();
  if (damping_force_.empty()) {
    damping_force_.assign(nn, Vec2::Zero());
    damping_force_prev_.assign(nn, Vec2::Zero());
    u_prev_.assign(nn, Vec2::Zero());
  }
  if (settings_.beta > 0.0 && shared_damping_force_.size() != shared_triangles_.size())
    shared_damping_force_.assign(shared_triangles_.size(), {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()});
}

void Solver::release_damping_buffers_if_unused() {
  // After an undamped step the previous damping forces are all +0, so the damping-work
  // term 0.5 (f_prev + f) . du is +0 at every node and leaves the energy ledger unchanged.
  if (settings_.alpha > 0.0 || settings_.beta > 0.0 || !damped()) return;
  std::vector<Vec2>().swap(damping_force_);
  std::vector<Vec2>().swap(damping_force_prev_);
  std::vector<Vec2>().swap(u_prev_);
}

void Solver::initialise() {
  clear_forces();
  add_gravity();
  add_internal_and_joint_forces();
  add_contact_forces();
  add_boundary_forces();
  add_damping_forces();
  apply_constraints();
  auto& n = model_.nodes;
  // The forces summed in n.a become the accelerations f/m, in place (as finish_velocities()).
#pragma omp parallel for schedule(static) if (parallel_)
  for (std::ptrdiff_t i = 0; i < ssize(n.size()); ++i) n.a[i] = n.m[i] > 0.0 ? Vec2(n.a[i] / n.m[i]) : Vec2(Vec2::Zero());
  if (damped()) damping_force_prev_ = damping_force_;
  update_energy();
  energy_.initial_total = energy_.mechanical() + energy_.dissipated() - energy_.external_work;
}

void Solver::step() {
  const auto start = std::chrono::steady_clock::now();
  if (has_time_step_rule() && broken_joints_ != step_rule_broken_) apply_time_step_rule();
  begin_kick();
  add_internal_and_joint_forces(Kick::first);  // the kick and drift first, in the same region (issue 7)
  add_contact_forces();
  add_boundary_forces();
  add_damping_forces();
  apply_constraints();
  update_energy(FinishVelocities::yes);  // v(n+1) and the energies in one node loop (issue 7)
  check_stability();
  ++step_;
  if (!setup_memory_released_) release_setup_memory();
  if (auto_parallel_) probe_parallel(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

void Solver::release_setup_memory() {
#if defined(__GLIBC__)
  // The set-up's temporaries (mesh, joint insertion, gather build) and the smaller
  // predecessors of the contact lists grown by the first step are free, but glibc keeps
  // their pages: hand them back, or the run holds them to its end (1003 -> 975 B per
  // element on the 10^5-element box, issue 7 memory). Once: no system call per step.
  malloc_trim(0);
#endif
  setup_memory_released_ = true;
}

void Solver::probe_parallel(double step_seconds) {
  // The probe window is steps probe_start_ .. + 2 kProbeSteps - 1: the first half on one
  // thread, the second with OpenMP; then the faster mode runs until the next probe.
  if (!parallel_) ++serial_steps_chosen_;
  const long k = step_ - 1 - probe_start_;  // position of the step just done in the window
  if (k == -1) use_parallel(false);  // the window starts with the next step
  if (k < 0) return;
  if (k >= 2 * kProbeSteps) {  // e.g. after a restore: start a window now
    probe_start_ = step_;
    use_parallel(false);
    return;
  }
  if (k < kProbeSteps)
    probe_serial_[static_cast<std::size_t>(k)] = step_seconds;
  else
    probe_parallel_[static_cast<std::size_t>(k - kProbeSteps)] = step_seconds;
  if (k + 1 == kProbeSteps) {
    use_parallel(true);
  } else if (k + 1 == 2 * kProbeSteps) {
    // One thread is re-checked soon, then less and less often while it stays faster
    // (kRecheckInterval, doubling up to kProbeInterval): a slow spell of the other core
    // does not hold the run on one thread for long, and a busy machine pays few probes.
    const bool parallel = choose_parallel(probe_serial_, probe_parallel_);
    use_parallel(parallel);
    if (parallel) {
      probe_start_ = step_ + kProbeInterval;
      serial_recheck_ = kRecheckInterval;
    } else {
      probe_start_ = step_ + serial_recheck_;
      serial_recheck_ = std::min(2 * serial_recheck_, kProbeInterval);
    }
  }
}

void Solver::begin_kick() {
  const auto& n = model_.nodes;
  // The displacements before the drift that the work of the supports and of the
  // viscous boundary needs (a few nodes; the damping work needs all, then in u_prev_).
  for (auto& d : constraints_) d.u_prev = n.u[d.node][d.dir];
  for (auto& bn : boundary_) bn.u_prev = n.u[bn.node];
  kick_from_ = time_;
  time_ += settings_.dt;
}

void Solver::kick_and_drift(std::size_t begin, std::size_t end) {
  auto& n = model_.nodes;
  const double dt = settings_.dt;
  const Vec2 g = settings_.gravity;
  const bool damped = this->damped();
  // One node loop for the kick, the drift, clearing the forces and gravity. Once the kick
  // has read the acceleration, n.a starts this step's force sum with gravity (Nodes::a).
  for (std::size_t i = begin; i < end; ++i) {
    n.v[i] += 0.5 * dt * n.a[i];
    if (damped) {
      u_prev_[i] = n.u[i];
      damping_force_[i].setZero();
    }
    n.u[i] += dt * n.v[i];
    n.a[i] = n.m[i] * g;
  }
  // Prescribed velocities of these nodes, and their drift redone with them (the same
  // expression u_prev + dt v as above, so bit-identical to prescribing before the drift);
  // then prescribed displacements. Three passes in list order, as over the whole list.
  const double t_half = kick_from_ + 0.5 * dt, t_end = time_;  // begin_kick() advanced time_
  for (const auto& d : constraints_)
    if (on_nodes(d, begin, end)) n.v[d.node][d.dir] = prescribed_velocity(d, t_half);
  for (const auto& d : constraints_)
    if (on_nodes(d, begin, end)) n.u[d.node][d.dir] = d.u_prev + dt * n.v[d.node][d.dir];
  for (const auto& d : constraints_)
    if (on_nodes(d, begin, end) && d.kind == PrescribedDof::Displacement) n.u[d.node][d.dir] = d.u_start + d.history->at(t_end - d.t_start);
}

void Solver::refresh_node_chunks(int threads) {
  node_chunks_.clear();
  if (!contact_ || threads < 2) return;
  const std::span<const Index> bound = contact_->node_split();
  const std::size_t chunks = detail::reduction_chunks(model_.nodes.size());
  if (bound.size() != static_cast<std::size_t>(threads) + 1 || chunks < 2) return;
  // Each bound to the nearest chunk start, ascending.
  node_chunks_.resize(bound.size());
  for (std::size_t t = 0; t < bound.size(); ++t) {
    const auto node = static_cast<std::size_t>(bound[t]);
    const std::size_t c = t + 1 == bound.size() ? chunks : std::min(chunks, (node + kReductionChunk / 2) / kReductionChunk);
    node_chunks_[t] = t == 0 ? 0 : std::max(c, node_chunks_[t - 1]);
  }
}

void Solver::clear_forces() {
  auto& n = model_.nodes;
  const bool damped = this->damped();
#pragma omp parallel for schedule(static) if (parallel_)
  for (std::ptrdiff_t i = 0; i < ssize(n.size()); ++i) {
    n.a[i].setZero();  // the force sum (Nodes::a)
    if (damped) damping_force_[i].setZero();
  }
}

void Solver::add_gravity() {
  auto& n = model_.nodes;
  const Vec2 g = settings_.gravity;
#pragma omp parallel for schedule(static) if (parallel_)
  for (std::ptrdiff_t i = 0; i < ssize(n.size()); ++i) n.a[i] += n.m[i] * g;
}

void Solver::add_internal_and_joint_forces(Kick kick) {
  auto& n = model_.nodes;
  auto& tri = model_.triangles;
  auto& J = model_.joints;
  const double beta = settings_.beta;
  const double thickness = model_.thickness;
  const bool joints = J.size() > 0;
  const bool damped = this->damped();
  const bool element_damping = beta > 0.0;  // the stiffness-damping forces (Rayleigh beta)
  const std::ptrdiff_t ns = ssize(shared_triangles_.size()), ng = ssize(gathered_nodes_.size());
  int inverted = 0;
  Index broken_now = 0;
  // One triangle: stress (unless on demand), strain energy, nodal forces r.force and
  // the stiffness-damping forces into damping (zeros when beta = 0).
  auto element = [&](std::size_t t, std::array<Vec2, 3>& damping) {
    fem::TriangleInput in = triangle_input(t);
    if (element_damping)  // the kernel reads v only when beta > 0
      for (int k = 0; k < 3; ++k) in.v[k] = n.v[tri.conn[t][k]];
    in.beta = beta;
    in.cauchy = !stress_on_demand_;
    fem::TriangleResponse r;
    fem::triangle_internal_force(in, elastic_[tri.material[t]], r, damping);
    if (!stress_on_demand_) {
      tri.stress[t] = r.cauchy;
      tri.strain[t] = r.green;
    }
    element_strain_energy_[t] = r.strain_energy;
    return r;
  };
  // One region per step (issue 7). Phase 0 (Kick::first), then a barrier: the kick and
  // drift of each thread's nodes. Phase 1: the shared triangles into their buffers and
  // the joints into theirs, sharing the threads without a barrier between them. Phase 2,
  // after the barrier: the own triangles (element force and their joints' forces straight
  // into their nodes' sums) and the gathered nodes. Every node's sum is formed as
  // f + fd + fj in a fixed order (elements, then joints in joint order): bit-identical
  // for any thread count. A broken joint's slots stay zero.
  int threads = 1;
#ifdef _OPENMP
  if (parallel_) threads = omp_get_max_threads();
#endif
  shared_split_.prepare(threads);
  joint_split_.prepare(threads);
  own_split_.prepare(threads);
  counted_share_bounds(own_prefix_, own_split_.cum(), own_bound_);
  const std::size_t n_joint_blocks = joints ? joint_blocks(J.size()) : 0;
  if (threads > 1) {  // the runs' bounds; a thread that ends its own run helps with the others'
    joint_bound_.resize(static_cast<std::size_t>(threads) + 1);
    for (int t = 0; t <= threads; ++t) joint_bound_[static_cast<std::size_t>(t)] = joint_split_.begin(n_joint_blocks, t);
    joint_runs_.reset(joint_bound_);
    own_runs_.reset(own_bound_);
  }
  if (kick == Kick::first) refresh_node_chunks(threads);
  bool full_team = false;
#pragma omp parallel num_threads(threads) if (parallel_) reduction(| : inverted)
  {
    int thread = 0, team = 1;
#ifdef _OPENMP
    thread = omp_get_thread_num();
    team = omp_get_num_threads();  // <= threads
#endif
    // This thread's shared slots and own triangles (all of them when the team is smaller
    // than asked for: then one thread).
    const bool split = team == threads;
    const auto th = static_cast<std::size_t>(thread);
    if (kick == Kick::first) {
      // The kick on this thread's node chunks (those it also finishes and sums at the
      // step's end: each node's lines stay on one core), then a barrier: the triangles
      // read any thread's nodes. A barrier instead of a fork and join of its own.
      const auto [begin, end] = detail::chunk_indices(n.size(), th, static_cast<std::size_t>(team), node_chunks_);
      kick_and_drift(begin, end);
#pragma omp barrier
    }
    const auto n_shared = static_cast<std::size_t>(ns);
    const std::ptrdiff_t s_begin = split ? static_cast<std::ptrdiff_t>(shared_split_.begin(n_shared, thread)) : (thread == 0 ? 0 : ns);
    const std::ptrdiff_t s_end = split ? static_cast<std::ptrdiff_t>(shared_split_.begin(n_shared, thread + 1)) : ns;
    double busy_from = 0.0;
#ifdef _OPENMP
    busy_from = omp_get_wtime();
#endif
    for (std::ptrdiff_t s = s_begin; s < s_end; ++s) {
      std::array<Vec2, 3> no_damping;  // beta = 0: the kernel writes zeros, nobody reads them
      const auto t = static_cast<std::size_t>(shared_triangles_[s]);
      const fem::TriangleResponse r = element(t, element_damping ? shared_damping_force_[s] : no_damping);
      shared_force_[s] = r.force;
      // check_stability() finds the element when this flag is set.
      if (!(r.detF > 0.0)) inverted = 1;
    }
#ifdef _OPENMP
    shared_split_.set_busy(thread, omp_get_wtime() - busy_from);
    busy_from = omp_get_wtime();
#endif
    if (joints) {
      // Any thread may evaluate any block (each writes its own slots; the count of
      // breaks is a sum of integers): one block per claim.
      if (split && team > 1) {
        const std::size_t done = joint_runs_.run(thread, 1, [&](std::size_t b0, std::size_t b1) {
          evaluate_joints(n, J, settings_.failure, thickness, joint_buf_, broken_now, b0, b1);
        });
#ifdef _OPENMP
        joint_split_.set_busy(thread, StealingRuns::busy_for_own_run(omp_get_wtime() - busy_from,
                                                                     joint_bound_[th + 1] - joint_bound_[th], done));
#endif
      } else if (thread == 0) {
        evaluate_joints(n, J, settings_.failure, thickness, joint_buf_, broken_now, 0, n_joint_blocks);
      }
    }
#pragma omp barrier
#ifdef _OPENMP
    busy_from = omp_get_wtime();
#endif
    const std::array<Vec2, 2>* jforce = joint_buf_.force.data();
    // Own triangles [own_begin, own_end) (they write only their own nodes; no order).
    auto own_triangles = [&](std::size_t own_begin, std::size_t own_end) {
      for (std::size_t t = own_begin; t < own_end; ++t) {
        const std::uint16_t code = own_corners_[t];
        if (code == kSharedTriangle) continue;
        std::array<Vec2, 3> df;
        const fem::TriangleResponse r = element(t, df);
        if (!(r.detF > 0.0)) inverted = 1;
        // The joints' forces per corner, in joint order (as a per-node incidence would).
        std::array<Vec2, 3> fj{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
        for (int s = 0; s < 3; ++s) {
          const Index j = triangle_joints_[t][s];
          if (j == kNoIndex) break;
          const unsigned c = static_cast<unsigned>(code) >> (5 * s);
          const std::array<Vec2, 2>& F = jforce[j];
          if (c & 16u) {  // face b: minus face a's force, bit for bit as adding it negated
            fj[c & 3u] -= F[0];
            fj[(c >> 2) & 3u] -= F[1];
          } else {
            fj[c & 3u] += F[0];
            fj[(c >> 2) & 3u] += F[1];
          }
        }
        for (int k = 0; k < 3; ++k) {
          const Index i = tri.conn[t][k];
          // The sums a gather over one element would form: +0 + force (and damping force).
          Vec2 f = Vec2::Zero(), fd = Vec2::Zero();
          f += r.force[k];
          if (element_damping) fd += df[k];  // without beta fd stays +0 (bit-identical)
          n.a[i] += f + fd + fj[k];  // the force sum (Nodes::a)
          if (damped) damping_force_[i] += fd;
        }
      }
    };
    // An own triangle writes only its own nodes: any thread may take it (kOwnChunk per claim).
    std::size_t own_done = 0;
    if (split && team > 1) own_done = own_runs_.run(thread, kOwnChunk, own_triangles);
    else if (thread == 0) own_triangles(0, tri.size());
    // Flat views: entry 3 s + k is shared_force_[s][k], entry 2 j + e joint_buf_.force[j][e].
    const Vec2* sf = shared_force_.empty() ? nullptr : shared_force_[0].data();
    const Vec2* sdf = shared_damping_force_.empty() ? nullptr : shared_damping_force_[0].data();
    const Vec2* jf = joint_buf_.force.empty() ? nullptr : joint_buf_.force[0].data();
#pragma omp for schedule(static) nowait
    for (std::ptrdiff_t g = 0; g < ng; ++g) {
      const Index i = gathered_nodes_[g];
      Vec2 f = Vec2::Zero(), fd = Vec2::Zero();
      // Without beta fd stays +0, the sum of the kernel's zeros it replaces (bit-identical).
      for (Index k = gather_offset_[g]; k < gather_offset_[g + 1]; ++k) {
        const Index e = gather_entry_[k];
        f += sf[e];
        if (sdf) fd += sdf[e];
      }
      Vec2 fj = Vec2::Zero();
      for (Index k = gather_joint_offset_[g]; k < gather_joint_offset_[g + 1]; ++k) {
        const Index c = gather_joint_entry_[k];
        if (c & 1) fj -= jf[c >> 1];  // face b: minus face a's force, bit for bit as adding it negated
        else fj += jf[c >> 1];
      }
      n.a[i] += f + fd + fj;  // the force sum (Nodes::a)
      if (damped) damping_force_[i] += fd;
    }
#ifdef _OPENMP
    // The gathered nodes' time counts as if spent on the own run: the loop is static.
    own_split_.set_busy(thread, split && team > 1 ? StealingRuns::busy_for_own_run(omp_get_wtime() - busy_from,
                                                                                 own_bound_[th + 1] - own_bound_[th], own_done)
                                                  : omp_get_wtime() - busy_from);
#endif
    if (thread == 0) full_team = split;
  }
  if (threads > 1 && full_team) {
    shared_split_.rebalance();
    joint_split_.rebalance();
    own_split_.rebalance();
  }
  inverted_ = inverted != 0;
  if (joints) {
    energy_.joint_elastic = joint_buf_.energy();
    energy_.fracture_dissipated += joint_buf_.dissipation();
    broken_joints_ += broken_now;
    if (broken_now) record_new_breaks(n, J, time_);
  }
}

void Solver::set_stress_on_demand(bool on) {
  stress_on_demand_ = on;
  auto& tri = model_.triangles;
  if (on) {
    release_stress();
  } else if (tri.stress.size() != tri.size()) {  // the element loop writes them every step
    tri.stress.assign(tri.size(), Vec3::Zero());
    tri.strain.assign(tri.size(), Vec3::Zero());
  }
}

void Solver::compute_stress(std::vector<Vec3>& stress, std::vector<Vec3>& strain) const {
  const auto& tri = model_.triangles;
  stress.resize(tri.size());
  strain.resize(tri.size());
  // The element loop's kernel on the same inputs (positions unchanged since the step):
  // the same stress and strain bits. Damping does not enter the Cauchy stress.
#pragma omp parallel for schedule(static) if (parallel_)
  for (std::ptrdiff_t t = 0; t < ssize(tri.size()); ++t) {
    const fem::TriangleInput in = triangle_input(static_cast<std::size_t>(t));
    fem::TriangleResponse r;
    std::array<Vec2, 3> no_damping;
    fem::triangle_internal_force(in, elastic_[tri.material[t]], r, no_damping);
    stress[t] = r.cauchy;
    strain[t] = r.green;
  }
}

void Solver::update_stress() { compute_stress(model_.triangles.stress, model_.triangles.strain); }

void Solver::release_stress() {
  if (!stress_on_demand_) return;  // the steps write them
  std::vector<Vec3>().swap(model_.triangles.stress);
  std::vector<Vec3>().swap(model_.triangles.strain);
}

bool Solver::bonded(Index i, Index j) const {
  const auto& J = model_.joints;
  for (Index jt : triangle_joints_[i]) {
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
                                     [this](Index i, Index j) { return bonded(i, j); }, n.a,
                                     broken_joints_);  // bonded() changes only when a joint breaks
  energy_.contact_elastic = contact_stats_.elastic_energy;
  energy_.friction_dissipated += contact_stats_.friction_dissipation;
  energy_.contact_damping_dissipated += contact_stats_.damping_dissipation;
}

void Solver::set_viscous_boundary(std::vector<boundary::BoundaryNode> nodes,
                                  const std::vector<PrescribedDof>& previous_constraints) {
  for (auto& bn : nodes) {
    bn.u_ref = model_.nodes.u[bn.node];
    bn.static_force.setZero();
    for (const auto& d : previous_constraints)
      if (d.node == bn.node) bn.static_force[d.dir] += d.reaction_prev;
  }
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
      if (quake_h_.record) ff += boundary::free_field_column(boundary::IncidentWave::SV, quake_h_, bn.medium, bn.y, bn.H, tq);
      if (quake_v_.record) ff += boundary::free_field_column(boundary::IncidentWave::P, quake_v_, bn.medium, bn.y, bn.H, tq);
      F += boundary::free_field_input_force(bn.coef, bn.area, bn.normal, ff);
    }
    n.a[i] += F;  // the force sum (Nodes::a)
    // Everything the boundary does (springs, dashpots, input) is booked as external work.
    work += 0.5 * (boundary_force_prev_[k] + F).dot(n.u[i] - bn.u_prev);
    boundary_force_prev_[k] = F;
  }
  energy_.external_work += work;
}

void Solver::add_damping_forces() {
  const double alpha = settings_.alpha;
  if (alpha <= 0.0) return;
  auto& n = model_.nodes;
#pragma omp parallel for schedule(static) if (parallel_)
  for (std::ptrdiff_t i = 0; i < ssize(n.size()); ++i) {
    const Vec2 fd = -alpha * n.m[i] * n.v[i];
    n.a[i] += fd;
    damping_force_[i] += fd;
  }
}

void Solver::apply_constraints() {
  auto& n = model_.nodes;
  for (auto& d : constraints_) {
    // The reaction makes the node follow its prescribed acceleration.
    const double reaction = n.m[d.node] * prescribed_acceleration(d, time_) - n.a[d.node][d.dir];  // force sum
    n.a[d.node][d.dir] += reaction;
    energy_.external_work += 0.5 * (d.reaction_prev + reaction) * (n.u[d.node][d.dir] - d.u_prev);
    d.reaction_prev = reaction;
  }
}

void Solver::finish_velocities(std::size_t begin, std::size_t end) {
  auto& n = model_.nodes;
  const double dt = settings_.dt;
  for (std::size_t i = begin; i < end; ++i) {
    n.a[i] = n.m[i] > 0.0 ? Vec2(n.a[i] / n.m[i]) : Vec2(Vec2::Zero());  // force sum -> f/m, in place
    n.v[i] += 0.5 * dt * n.a[i];
  }
  // The prescribed velocities of these nodes, in list order (a later dof on the same node
  // and direction wins, as in one pass over the list).
  for (const auto& d : constraints_)
    if (on_nodes(d, begin, end)) n.v[d.node][d.dir] = prescribed_velocity(d, time_);
}

void Solver::update_energy(FinishVelocities finish) {
  auto& n = model_.nodes;
  const Vec2 g = settings_.gravity;
  // The node sums and the strain energy in one parallel region, fixed chunks:
  // deterministic. Each sum is accumulated on its own, so leaving the damping work out
  // changes no other sum; undamped, its terms would all be +0 and the sum +0. With
  // FinishVelocities::yes each thread first finishes the velocities of the nodes it sums
  // (node-local, so no barrier): one fork and join per step fewer than a loop of its own.
  auto prepare = [&](std::size_t begin, std::size_t end) {
    if (finish == FinishVelocities::yes) finish_velocities(begin, end);
  };
  auto strain = [&](std::size_t t) { return std::array<double, 1>{element_strain_energy_[t]}; };
  const std::size_t nt = element_strain_energy_.size();
  if (damped()) {
    const auto [node_sums, strain_sum] = deterministic_sums<3, 1>(
        n.size(), prepare,
        [&](std::size_t i) {
          return std::array<double, 3>{0.5 * n.m[i] * n.v[i].squaredNorm(), -n.m[i] * g.dot(n.u[i]),
                                       0.5 * (damping_force_prev_[i] + damping_force_[i]).dot(n.u[i] - u_prev_[i])};
        },
        nt, strain, reduction_scratch_, parallel_, node_chunks_);
    energy_.kinetic = node_sums[0];
    energy_.gravity_potential = node_sums[1];
    energy_.damping_dissipated -= node_sums[2];
    energy_.strain = strain_sum[0];
  } else {
    const auto [node_sums, strain_sum] = deterministic_sums<2, 1>(
        n.size(), prepare,
        [&](std::size_t i) {
          return std::array<double, 2>{0.5 * n.m[i] * n.v[i].squaredNorm(), -n.m[i] * g.dot(n.u[i])};
        },
        nt, strain, reduction_scratch_, parallel_, node_chunks_);
    energy_.kinetic = node_sums[0];
    energy_.gravity_potential = node_sums[1];
    energy_.strain = strain_sum[0];
  }
  std::swap(damping_force_prev_, damping_force_);
  release_damping_buffers_if_unused();
}

Vec2 Solver::reaction_on(const std::vector<Index>& nodes) const {
  Vec2 r = Vec2::Zero();
  for (const auto& d : constraints_)
    if (std::binary_search(nodes.begin(), nodes.end(), d.node)) r[d.dir] += d.reaction_prev;
  return r;
}

void Solver::check_stability() {
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
  // whose impulse is no work) or a slow drift does not.
  constexpr double kEnergyGrowthRatio = 0.1;
  constexpr double kEnergyGrowthRate = 1.15;
  constexpr int kEnergyGrowthSteps = 5;
  const double created = energy_.mechanical() - energy_.initial_total + energy_.dissipated() - energy_.external_work;
  const double in_play = std::max({std::abs(energy_.kinetic), std::abs(energy_.strain), std::abs(energy_.gravity_potential),
                                   std::abs(energy_.joint_elastic), std::abs(energy_.contact_elastic),
                                   std::abs(energy_.external_work), std::abs(energy_.dissipated()),
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

}  // namespace dsdem::solver
