#pragma once
// Weakly compressible SPH water in the vertical plane (docs/theory.md §11): fluid particles,
// boundary particles that make the walls (the dynamic boundary condition: their density
// follows the continuity equation and their pressure pushes the fluid back), an O(N) cell
// list, and a velocity-Verlet step with the density advanced like a position:
//   v(n+1/2) = v(n) + dt/2 a(n);  x(n+1) = x(n) + dt v(n+1/2);
//   rho(n+1) = rho(n) + dt Drho(x(n+1), v(n+1/2));  a(n+1) from x, rho (n+1), v(n+1/2);
//   v(n+1) = v(n+1/2) + dt/2 a(n+1).
// The pressure waves (rho from v, v from rho) are then integrated by the Stormer-Verlet
// scheme, stable for dt below the acoustic limit, in the same kick-drift-kick order as the
// solid's integrator, so that a coupled step can run the two side by side.
// Each particle gathers its sums over its fluid partners within the support, picked out of
// a Verlet list (support plus a skin) in ascending index and summed in a fixed order
// (pair_lanes.hpp), and over the walls: the same bits for any thread count and whenever the
// lists were built. Nothing allocates in the time loop once the grid stopped growing.
#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "exec/team.hpp"
#include "model/types.hpp"
#include "sph/cell_list.hpp"
#include "sph/pair_lanes.hpp"
#include "sph/particles.hpp"

namespace dsdem::sph {

// How the boundary particles get their density. Dynamic (Crespo et al. 2007): the
// continuity equation, as for the fluid. Modified dynamic (English et al. 2022): extrapolated
// from the fluid around the particle's ghost node, its mirror image across the wall face,
// with a first-order consistent (Liu & Liu 2006) interpolation; the wall then holds the
// fluid at its face, with no gap and the hydrostatic pressure on it.
enum class BoundaryCondition { Dynamic, ModifiedDynamic };

// The density diffusion. Fourtakas et al. (2019): Molteni & Colagrossi's term less Tait's
// hydrostatic density difference. DeltaSph (Antuono et al. 2010; Marrone et al. 2011): less
// the renormalised density gradient, so that any linear density field is left alone (with
// the (p_i + p_j) pressure form, the layer under the free surface settles off Tait's
// hydrostatics, and Fourtakas' term keeps stirring it).
enum class DensityDiffusion { Fourtakas, DeltaSph };

// The artificial viscosity between the water and its walls (docs/theory.md §11, "Walls").
// NoSlip: Monaghan's term along r_ib with the wall's velocity, as between two fluid
// particles: the wall holds the water still at its face, a viscous layer of alpha h c0 / 8
// (2000 times water's at dp = 0.025 m) about a particle thick. FreeSlip: the term along the
// wall's normal alone (wall_normal_viscosity): it resists the approach through the face, not
// the sliding along it.
enum class WallViscosity { NoSlip, FreeSlip };

struct FluidParameters {
  double rho0 = 1000.0;   // kg/m^3, the rest density
  double dp = 0.0;        // m, the initial particle spacing
  double h_over_dp = 1.5; // smoothing length h in units of dp (docs/theory.md §11: 1.3-2)
  double c0 = 0.0;        // m/s, the numerical speed of sound (>= 10 max(sqrt(g H), v_max))
  double alpha = 0.02;    // artificial viscosity (docs/theory.md §11: 0.01-0.1)
  double delta = 0.1;     // density diffusion coefficient
  DensityDiffusion diffusion = DensityDiffusion::DeltaSph;
  Vec2 gravity{0.0, -9.81};
  double cfl = 0.2;       // dt <= cfl h / (c0 + v_max)
  int resort_interval = 16;  // steps between re-sorts of the fluid arrays by cell
  // The neighbour lists' skin in units of h: candidates within 2h + skin, rebuilt once a
  // particle moved half of it. Speed only: the results do not depend on it. 0.3: at a
  // tenth of c0 a particle moves half of it in ~8 steps at CFL 0.2 (the re-sort interval's
  // order), for 1.3 times the neighbours as candidates.
  double verlet_skin = 0.3;
  BoundaryCondition boundary = BoundaryCondition::ModifiedDynamic;
  WallViscosity wall_viscosity = WallViscosity::NoSlip;
  // Particles that leave the weakly compressible range (sound()) are taken out of the water,
  // up to this fraction of the particles the fluid was built with (DualSPHysics excludes
  // them likewise, by density and position): a particle flung out of a squeeze does not end
  // the run, many do. 0: none; the first such particle makes the fluid unsound.
  double excluded_limit = 0.0;

  double h() const { return h_over_dp * dp; }
  double mass() const { return rho0 * dp * dp; }  // kg/m: one particle's area times rho0
};

// The sound speed of docs/theory.md §11 for water depth H and an expected largest speed.
double sound_speed_for(double depth, double v_max, double g);

class Fluid;
// Brings freshly laid-out water to rest for `duration` s with its walls held still: the
// velocities damped at `rate` (1/s) throughout, the particles packed (Fluid::set_packing)
// over the first half so that the lattice fills the gaps it leaves against slanted walls,
// the second half damped alone; the walls' work is counted from its end. Returns the
// largest particle speed at the end, m/s.
double settle(Fluid& fluid, double duration, double rate);

class Fluid {
 public:
  // Throws std::invalid_argument on non-positive dp, h, c0 or rho0.
  Fluid(const FluidParameters& parameters, FluidParticles fluid, BoundaryParticles boundary, bool parallel = false);

  void set_parallel(bool on) { team_.set_parallel(on); }

  // The room each particle's neighbour lists keep: 1.6 times a square lattice's neighbours
  // within the support and skin (the water compresses by a few per cent at most).
  static std::size_t neighbour_capacity(const FluidParameters& parameters);
  // The memory a fluid particle takes in a Fluid (its state, lists, records and scratch), bytes:
  // for sizing a run before its water is laid out.
  static std::size_t bytes_per_particle(const FluidParameters& parameters);

  // The largest stable step for the current state (docs/theory.md §11).
  double stable_dt() const;
  // Advances by dt_outer in n equal sub-steps no longer than stable_dt(); returns n. This
  // is how a solid step larger than the fluid's limit drives the water.
  int advance(double dt_outer);
  // The n of advance(dt_outer) at the current state.
  int substeps(double dt_outer) const;
  // One step of length dt.
  void step(double dt);
  // A damping of every fluid velocity at `rate` (1/s), v multiplied by exp(-rate dt) each
  // step, until set back to 0. Not a physical force: for bringing a freshly laid-out body of
  // water to rest before the run, and for a damped stage's mass-proportional damping.
  void set_settling_damping(double rate) { damping_rate_ = rate; }
  double settling_damping() const { return damping_rate_; }
  // Packing while the water settles: after each step every particle away from the free
  // surface moves down its concentration gradient by `coefficient` h^2 grad C, at most dp / 10
  // (particle shifting, Lind et al. 2012; grad C over the fluid and wall partners), its
  // density carried along delta-SPH's density gradient, so that a lattice laid against a
  // slanted wall fills the gap it leaves there. Not a physical motion: for settle() only,
  // before a run. 0: off.
  void set_packing(double coefficient) { packing_ = coefficient; }
  double packing() const { return packing_; }

  // The water's force on each boundary particle (N/m), the reaction of the pressure and
  // viscous terms it puts on its fluid neighbours at the last force evaluation (Newton's
  // third law pair by pair): what a coupled solid takes back to its nodes through the
  // edge's shape functions. fx, fy: boundary().size() each. A gather per boundary particle:
  // the same bits for any thread count.
  void boundary_forces(std::span<double> fx, std::span<double> fy) const;
  // Recording: each step also keeps boundary_forces() at the state of its force evaluation
  // (the positions, densities and half-step velocities that gave the fluid's
  // accelerations), so that the recorded forces are minus the walls' forces on the fluid
  // pair by pair. Turning it on sizes the arrays and records the current state.
  void set_record_boundary_forces(bool on);
  std::span<const double> recorded_boundary_force_x() const { return rec_fx_; }
  std::span<const double> recorded_boundary_force_y() const { return rec_fy_; }

  // The water's energy per unit width (J/m): kinetic, gravity potential -m g.x (from the
  // origin) and the compression stored by Tait's equation of state,
  // m B (rho^6 / (6 rho0^7) + 1 / rho - 7 / (6 rho0)) per particle (the integral of p / rho^2).
  // Serial sums in the particles' order.
  struct Energy {
    double kinetic = 0.0, potential = 0.0, compression = 0.0;
    double total() const { return kinetic + potential + compression; }
  };
  Energy energy() const;

  // A particle taken out of the water (FluidParameters::excluded_limit): its id, when,
  // where, its speed and density, and the energy it took with it (kinetic, potential
  // -m g.x and compression, as energy() counts them).
  struct ExcludedParticle {
    std::int32_t id = 0;
    double time = 0.0, x = 0.0, y = 0.0, speed = 0.0, density = 0.0;
    double energy = 0.0;  // J/m
  };
  // In the order they were taken out; their energies summed are excluded_energy().
  std::span<const ExcludedParticle> excluded() const { return excluded_; }
  double excluded_energy() const;
  // The particle count the fluid was built with (the excluded ones included).
  std::size_t initial_size() const { return initial_size_; }
  // The most particles that may be taken out: excluded_limit of initial_size(), rounded down.
  std::size_t excluded_capacity() const;
  // The particles out of the weakly compressible range now (0 while sound()).
  std::size_t unsound_count() const;
  // The work the walls' own pressure has done on the water since the fluid was built or its
  // settle() ended (J/m):
  // with the modified dynamic boundary the extrapolated wall density follows no continuity
  // equation, so the pressure term of the fluid-wall pairs does work no state stores. It is
  // -m_b p_j / rho_j^2 D_j summed over the walls, D_j the continuity rate the wall would have
  // (as the dynamic boundary integrates it), at each step's start. Zero with the
  // dynamic boundary, whose walls store it as compression. The water's energy gain less the
  // solid's work on it and this stays at or below zero (viscosity and diffusion dissipate).
  double boundary_work() const { return boundary_work_; }
  // Counts the walls' work from now (settle(): its motion is not the run's).
  void reset_boundary_work() { boundary_work_ = 0.0; }

  double time() const { return time_; }
  long steps() const { return steps_; }
  // The step count when the neighbour lists were last built (diagnostics and tests: the
  // results do not depend on it).
  long neighbour_lists_built_at() const { return vl_built_at_; }
  const FluidParameters& parameters() const { return par_; }
  const FluidParticles& fluid() const { return f_; }
  const BoundaryParticles& boundary() const { return b_; }
  // For a driver that moves the walls (a coupled solid): positions and velocities may be
  // changed between steps; the next step's cell lists see them. Not the particle count.
  BoundaryParticles& moving_boundary() { return b_; }
  double max_speed() const { return v_max_; }
  // Whether every fluid particle is within the weakly compressible range after the last
  // step: finite, no faster than c0, density within (1 +- kSoundRange) rho0. Off it the water
  // no longer models water (a squeeze no flow can leave, an unstable step);
  // first_unsound_particle() names one (its index; size() when none).
  static constexpr double kSoundRange = 0.5;
  bool sound() const { return sound_; }
  std::size_t first_unsound_particle() const;
  // Whether boundary particle b was within reach of the water at the last cell update
  // (near enough for a fluid particle to be within the support of it or of its ghost
  // node): binned in the walls' cells. The others are skipped by the step's wall loops.
  bool wall_active(std::size_t b) const { return boundary_cells_.cell(b) >= 0; }

  // Everything a step reads from the steps before (a checkpoint; fluid_state.cpp): the
  // particles in their current order, the clock, the step count (it times the re-sorts),
  // the step control's maxima, the settling damping and the recorded boundary forces.
  struct State {
    FluidParticles fluid;
    BoundaryParticles boundary;
    double time = 0.0, v_max = 0.0, a_max = 0.0, damping_rate = 0.0;
    double boundary_work = 0.0;
    long steps = 0;
    bool record = false;
    std::vector<double> rec_fx, rec_fy;
    std::vector<ExcludedParticle> excluded;
  };
  State state() const;
  // Puts a state() back into a fluid built with the same parameters, particle counts (its
  // particles and the excluded ones) and walls (the boundary particles' edges); the next
  // step continues bit-identically.
  // Throws std::invalid_argument naming what differs.
  void restore(const State& s);

 private:
  void update_cells();
  void resort_fluid();
  void rebuild_neighbour_lists();
  bool neighbour_lists_stale() const;
  std::size_t chunks() const;
  void density_rates();
  template <bool fourtakas>
  void fluid_density_rates();
  template <bool fourtakas>
  void density_within(std::size_t lo, std::size_t hi);
  void density_from_walls(std::size_t lo, std::size_t hi);
  void update_densities(double dt);
  void update_boundary_densities(double dt);
  void extrapolate_boundary_densities();
  void accelerations();
  template <bool grad>
  void fluid_accelerations();
  template <bool grad>
  void forces_within(std::size_t lo, std::size_t hi);
  template <bool grad>
  void finish_accelerations(std::size_t lo, std::size_t hi);
  DensityPairConstants density_constants() const;
  ForcePairConstants force_constants() const;
  void update_maxima();
  bool particle_sound(std::size_t i) const;
  void exclude_unsound_particles();
  // Every per-particle array of doubles of f_ (the ids aside): what a re-sort permutes and an
  // exclusion closes up.
  std::array<std::vector<double>*, 12> particle_arrays();
  // Particle i's share of energy(); r7 = rho0^7, e0 = 7 / (6 rho0).
  Energy particle_energy(std::size_t i, double r7, double e0) const;
  void pack_particles();
  void pack_density_records();
  void pack_force_records();
  DensityPoint density_point(std::size_t i) const {
    return {f_.x[i], f_.y[i], f_.vx[i], f_.vy[i], f_.rho[i], f_.gx[i], f_.gy[i]};
  }
  ForcePoint force_point(std::size_t i) const { return {f_.x[i], f_.y[i], f_.vx[i], f_.vy[i], f_.rho[i], f_.p[i]}; }
  void gather_boundary_forces(std::span<double> fx, std::span<double> fy) const;

  FluidParameters par_;
  FluidParticles f_;
  BoundaryParticles b_;
  exec::Team team_;
  CellList fluid_cells_, boundary_cells_;
  std::vector<std::uint8_t> near_wall_;  // per cell: a boundary particle within the search block
  // The boundary particles within wall_reach_ of the water's bounding box (update_cells):
  // the others have no fluid within the support of them or of their ghost node.
  std::vector<std::int32_t> active_walls_;
  double wall_reach_ = 0.0;
  double h_ = 0.0, b_tait_ = 0.0, grad_c_ = 0.0, support2_ = 0.0;
  double skin_ = 0.0;
  double time_ = 0.0;
  long steps_ = 0;
  double boundary_work_ = 0.0;      // J/m, boundary_work()
  std::vector<double> wall_power_;  // scratch: each fluid particle's share of the walls' power
  long vl_built_at_ = 0;
  double v_max_ = 0.0, a_max_ = 0.0;
  bool sound_ = true;
  double damping_rate_ = 0.0;
  double packing_ = 0.0;
  std::vector<double> shift_x_, shift_y_;  // pack_particles' shifts
  // Each fluid particle's Verlet list: the fluid particles within the support plus a skin
  // at the last rebuild, ascending, neighbour_capacity_ slots per particle, vl_n_ used.
  // Rebuilt after every re-sort and when a particle moved half the skin from vl_x_, vl_y_.
  // The sums run over the partners within the support whatever the list holds beyond it,
  // so the results do not depend on when the lists were rebuilt.
  std::size_t neighbour_capacity_ = 0;
  std::vector<std::int32_t> vl_j_, vl_n_;
  std::vector<double> vl_x_, vl_y_;
  // Each particle's partners within the support and their F, found by the density pass and
  // read by the force pass (the same positions): nb_n_[i] of them from slot nb_at_[i], each
  // block of particles' one after another in its own n_block x capacity slots (left
  // uninitialised: the slots beyond the partners are never touched, nor resident).
  std::unique_ptr<std::int32_t[]> nb_j_;
  std::unique_ptr<double[]> nb_f_;
  std::vector<std::int32_t> nb_n_;
  std::vector<std::size_t> nb_at_;
  std::vector<ForceSums> sums_;
  // The partners' values of each pass in one line apiece (pair_lanes.hpp), packed at the
  // start of the pass.
  std::vector<DensityRecord> density_records_;
  std::vector<ForceRecord> force_records_;
  bool record_ = false;
  std::vector<double> rec_fx_, rec_fy_;  // recorded boundary forces (set_record_boundary_forces)
  std::vector<ExcludedParticle> excluded_;  // reserved for the limit: no allocation in the loop
  std::size_t initial_size_ = 0;
  std::vector<double> scratch_;          // re-sort buffer
  std::vector<std::int32_t> scratch_id_;
};

}  // namespace dsdem::sph
