#pragma once
// The explicit time step (DESIGN.md §1): one short named sequence of phases.
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include <memory>

#include "boundary/boundary_setup.hpp"
#include "contact/contact_forces.hpp"
#include "fem/cst.hpp"
#include "io/checkpoint.hpp"
#include "joint/joint_phase.hpp"
#include "model/model.hpp"
#include "model/work_split.hpp"
#include "solver/constraints.hpp"
#include "solver/energy.hpp"

namespace dsdem::solver {

// A run that went unstable: what, where and when.
class InstabilityError : public std::runtime_error {
 public:
  InstabilityError(const std::string& what, std::string kind, Index id, Vec2 position, long step, double time)
      : std::runtime_error(what), kind(std::move(kind)), id(id), position(position), step(step), time(time) {}
  std::string kind;  // "inverted_element", "non_finite", "energy_growth"
  Index id;
  Vec2 position;
  long step;
  double time;
};

constexpr std::size_t kParallelThreshold = 1000;

struct StepSettings {
  Vec2 gravity = Vec2(0.0, -9.81);
  double alpha = 0.0;  // Rayleigh mass coefficient, 1/s
  double beta = 0.0;   // Rayleigh stiffness coefficient, s
  double dt = 0.0;     // s
  bool failure = true; // joints may damage and break (false in a gravity stage)
};

// What controls the stable time step.
struct StableStep {
  double dt = 0.0;           // critical step (before the safety factor), s
  std::string controlled_by; // e.g. "triangle 12 (group rock) h = 0.1 m, cp = 3000 m/s"
  Index element = kNoIndex;
  Vec2 position = Vec2::Zero();
};
StableStep stable_time_step(const Model& model, double beta);
// Its parts (stable_time_step is the least of them, ties to the earlier part): the
// triangles' bulk limit, the contact springs' limit, and each intact joint's limit (the
// lesser of its two ends) in ascending order (ties by joint index; broken joints left
// out unless intact_only is false), for the time step that follows the joints as they
// break (Solver::set_time_step_rule).
StableStep triangle_step_limit(const Model& model, double beta);
StableStep contact_step_limit(const Model& model);
struct JointStepLimit {
  double dt = 0.0;  // s
  Index joint = kNoIndex;
  int end = 0;      // the end (0 or 1) that sets it
};
std::vector<JointStepLimit> joint_step_limits(const Model& model, bool intact_only = true);
StableStep describe_joint_limit(const Model& model, const JointStepLimit& limit);

class Solver {
 public:
  explicit Solver(Model& model);

  // Sizes the Rayleigh-damping buffers when alpha or beta > 0 (a stage start, not in the
  // time loop); an undamped run never holds them (issue 7, memory per element).
  void set_settings(const StepSettings& s);
  const StepSettings& settings() const { return settings_; }
  // Replaces the prescribed motions (a new stage); keeps the state.
  void set_constraints(std::vector<PrescribedDof> dofs);
  const std::vector<PrescribedDof>& constraints() const { return constraints_; }
  // Viscous-spring boundary nodes for the coming stage. Nodes that were supported in the
  // previous stage keep that support's reaction as a constant load, and their springs
  // start from the current displacement (DESIGN.md §6, stage 2).
  void set_viscous_boundary(std::vector<boundary::BoundaryNode> nodes,
                            const std::vector<PrescribedDof>& previous_constraints);
  const std::vector<boundary::BoundaryNode>& viscous_boundary() const { return boundary_; }
  // Earthquake input through the viscous-spring boundary (DESIGN.md §5); records may be
  // null; time zero of the records is `start_time`. Call with both null to switch it off.
  void set_earthquake(const seismic::Accelerogram* horizontal, const seismic::Accelerogram* vertical,
                      double incident_factor, double start_time);

  // The time step as the joints break (DESIGN.md §6: dt = safety x the stable step of
  // the model as it is): each step starts with dt = safety x min(fixed_limit, the limit of
  // the stiffest intact joint), taken again whenever joints broke. fixed_limit holds the
  // triangles' and contact springs' limits. Joints only break, so dt only grows, and a
  // state gives one dt whatever came before: a restart and any thread count take the same
  // steps. Also applied at once and after set_settings() / restore(), whose dt it replaces.
  void set_time_step_rule(double safety, double fixed_limit);
  bool has_time_step_rule() const { return step_rule_safety_ > 0.0; }
  // The intact joint that sets dt under the rule; null when fixed_limit does, or no rule.
  const JointStepLimit* time_step_joint() const;

  // Computes forces and accelerations at the current state without advancing, and sets
  // the energy reference. Call once before the first step.
  void initialise();
  // One explicit step of velocity Verlet (DESIGN.md §1).
  void step();

  // Checkpoint of the whole state (bit-identical restart). restore() expects a solver
  // built on the same model, with the stage's settings, constraints and boundary set.
  void save(io::CheckpointWriter& out) const;
  void restore(const io::CheckpointReader& in);

  double time() const { return time_; }
  long step_count() const { return step_; }
  const EnergyLedger& energy() const { return energy_; }
  EnergyLedger& energy() { return energy_; }
  Model& model() { return model_; }
  const Model& model() const { return model_; }
  // Reaction force on a group's constrained nodes (sum), N.
  Vec2 reaction_on(const std::vector<Index>& nodes) const;
  long broken_joints() const { return broken_joints_; }
  long active_contacts() const { return contact_stats_.active_contacts; }
  // Each thread's node chunks in this step's node loops (see node_chunks_); empty: the
  // equal shares of own_chunks().
  std::span<const std::size_t> node_chunks() const { return node_chunks_; }
  const contact::ContactStepStats& contact_stats() const { return contact_stats_; }
  const contact::ContactForces* contact() const { return contact_.get(); }
  // True when triangles i and j are still glued by an intact joint (no contact between them).
  bool bonded(Index i, Index j) const;
  // OpenMP on or off for this model's loops (default: on above kParallelThreshold
  // triangles). Results are bit-identical either way and for any thread count.
  // Setting it by hand turns the automatic choice below off.
  void set_parallel(bool on) {
    auto_parallel_ = false;
    use_parallel(on);
  }
  bool parallel() const { return parallel_; }
  // Triangles' stress and strain are output only: with on_demand the step leaves them
  // (the Cauchy stress is 3 % of a Dr2 step, issue 7) and the model holds no arrays
  // for them (48 B per triangle) except between update_stress(), which computes them
  // for the current state, the same as a step would have, and release_stress(). The
  // checkpoint computes its own. Off by default: every step writes them (sized here).
  void set_stress_on_demand(bool on);
  void update_stress();
  void release_stress();
  // Current positions and reference data of triangle t (no velocities, beta 0): the
  // element loop and update_stress() both start from it. Always inline: a call per
  // triangle returning the ~200-byte input through memory was 1.7 % of a late Dr2 step.
  [[gnu::always_inline]] fem::TriangleInput triangle_input(std::size_t t) const {
    const auto& n = model_.nodes;
    const auto& tri = model_.triangles;
    const auto& c = tri.conn[t];
    fem::TriangleInput in;
    for (int k = 0; k < 3; ++k) in.x[k] = n.X[c[k]] + n.u[c[k]];
    in.Dm_inv = tri.Dm_inv[t];
    in.area0 = tri.area0[t];
    in.thickness = model_.thickness;
    in.S0 = tri.initial_stress(t);
    return in;
  }
  // Large models on more than one thread choose between OpenMP and one thread by
  // timing both now and then (kProbeSteps steps each, every kProbeInterval steps), and
  // keep the faster: on a machine shared with other busy processes the threads of a
  // parallel region wait for each other at every barrier, and a run can be 10x slower
  // than on one thread (issue 7, Dr2 measured). Results are bit-identical either way.
  // A verdict for one thread is checked again after kRecheckInterval steps, then after
  // twice as many, and so on up to kProbeInterval (see probe_parallel).
  static constexpr long kProbeInterval = 4000;
  static constexpr long kRecheckInterval = 500;
  static constexpr int kProbeSteps = 8;
  // Steps run on one thread by the automatic choice (probe windows included): the run's
  // log reports them, so a run slowed by a busy machine says why.
  long serial_steps_chosen() const { return serial_steps_chosen_; }

 private:
  // Phases of one step, in order.
  // The step's kick and drift: begin_kick() (serial: the supports' and boundary's
  // displacements before the drift, time_ to the step's end), then kick_and_drift() on
  // node ranges that cover every node once: v(n+1/2), x(n+1), forces cleared to gravity,
  // prescribed motions.
  void begin_kick();
  void kick_and_drift(std::size_t begin, std::size_t end);
  void clear_forces();
  void add_gravity();
  // Triangles, objective CST (DESIGN.md §2), and cohesive joints, breaking for good
  // (DESIGN.md §3): one parallel region, per-element and per-joint force buffers
  // gathered per node in a fixed order (bit-identical for any thread count).
  enum class Kick : bool { no, first };
  // With Kick::first, kick_and_drift() on each thread's node chunks first, in the same region.
  void add_internal_and_joint_forces(Kick kick = Kick::no);
  void add_contact_forces();      // spheropolygons of zones A and C (DESIGN.md §4)
  void add_boundary_forces();     // viscous-spring boundary and free-field seismic input (DESIGN.md §5)
  void add_damping_forces();      // Rayleigh mass part (stiffness part is in the element loop)
  void apply_constraints();       // reactions at prescribed dofs
  // a(n+1) = f/m, v(n+1) and the prescribed velocities, of the nodes in [begin, end).
  void finish_velocities(std::size_t begin, std::size_t end);
  enum class FinishVelocities : bool { no, yes };
  // The energies; with FinishVelocities::yes, finish_velocities() first, in the same loop.
  void update_energy(FinishVelocities finish = FinishVelocities::no);
  void check_stability();

  // Damping buffers held: set_settings allocates them for a damped stage; update_energy
  // frees them after the first undamped step (its previous damping forces are then zero).
  bool damped() const { return !damping_force_.empty(); }
  void allocate_damping_buffers();
  void release_damping_buffers_if_unused();

  void use_parallel(bool on) {
    parallel_ = on;
    if (contact_) contact_->set_parallel(on);
  }
  void probe_parallel(double step_seconds);  // the automatic choice, after each step
  void release_setup_memory();               // after the first step (see solver.cpp)

  // Stress and strain of every triangle at the current state (update_stress, save).
  void compute_stress(std::vector<Vec3>& stress, std::vector<Vec3>& strain) const;

  void build_gather();

  Model& model_;
  // Small models run serially: a parallel region costs more than it saves there.
  bool parallel_ = false;
  bool auto_parallel_ = false;           // choose parallel_ by timing (see kProbeInterval)
  long probe_start_ = kProbeSteps;       // step at which the next probe starts (after a warm-up)
  std::array<double, kProbeSteps> probe_serial_{};    // step times of the window, s
  std::array<double, kProbeSteps> probe_parallel_{};
  long serial_steps_chosen_ = 0;
  bool setup_memory_released_ = false;  // after the first step of this solver (a restart's too)
  long serial_recheck_ = kRecheckInterval;  // steps to the next probe after a verdict for one thread
  StepSettings settings_;
  std::vector<PrescribedDof> constraints_;
  EnergyLedger energy_;
  double time_ = 0.0;
  double kick_from_ = 0.0;  // time_ at the step's start, while the kick runs (begin_kick)
  long step_ = 0;
  long broken_joints_ = 0;
  // The time-step rule (set_time_step_rule): joints by ascending limit, the first that may
  // be intact, and the broken count dt was last taken at (-1: take it at the next step).
  double step_rule_safety_ = 0.0;  // 0: no rule, settings_.dt as set
  double step_rule_fixed_ = 0.0;   // s
  std::vector<JointStepLimit> joint_limits_;
  std::size_t joint_limit_first_ = 0;
  long step_rule_broken_ = -1;
  void apply_time_step_rule();
  int energy_growth_steps_ = 0;  // consecutive steps with energy created beyond the work put in
  double created_prev_ = 0.0;    // energy created (not put in) at the previous step

  // Contact: driver, pair parameters. The contact phase reads the positions as X + u
  // (no copy of them: 16 B per node, issue 7).
  std::unique_ptr<contact::ContactForces> contact_;
  contact::ContactParamTable contact_params_;
  contact::ContactStepStats contact_stats_;
  // Joints per triangle (bonded(), and the own triangles' joint gather): up to 3, in
  // ascending joint order, then kNoIndex.
  std::vector<std::array<Index, 3>> triangle_joints_;

  // Viscous-spring boundary and earthquake.
  std::vector<boundary::BoundaryNode> boundary_;
  std::vector<Vec2> boundary_force_prev_;
  boundary::IncidentMotion quake_h_, quake_v_;
  double quake_start_ = 0.0;

  // Element and joint forces into the node force sums, deterministic for any thread
  // count without a force buffer per element nor an incidence per node where possible
  // (issue 7, memory): an "own" triangle, whose three nodes belong to no other triangle
  // (every triangle of a discrete zone), adds its element force and its joints' forces
  // (from joint_buf_, in joint order) to its nodes itself. The other, "shared" triangles
  // (continuous zones, or a triangle with more than 3 joints) write their forces into
  // shared_force_, and the nodes of shared triangles and the nodes of no triangle (the
  // "gathered" nodes) sum them, and their joints' forces, through incidence lists (CSR).
  // own_corners_[t]: kSharedTriangle for a shared triangle; for an own one, per joint
  // slot s of triangle_joints_[t], bits 5s..5s+4: the corner of the joint's end 0 (2
  // bits), of its end 1 (2 bits), and 1 when t is the joint's face b (minus the force).
  static constexpr std::uint16_t kSharedTriangle = 0x8000;
  std::vector<std::uint16_t> own_corners_;
  std::vector<Index> shared_triangles_;  // ascending; shared slot s = position here
  // Per shared slot: nodal forces; the stiffness-damping forces only while beta > 0.
  std::vector<std::array<Vec2, 3>> shared_force_;
  std::vector<std::array<Vec2, 3>> shared_damping_force_;
  std::vector<Index> gathered_nodes_;  // ascending
  // own_prefix_[t]: own triangles before triangle t (size + 1).
  std::vector<Index> own_prefix_;
  // The element loops' split between threads (model/work_split.hpp): each thread's share of
  // the shared triangles and of the joint blocks (before the barrier; each tuned on its own
  // loop's time) and of the own triangles (after it, with the gathered nodes), tuned each
  // step from the threads' busy times, and the index bounds they give. Which thread
  // computes a triangle or a joint changes no result.
  TunedSplit shared_split_, joint_split_, own_split_;
  std::vector<std::size_t> own_bound_;  // triangle index bounds of the own-triangle runs
  std::vector<std::size_t> joint_bound_;  // joint block bounds of the joint runs
  // The joint blocks' and own triangles' runs, claimed in chunks: a thread that ends its
  // own run takes what is left of the other's (one step's imbalance; the splits above
  // follow the threads' speeds over steps).
  StealingRuns joint_runs_, own_runs_;
  static constexpr std::size_t kOwnChunk = 32;  // own triangles per claim (~1-2 us of work)
  // Per gathered node: shared slot entries 3 s + corner (ascending triangle), joint
  // entries 2 (2 j + end) + side (ascending joint; side 1 = face b, negated).
  std::vector<Index> gather_offset_, gather_entry_;
  std::vector<Index> gather_joint_offset_, gather_joint_entry_;
  std::vector<double> element_strain_energy_;
  bool inverted_ = false;  // some element had det F <= 0 in the last element loop (check_stability finds it)
  bool stress_on_demand_ = false;
  // Joints: per-joint forces (face a; face b gets their negatives) before the gathers.
  JointPhaseBuffers joint_buf_;
  // Damping forces of the previous and current step and the displacement before the
  // drift (trapezoidal work of the damping), per node; empty when undamped (see damped()).
  // Constrained and boundary nodes keep their own u_prev (PrescribedDof, BoundaryNode).
  std::vector<Vec2> damping_force_, damping_force_prev_;
  std::vector<Vec2> u_prev_;
  std::vector<double> reduction_scratch_;
  // The node chunks (kReductionChunk) of each thread in the node loops of this step (the
  // kick and drift, the velocities, the node sums), T + 1 bounds; empty: own_chunks().
  // From the contact phase's last partition (ContactForces::node_split): each thread then
  // kicks the nodes its contact pairs read (issue 7: on late Dr2 the second thread's first
  // ~350 triangles' nodes were kicked by the other core).
  std::vector<std::size_t> node_chunks_;
  void refresh_node_chunks(int threads);
  std::vector<fem::ElasticConstants> elastic_;
};

}  // namespace dsdem::solver
