#pragma once
// The explicit time step (docs/theory.md §1): one short named sequence of phases.
#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "boundary/boundary_setup.hpp"
#include "contact/contact_forces.hpp"
#include "exec/element_region.hpp"
#include "exec/node_scatter.hpp"
#include "exec/team.hpp"
#include "fem/cst.hpp"
#include "fem/bulk_law.hpp"
#include "io/checkpoint.hpp"
#include "joint/joint_phase.hpp"
#include "model/model.hpp"
#include "solver/constraints.hpp"
#include "solver/energy.hpp"
#include "solver/integrator.hpp"
#include "solver/node_forces.hpp"
#include "solver/time_step.hpp"
#include "solver/water_loads.hpp"
#include "sph/fluid.hpp"
#include "sph/solid_coupling.hpp"

namespace dsdem::solver {

// A run that went unstable: what, where and when.
class InstabilityError : public std::runtime_error {
 public:
  InstabilityError(const std::string& what, std::string kind, Index id, Vec2 position, long step, double time)
      : std::runtime_error(what), kind(std::move(kind)), id(id), position(position), step(step), time(time) {}
  // In a 3D model: the position with its z.
  static InstabilityError in_3d(const std::string& what, std::string kind, Index id, const Vec3& position, long step,
                                double time) {
    InstabilityError e(what, std::move(kind), id, Vec2(position.x(), position.y()), step, time);
    e.z = position.z();
    e.three_d = true;
    return e;
  }
  std::string kind;  // "inverted_element", "non_finite", "energy_growth", "water_unsound"
  Index id;
  Vec2 position;
  double z = 0.0;        // m, the position's z in a 3D model
  bool three_d = false;  // thrown by a 3D model
  long step;
  double time;
};

constexpr std::size_t kParallelThreshold = 1000;

struct StepSettings {
  Vec2 gravity = Vec2(0.0, -9.81);
  double alpha = 0.0;  // Rayleigh mass coefficient, 1/s
  double beta = 0.0;   // Rayleigh stiffness coefficient, s
  // The step, s: asked for by set_settings; settings().dt is the step in use, which the
  // time-step control decides (the fixed step, or its rule).
  double dt = 0.0;
  bool failure = true; // joints may damage and break (false in a gravity stage)
  // Cundall's local non-viscous damping coefficient (docs/theory.md §9), 0: none. The
  // quasi-static solver of strength reduction; a dynamic stage never takes it.
  double local_damping = 0.0;
};

class Solver {
 public:
  explicit Solver(Model& model);

  // Sizes the Rayleigh-damping buffers when alpha or beta > 0 (a stage start, not in the
  // time loop); an undamped run never holds them.
  void set_settings(const StepSettings& s);
  const StepSettings& settings() const { return settings_; }
  // The Rayleigh mass coefficient alone, 1/s, from the next step on (the quasi-static
  // trials adapt it to the response, docs/theory.md §9); the rest of the settings stay.
  void set_mass_damping(double alpha);
  double dt() const { return settings_.dt; }
  // Replaces the prescribed motions (a new stage); keeps the state.
  void set_constraints(std::vector<PrescribedDof> dofs);
  const std::vector<PrescribedDof>& constraints() const { return constraints_; }
  // Viscous-spring boundary nodes for the coming stage. Nodes that were supported in the
  // previous stage keep that support's reaction as a constant load, and their springs
  // start from the current displacement (docs/theory.md §6, stage 2).
  void set_viscous_boundary(std::vector<boundary::BoundaryNode> nodes,
                            const std::vector<PrescribedDof>& previous_constraints);
  const std::vector<boundary::BoundaryNode>& viscous_boundary() const { return boundary_; }
  // Earthquake input through the viscous-spring boundary (docs/theory.md §5); records may be
  // null; time zero of the records is `start_time`. Call with both null to switch it off.
  void set_earthquake(const seismic::Accelerogram* horizontal, const seismic::Accelerogram* vertical,
                      double incident_factor, double start_time);

  // Water at rest for the coming stage (docs/theory.md §8), or none from now.
  void set_water(WaterSetup w);
  void clear_water();
  const WaterLoads& water() const { return water_; }

  // Moving water (docs/theory.md §11): SPH water whose riding boundary particles sit on the
  // model's edges `edges` (their `edge` indexes it; sph::lay_edge_particles lays them), from
  // now on, two ways: the water's force reaches the edges' nodes each step (phase 5b) and
  // the nodes move its walls. Call before initialise(). The fluid's own thread choice is
  // its own (sph::Fluid::set_parallel); it is bit-identical either way.
  void set_moving_water(sph::Fluid fluid, std::vector<sph::SolidEdge> edges);
  const sph::Fluid* moving_water() const { return moving_ ? &moving_->fluid : nullptr; }
  sph::SolidCoupling* moving_water_coupling() { return moving_ ? &moving_->coupling : nullptr; }

  // The time step as the joints break (TimeStepControl::set_rule): applied at once and
  // after set_settings() / restore(), whose dt it replaces.
  void set_time_step_rule(double safety, double fixed_limit);
  bool has_time_step_rule() const { return time_step_.has_rule(); }
  const TimeStepControl& time_step_control() const { return time_step_; }
  // The intact joint that sets dt under the rule; null when fixed_limit does, or no rule.
  const JointStepLimit* time_step_joint() const { return time_step_.controlling_joint(); }

  // Computes forces and accelerations at the current state without advancing, and sets
  // the energy reference. Call once before the first step.
  void initialise();
  // One explicit step of velocity Verlet (docs/theory.md §1).
  void step();

  // Checkpoint of the whole state (bit-identical restart). restore() expects a solver
  // built on the same model, with the stage's settings, constraints and boundary set, and
  // moving water (if any) set as the saved run's, from a freshly laid-out fluid.
  void save(io::CheckpointWriter& out) const;
  void restore(const io::CheckpointReader& in);

  double time() const { return time_; }
  long step_count() const { return step_; }
  // The ledger at the current state. Its Verlet kinetic offset is brought up to date on
  // the first read after a step (an O(N) sum; see VerletOffset).
  const EnergyLedger& energy() const {
    if (!offset_settled_) settle_verlet_offset();
    return energy_;
  }
  // The full step's kinetic energy, for per-step checks: no O(N) sum.
  double kinetic_energy() const { return energy_.kinetic; }
  Model& model() { return model_; }
  const Model& model() const { return model_; }
  // Reaction force on a group's constrained nodes (sum), N.
  Vec2 reaction_on(const std::vector<Index>& nodes) const;
  long broken_joints() const { return broken_joints_; }
  // The damping force (Rayleigh and local) each node took in the last step, N; empty when
  // the step was undamped. The unbalanced force of a node is m a less this.
  std::span<const Vec2> damping_forces() const { return damping_force_prev_; }
  long active_contacts() const { return contact_stats_.active_contacts; }
  // Each thread's node chunks in this step's node loops; empty: equal shares.
  std::span<const std::size_t> node_chunks() const { return team_.node_chunks(); }
  const contact::ContactStepStats& contact_stats() const { return contact_stats_; }
  const contact::ContactForces* contact() const { return contact_.get(); }
  // True when triangles i and j are still glued by an intact joint (no contact between them).
  bool bonded(Index i, Index j) const;
  // OpenMP on or off for this model's loops (default: on above kParallelThreshold
  // triangles, chosen by timing now and then; exec::Team). Results are bit-identical
  // either way and for any thread count. Setting it by hand turns the automatic choice off.
  void set_parallel(bool on) {
    team_.set_parallel(on);
    if (contact_) contact_->set_parallel(on);
  }
  bool parallel() const { return team_.parallel(); }
  static constexpr int kProbeSteps = exec::Team::kProbeSteps;
  // Steps run on one thread by the automatic choice (probe windows included): the run's
  // log reports them, so a run slowed by a busy machine says why.
  long serial_steps_chosen() const { return team_.serial_steps_chosen(); }
  // Triangles' stress and strain are output only: with on_demand the step leaves them and
  // the model holds no arrays for them except between update_stress(), which computes
  // them for the current state, the same as a step would have, and release_stress(). The
  // checkpoint computes its own. Off by default: every step writes them (sized here).
  void set_stress_on_demand(bool on);
  void update_stress();
  void release_stress();
  // Current positions and reference data of triangle t (no velocities, beta 0): the
  // element kernel's input in the step and in update_stress(). Always inline: a call per
  // triangle would return the ~200-byte input through memory.
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

 private:
  // The phases of one step (docs/theory.md §1), in order; step() calls each once.
  void begin_step();                   // dt from the time-step control; the clock advanced
  void kick_drift_and_restart_forces();  // 1-2: velocity Verlet's first half, forces restart at gravity
  void add_element_and_joint_forces();   // 3-4: triangles (§2) and cohesive joints (§3)
  void add_contact_forces();           // 5: spheropolygons of zones A and C (§4)
  void add_moving_water_forces();      // 5b: SPH water on the exposed edges (§11)
  void add_boundary_forces();          // 6: viscous-spring boundary and seismic input (§5)
  void add_damping_forces();           // 7: local and Rayleigh mass parts (the stiffness part is in 3)
  void apply_constraints();            // reactions at prescribed dofs
  void finish_velocities();            // 8: a = f/m, velocity Verlet's second half
  // The energy ledger but its Verlet kinetic offset, which energy() settles.
  void update_energy();
  void check_stability();
  [[noreturn]] void throw_water_unsound() const;
  void end_step();

  // initialise(): phases 2-7 at the current state, unfused.
  void clear_forces();
  void add_gravity();

  // Node passes handed to the execution layer (exec::Team::defer_node_pass): the region
  // that runs them is the execution layer's choice; these say only what one node range does.
  void kick_drift_nodes(std::size_t begin, std::size_t end);
  void finish_velocity_nodes(std::size_t begin, std::size_t end);
  struct KickPass {
    Solver* solver;
    void operator()(std::size_t b, std::size_t e) const { solver->kick_drift_nodes(b, e); }
  };
  struct FinishPass {
    Solver* solver;
    void operator()(std::size_t b, std::size_t e) const { solver->finish_velocity_nodes(b, e); }
  };
  KickPass kick_pass_{this};
  FinishPass finish_pass_{this};
  // The per-item kernels of the element region (exec::ElementRegion), in solver_elements.cpp.
  template <bool Damping, bool LawState, bool Water, bool StoreStress>
  friend struct ElementKernels;

  // Damping buffers held: set_settings allocates them for a damped stage; update_energy
  // frees them after the first undamped step (its previous damping forces are then zero).
  bool damped() const { return !damping_force_.empty(); }
  bool damping_on() const { return settings_.alpha > 0.0 || settings_.beta > 0.0 || settings_.local_damping > 0.0; }
  void allocate_damping_buffers();
  void release_damping_buffers_if_unused();

  void release_setup_memory();  // after the first step (see solver.cpp)

  // The checkpoint's parts (solver_checkpoint.cpp).
  void save_nodes(io::CheckpointWriter& out) const;
  void save_triangles(io::CheckpointWriter& out) const;
  void save_joints(io::CheckpointWriter& out) const;
  void save_supports(io::CheckpointWriter& out) const;  // constraints, boundary, earthquake, stability watch
  void save_contact(io::CheckpointWriter& out) const;
  void save_moving_water(io::CheckpointWriter& out) const;
  void restore_nodes(const io::CheckpointReader& in);
  void restore_triangles(const io::CheckpointReader& in);
  void restore_joints(const io::CheckpointReader& in);
  void restore_supports(const io::CheckpointReader& in);
  void restore_contact(const io::CheckpointReader& in);
  void check_moving_water(const io::CheckpointReader& in) const;  // before anything is restored
  void restore_moving_water(const io::CheckpointReader& in);

  // Stress and strain of every triangle at the current state (update_stress, save).
  void compute_stress(std::vector<Vec3>& stress, std::vector<Vec3>& strain) const;

  Model& model_;
  exec::Team team_;
  NodeForces forces_{model_.nodes.a};  // every phase's forces into the force sum
  TimeStepControl time_step_;
  bool setup_memory_released_ = false;  // after the first step of this solver (a restart's too)
  StepSettings settings_;
  std::vector<PrescribedDof> constraints_;
  mutable EnergyLedger energy_;  // mutable: energy() settles its verlet_kinetic_offset
  double time_ = 0.0;
  double kick_from_ = 0.0;  // time_ at the step's start (begin_step)
  long step_ = 0;
  long broken_joints_ = 0;
  int energy_growth_steps_ = 0;  // consecutive steps with energy created beyond the work put in
  double created_prev_ = 0.0;    // energy created (not put in) at the previous step
  // Velocity Verlet's kinetic offset (EnergyLedger::verlet_kinetic_offset) is the sum of each
  // step's dt^2/8 (S(n+1) - S(n)), S = sum m |a|^2 (docs/theory.md §7). Over steps of one dt it
  // telescopes, so S is summed only where dt changes and when the ledger is read: the
  // offset is the closed segments' sum plus dt^2/8 (S - s_start) of the open one.
  struct VerletOffset {
    double closed = 0.0;   // J/m: the segments before the open one
    double s_start = 0.0;  // S at the open segment's start
    double dt = 0.0;       // the open segment's step, s (0 before initialise(): books nothing)
  };
  VerletOffset verlet_offset_;
  mutable bool offset_settled_ = false;  // energy_.verlet_kinetic_offset is that of the current state
  double mass_accel2() const;            // S at the current state, summed in node order
  // Closes the open segment at the current state and opens one with step dt.
  void restart_verlet_segment(double dt);
  void settle_verlet_offset() const;

  // Contact: driver, pair parameters. The contact phase reads the positions as X + u.
  std::unique_ptr<contact::ContactForces> contact_;
  contact::ContactParamTable contact_params_;
  contact::ContactStepStats contact_stats_;

  // Viscous-spring boundary and earthquake.
  std::vector<boundary::BoundaryNode> boundary_;
  std::vector<Vec2> boundary_force_prev_;
  boundary::IncidentMotion quake_h_, quake_v_;
  double quake_start_ = 0.0;

  // Element and joint forces into the node sums (exec::NodeScatter) in one region per
  // step (exec::ElementRegion).
  exec::NodeScatter scatter_;
  exec::ElementRegion element_region_;
  std::vector<double> element_strain_energy_;
  bool inverted_ = false;  // some element had det F <= 0 in the last element loop (check_stability finds it)
  bool stress_on_demand_ = false;
  // Joints: per-joint forces (face a; face b gets their negatives) before the scatter.
  JointPhaseBuffers joint_buf_;
  // Damping forces of the previous and current step and the displacement before the
  // drift (trapezoidal work of the damping), per node; empty when undamped (see damped()).
  // Constrained and boundary nodes keep their own u_prev (PrescribedDof, BoundaryNode).
  std::vector<Vec2> damping_force_, damping_force_prev_;
  std::vector<Vec2> u_prev_;
  std::vector<double> reduction_scratch_;
  std::vector<fem::ElasticConstants> elastic_;
  // Water at rest (the element kernels add its forces); its work is booked except in
  // initialise(), where no step is taken.
  WaterLoads water_;
  bool water_booking_ = true;
  // Moving water: the fluid, its coupling to the edges' nodes, and per coupled node (in
  // the coupling's order) the force of the last step and the displacement at its end (the
  // drift_work of the next step).
  struct MovingWater {
    sph::Fluid fluid;
    sph::SolidCoupling coupling;
    std::vector<Vec2> force_prev, u_prev;
    sph::Fluid::Energy start;  // the fluid's energy when it was set
    double waiting = 0.0;      // s: solid time since the water last advanced, its forces held
  };
  std::unique_ptr<MovingWater> moving_;
  void apply_moving_water_forces(bool book);
  double water_work_sum();  // J/m: this step's work of the water forces

  // The bulk laws (fem/bulk_law.hpp), per material: the kernel the element loop
  // dispatches to and the columns of Triangles::state that hold the state its law
  // declares. The model's state arrays hold each triangle's state at the end of the last
  // step; law_start_ the state at its start, from which the step's
  // update is taken (so the update is a function of the step's start: stress on demand and
  // a restart give the same bits).
  struct MaterialLaw {
    fem::BulkLaw kernel;
    std::array<Index, fem::kMaxBulkState> columns{};
    Index dissipation = kNoIndex;  // the column of the accumulated plastic work, if any
  };
  std::vector<MaterialLaw> laws_;
  bool any_law_state_ = false;  // some triangle's law has state (the element passes dispatch)
  std::size_t law_stride_ = 0;  // the most state variables of a law in use (the checkpoint's record)
  std::vector<double> law_start_;  // law_stride_ doubles per triangle
  void setup_laws();
  void commit_law_state();       // the last step's end state becomes this step's start
  double law_dissipation_sum();  // J/m: the accumulated plastic work of all triangles
  std::vector<double> plastic_scratch_;
};

}  // namespace dsdem::solver
