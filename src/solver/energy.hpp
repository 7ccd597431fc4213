#pragma once
// The energy ledger (J, per unit thickness in plane strain). Conservative parts are
// evaluated from the state; work and dissipation are accumulated with the trapezoidal
// rule on each step's displacement increment, which matches velocity Verlet to O(dt^2).
namespace dsdem::solver {

struct EnergyLedger {
  double kinetic = 0.0;
  double strain = 0.0;                // elastic energy of the triangles
  double gravity_potential = 0.0;     // -sum m g.u, relative to the start of the run
  double joint_elastic = 0.0;         // elastic energy stored in intact joints
  double contact_elastic = 0.0;       // elastic energy stored in contact springs
  double external_work = 0.0;         // work done on the model by prescribed motions and boundary loads
  double damping_dissipated = 0.0;    // Rayleigh damping (and boundary dashpots)
  double fracture_dissipated = 0.0;   // cohesive softening
  double friction_dissipated = 0.0;   // contact friction (Coulomb sliding)
  double initial_total = 0.0;         // mechanical energy at the start of the run
  // Normal contact dashpots (contact restitution < 1), booked as velocity Verlet applies
  // them: half of each force's work at the step it is computed, half at the next
  // (docs/theory.md §7; ContactForces::settle_previous).
  double contact_damping_dissipated = 0.0;
  // Plastic work of the bulk (Mohr-Coulomb, docs/theory.md §10): a function of the state, the
  // sum of each triangle's accumulated plastic work.
  double plastic_dissipated = 0.0;
  // Work of the water at rest on the solid (docs/theory.md §8), booked as the work of the
  // other loads: trapezoidal on each step's displacement increments.
  double water_work = 0.0;
  // Work of the moving (SPH) water on the solid (docs/theory.md §11), booked the same way.
  double moving_water_work = 0.0;
  // The moving water's own energy (J/m), reported beside the solid's: kinetic, and the
  // changes of its gravity potential and compression (Tait) since it was set. Not part of
  // mechanical(): the solid's
  // balance closes with moving_water_work; the water's energy plus that work falls by what
  // the fluid's artificial viscosity and density diffusion dissipate.
  double fluid_kinetic = 0.0, fluid_potential = 0.0, fluid_compression = 0.0;
  // The energy the particles taken out of the water took with them (sph::Fluid::excluded):
  // still the water's.
  double fluid_excluded = 0.0;
  double fluid_energy() const { return fluid_kinetic + fluid_potential + fluid_compression + fluid_excluded; }
  // Velocity Verlet's kinetic offset (docs/theory.md §7): with the trapezoidal work of the
  // forces the integrator conserves 1/2 m v(n-1/2).v(n+1/2) = 1/2 m v(n)^2 - dt^2/8 m |a(n)|^2,
  // not the kinetic energy at the full step. This is the change of sum dt^2/8 m |a|^2 since
  // the start, each step's with its dt (Solver sums it per stretch of constant dt, settled
  // when the ledger is read: Solver::energy()); large where nodes vibrate near the stable step.
  double verlet_kinetic_offset = 0.0;

  double mechanical() const { return kinetic + strain + gravity_potential + joint_elastic + contact_elastic; }
  double dissipated() const {
    return damping_dissipated + fracture_dissipated + friction_dissipated + contact_damping_dissipated +
           plastic_dissipated;
  }
  double work_in() const { return external_work + water_work + moving_water_work; }
  // Relative balance error: |E - K_v - E0 + D - W| over the largest energy in play (K_v:
  // verlet_kinetic_offset; W: the work put in, water included).
  double balance_error() const;
};

}  // namespace dsdem::solver
