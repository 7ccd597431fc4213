#pragma once
// The explicit time step of a 3D continuum (docs/theory.md §14): linear tetrahedra of
// St Venant-Kirchhoff or any bulk law that runs in 3D, lumped masses, gravity, Rayleigh
// damping and prescribed motions, advanced by the same velocity Verlet (integrator.hpp),
// node-force rule (node_forces.hpp), prescribed dofs (constraints.hpp), execution layer
// (exec/) and energy ledger (energy.hpp) as the plane solver. Joints, contact, water and
// the viscous boundary of the plane solver join it as they come to 3D.
#include <array>
#include <span>
#include <vector>

#include "boundary/boundary_setup3d.hpp"
#include "exec/team.hpp"
#include "fem/bulk_law.hpp"
#include "fem/tet4.hpp"
#include "io/checkpoint.hpp"
#include "model/model3d.hpp"
#include "solver/constraints.hpp"
#include "solver/energy.hpp"
#include "solver/node_forces.hpp"

namespace dsdem::solver {

// The largest safety factor of a 3D step: the altitude step h / cp can exceed a tetrahedron's
// own stability limit by up to 1.87 times, and half of it never does (docs/theory.md §2).
inline constexpr double kMaxSafety3D = 0.5;

struct StepSettings3 {
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);  // m/s^2
  double alpha = 0.0;  // Rayleigh mass coefficient, 1/s
  double beta = 0.0;   // Rayleigh stiffness coefficient, s
  // Cundall's local non-viscous damping coefficient (docs/theory.md §9), 0: none.
  double local_damping = 0.0;
  double dt = 0.0;     // s; 0: safety x the stable step (stable_time_step())
  double safety = 0.3; // of the stable step, when dt is 0; at most kMaxSafety3D
};

class Solver3 {
 public:
  // Throws std::invalid_argument for a material whose law does not run in 3D or whose
  // parameters it refuses.
  explicit Solver3(Model3& model);

  void set_settings(const StepSettings3& s);
  const StepSettings3& settings() const { return settings_; }
  // The Rayleigh mass coefficient from the next step on, 1/s (the factor of safety's
  // adaptive dynamic relaxation, docs/theory.md §9).
  void set_mass_damping(double alpha);
  double dt() const { return dt_; }
  // The stable step of the model as it is, s, as in 2D: the smallest altitude over cp, with
  // the stiffness damping's reduction (docs/theory.md §2, §6). Only kMaxSafety3D of it is
  // within every tetrahedron's own limit.
  double stable_time_step() const;
  void set_constraints(std::vector<PrescribedDof> dofs) { constraints_ = std::move(dofs); }
  const std::vector<PrescribedDof>& constraints() const { return constraints_; }

  // Viscous-spring boundary nodes for the coming stage (boundary_setup3d.hpp). Nodes that
  // were supported in the previous stage keep that support's reaction as a constant load,
  // and their springs start from the current displacement (docs/theory.md §6, stage 2).
  void set_viscous_boundary(std::vector<boundary::BoundaryNode3> nodes,
                            const std::vector<PrescribedDof>& previous_constraints);
  const std::vector<boundary::BoundaryNode3>& viscous_boundary() const { return boundary_; }
  // Earthquake input through the viscous-spring boundary (docs/theory.md §5, §14): SV waves
  // moving in x and in y and a P wave in z, each record may be null; time zero of the
  // records is `start_time`.
  void set_earthquake(const seismic::Accelerogram* x, const seismic::Accelerogram* y, const seismic::Accelerogram* z,
                      double incident_factor, double start_time);

  // Forces and accelerations at the current state, and the energy reference. Call once
  // before the first step.
  void initialise();
  // One explicit step of velocity Verlet (docs/theory.md §1). Throws InstabilityError
  // (solver.hpp) when a tetrahedron inverts or the state is no longer finite.
  void step();

  double time() const { return time_; }
  long step_count() const { return step_; }
  // The ledger at the current state (its Verlet offset an O(N) sum on each call).
  const EnergyLedger& energy() const;
  double kinetic_energy() const { return energy_.kinetic; }  // for per-step checks: no sum
  // The damping force (Rayleigh and local) each node took in the last step, N; empty when
  // no damping is on.
  std::span<const Vec3> damping_forces() const { return damping_force_prev_; }
  // Checkpoint of the whole state (bit-identical restart): restore() expects a solver set
  // up as the saved one (the same model, stage supports and boundary), after initialise().
  // Throws std::runtime_error naming the entry when the file belongs to another model.
  void save(io::CheckpointWriter& out) const;
  void restore(const io::CheckpointReader& in);
  Model3& model() { return model_; }
  const Model3& model() const { return model_; }
  // Sum of the reactions at the prescribed dofs of `nodes`, N.
  Vec3 reaction_on(std::span<const Index> nodes) const;
  // Cauchy stress and Green strain of every tetrahedron at the current state, into the
  // model's arrays (the step's kernel from the step's start: the same bits).
  void update_stress();
  // OpenMP on or off by hand (turns the automatic choice by timing off).
  void set_parallel(bool on) { team_.set_parallel(on); }
  // Bytes held by the model's and this solver's arrays (capacity), for the memory budget.
  std::size_t memory_bytes() const;
  bool parallel() const { return team_.parallel(); }

 private:
  // The phases of one step (docs/theory.md §1), in order.
  void begin_step();
  void kick_drift_and_restart_forces();  // 1-2
  void add_element_forces();             // 3: tetrahedra through their laws
  void add_boundary_forces();            // 6: viscous-spring boundary and seismic input
  void add_damping_forces();             // 7: Rayleigh mass part (the stiffness part is in 3)
  void apply_constraints();
  void finish_velocities();              // 8
  void update_energy();
  void check_stability() const;

  void setup_laws();
  bool damping_on() const { return settings_.alpha > 0.0 || settings_.beta > 0.0 || settings_.local_damping > 0.0; }
  void allocate_damping_buffers();
  // One tetrahedron's response from the state at the step's start; the end state to `end`.
  fem::TetResponse respond(std::size_t t, bool cauchy, std::array<Vec3, 4>& damping, double* end) const;
  // Node ranges of the node loops: contiguous, fixed for the model.
  std::size_t node_chunks() const;

  Model3& model_;
  exec::Team team_;
  NodeForcesD<3> forces_{model_.nodes.a};
  StepSettings3 settings_;
  double dt_ = 0.0;
  std::vector<PrescribedDof> constraints_;
  mutable EnergyLedger energy_;
  double time_ = 0.0;
  double kick_from_ = 0.0;
  long step_ = 0;
  double s_start_ = 0.0;  // sum m |a|^2 at initialise(): the Verlet offset's reference
  bool inverted_ = false;

  // Per material: its law's kernel, the position of its dissipation in the state record.
  struct MaterialLaw {
    fem::BulkLaw kernel;
    int dissipation = -1;
  };
  std::vector<MaterialLaw> laws_;
  bool any_law_state_ = false;
  std::size_t law_stride_ = 0;   // doubles per tetrahedron in the state records
  std::vector<double> law_start_, law_end_;  // the state at the step's start and end

  // Element forces before the node gather: each node sums its tetrahedra's forces in a
  // fixed order (node_tets_), so any thread count gives the same bits.
  std::vector<std::array<Vec3, 4>> tet_force_, tet_damping_;
  std::vector<double> tet_energy_;
  std::vector<Index> node_tet_start_;  // CSR over nodes: entries 4 t + k of the tetrahedra at the node
  std::vector<Index> node_tets_;
  // Damping forces (Rayleigh) of this and the previous step and the displacement before the
  // drift, per node: booked with drift_work; empty when undamped.
  std::vector<Vec3> damping_force_, damping_force_prev_, u_prev_;
  std::vector<double> scratch_;

  std::vector<boundary::BoundaryNode3> boundary_;
  std::vector<Vec3> boundary_force_prev_;
  std::array<boundary::IncidentMotion, 3> quake_{};  // SV in x, SV in y, P in z
  double quake_start_ = 0.0;
};

}  // namespace dsdem::solver
