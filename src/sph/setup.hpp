#pragma once
// Initial particle layouts for SPH water (docs/theory.md §11): a rectangle of fluid on a
// square lattice at hydrostatic density, and the walls of a rectangular tank as layers of
// fixed boundary particles.
#include "sph/fluid.hpp"
#include "sph/particles.hpp"

namespace dsdem::sph {

// The hydrostatic density at depth `depth` below the free surface (Tait's equation of
// state inverted at p = rho0 g depth; rho0 above the surface).
double hydrostatic_density(double depth, const FluidParameters& par);

// Fluid particles at the centres of the dp x dp squares of [x0, x1] x [y0, y1], at the
// hydrostatic density below the level `surface` (m).
void fill_rectangle(FluidParticles& fluid, double x0, double y0, double x1, double y1, const FluidParameters& par,
                    double surface);

// The walls of a tank whose inner faces are the bottom y = y0 and the sides x = x0, x = x1,
// up to y1: `layers` rows of particles dp apart, the first dp/2 behind each face (the face
// lies halfway between the fluid's first row and the walls' first row), the bottom rows
// running under the side walls to close the corners. Densities hydrostatic below `surface`.
void add_tank_walls(BoundaryParticles& walls, double x0, double y0, double x1, double y1, int layers,
                    const FluidParameters& par, double surface);

// Layers needed to fill the kernel's support behind a wall: ceil(2 h / dp).
int wall_layers(const FluidParameters& par);

}  // namespace dsdem::sph
