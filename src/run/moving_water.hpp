#pragma once
// The reservoir as moving water (docs/theory.md §11), from the scenario to the solver and back:
// the particles laid out in the fill regions outside the solid, the solid faces they are
// coupled with, and the settling before step 0 (run/water_watch.hpp reads the water).
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "io/scenario.hpp"
#include "model/model.hpp"
#include "sph/fluid.hpp"
#include "sph/solid_coupling.hpp"

namespace dsdem::run {

// The water as laid out before step 0, and the faces it is coupled with.
struct MovingWaterLayout {
  sph::FluidParameters parameters;
  sph::FluidParticles fluid;
  sph::BoundaryParticles walls;  // on the coupled faces (sph::lay_edge_particles)
  std::vector<sph::SolidEdge> edges;
  double depth = 0.0;        // m: the deepest still water (level less the lowest particle's bottom)
  double x_min = 0.0, x_max = 0.0;  // m: the filled span
  double coupled_top = 0.0;  // m: the level plus the freeboard, the top of the coupled bedrock faces
  // m: the region of the coupled bedrock faces (the banks the water may run up): x0-x1 over
  // bottom-top (bottom: the deepest water less the wall layers).
  double coupled_x0 = 0.0, coupled_x1 = 0.0, coupled_bottom = 0.0;
  // Discrete faces whose triangle carries no wall particle: the water would not see them
  // (sph::lay_edge_particles gives every triangle at least one; a guard).
  long faces_without_walls = 0;
};

// Fills the regions (default: below reservoir.level over reservoir.x) with particles dp
// apart, each outside every triangle and at least dp/2 from the solid's surface; couples
// every face of the discrete zone and the other surface faces up to the freeboard, over the
// filled span widened by its own width on each side (the banks the water may run up). Throws io::ScenarioError naming the section when no water fits.
MovingWaterLayout lay_out_moving_water(const io::Scenario& sc, const Model& model);

// Where reservoir.sph.spacing stands in the scenario: the key the spacing's errors and
// warnings name.
inline io::SourceLocation spacing_key(const io::SphSpec& sph) {
  io::SourceLocation at = sph.where;
  at.key += ".spacing";
  return at;
}

// The velocity damping rate of the settling (1/s): 2 sqrt(g / H), about critical for the
// reservoir's slowest gravity waves.
double settling_rate(double depth, double g);

// sph::settle for `duration` s at settling_rate(depth); returns the largest particle speed
// at its end, m/s.
double settle_moving_water(sph::Fluid& fluid, double duration, double depth);

}  // namespace dsdem::run
