#pragma once
// The SPH benchmark's tank (docs/theory.md §11): n x n fluid particles at rest, dp = 0.01 m, in a
// tank walled on three sides 1.2 times as high as the water. Shared by BM_SphTank and
// dsdem_profile_sph so that the profiler runs what the benchmark times.
#include <utility>

#include "sph/fluid.hpp"
#include "sph/setup.hpp"

namespace dsdem::bench {

inline sph::Fluid sph_tank(int n, bool parallel) {
  sph::FluidParameters par;
  par.dp = 0.01;
  const double side = n * par.dp;
  par.c0 = sph::sound_speed_for(side, 0.0, 9.81);
  sph::FluidParticles water;
  sph::BoundaryParticles walls;
  sph::fill_rectangle(water, 0.0, 0.0, side, side, par, side);
  sph::add_tank_walls(walls, 0.0, 0.0, side, 1.2 * side, sph::wall_layers(par), par, side);
  return sph::Fluid(par, std::move(water), std::move(walls), parallel);
}

}  // namespace dsdem::bench
