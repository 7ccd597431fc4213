#include "sph/setup.hpp"

#include <algorithm>
#include <cmath>

#include "sph/kernels.hpp"

namespace dsdem::sph {

double hydrostatic_density(double depth, const FluidParameters& par) {
  if (depth <= 0.0) return par.rho0;
  const double g = par.gravity.norm();
  return tait_density(par.rho0 * g * depth, par.rho0, tait_b(par.rho0, par.c0));
}

void fill_rectangle(FluidParticles& fluid, double x0, double y0, double x1, double y1, const FluidParameters& par,
                    double surface) {
  const double dp = par.dp;
  const int nx = static_cast<int>(std::floor((x1 - x0) / dp + 1e-9));
  const int ny = static_cast<int>(std::floor((y1 - y0) / dp + 1e-9));
  fluid.reserve(fluid.size() + static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = x0 + (i + 0.5) * dp, y = y0 + (j + 0.5) * dp;
      fluid.add(x, y, hydrostatic_density(surface - y, par));
    }
  fluid.mass = par.mass();
}

void add_tank_walls(BoundaryParticles& walls, double x0, double y0, double x1, double y1, int layers,
                    const FluidParameters& par, double surface) {
  const double dp = par.dp;
  const int nx = static_cast<int>(std::lround((x1 - x0) / dp));
  const int ny = static_cast<int>(std::lround((y1 - y0) / dp));
  // Under the side walls the bottom rows mirror through the tank's corner.
  const double rho_bottom = hydrostatic_density(surface - y0, par);
  for (int k = 0; k < layers; ++k) {
    const double d = (k + 0.5) * dp, y = y0 - d;
    for (int i = -layers; i < nx + layers; ++i) {
      const double x = x0 + (i + 0.5) * dp;
      const Vec2 corner(i < 0 ? x0 : x1, y0);
      if (i < 0 || i >= nx) {
        const Vec2 to = corner - Vec2(x, y);
        walls.add_fixed(x, y, rho_bottom, to.normalized(), to.norm());
      } else {
        walls.add_fixed(x, y, rho_bottom, Vec2(0.0, 1.0), d);
      }
    }
  }
  for (int k = 0; k < layers; ++k) {
    const double d = (k + 0.5) * dp;
    for (int j = 0; j < ny; ++j) {
      const double y = y0 + (j + 0.5) * dp, rho = hydrostatic_density(surface - y, par);
      walls.add_fixed(x0 - d, y, rho, Vec2(1.0, 0.0), d);
      walls.add_fixed(x1 + d, y, rho, Vec2(-1.0, 0.0), d);
    }
  }
  walls.mass = par.mass();
}

int wall_layers(const FluidParameters& par) {
  return std::max(1, static_cast<int>(std::ceil(2.0 * par.h_over_dp - 1e-9)));
}

}  // namespace dsdem::sph
