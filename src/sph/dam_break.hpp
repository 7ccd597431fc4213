#pragma once
// The dam break of Martin & Moyce (1952) and Koshizuka & Oka (1996) (docs/validation.md §5.2, docs/theory.md §11): a
// column of water a wide and n^2 a high at the left end of a tank, released at t = 0. The
// surge front Z = x_front / a against T = t sqrt(2 g / a), and the residual column height
// H = y_top(left wall) / (n^2 a) against tau = t n sqrt(g / a) (Martin & Moyce's scalings).
#include <functional>
#include <vector>

#include "sph/fluid.hpp"

namespace dsdem::sph {

struct DamBreakSetup {
  double a = 0.146;           // m, the column's width (Koshizuka & Oka)
  double n2 = 2.0;            // height / width
  double tank_length = 0.584; // m (4 a in Koshizuka & Oka)
  double dp = 0.146 / 40.0;   // m
  double h_over_dp = 1.5;
  double alpha = 0.1;   // artificial viscosity (docs/theory.md §11: 0.01-0.1)
  double delta = 0.1;
  double g = 9.81;
};

struct DamBreakSample {
  double t = 0.0;       // s
  double front = 0.0;   // m, the surge front's distance from the left wall
  double height = 0.0;  // m, the water's height at the left wall
};

// The parameters: c0 = 10 times the largest speed expected, 2 sqrt(g n^2 a) (docs/theory.md §11).
FluidParameters dam_break_parameters(const DamBreakSetup& s);
// The column at hydrostatic density, and the tank's walls (up to twice the column height).
Fluid make_dam_break(const DamBreakSetup& s, bool parallel = false);
// The front: the largest x of the fluid plus dp/2; the height: the top of the water in the
// first column of particles at the left wall (x < 1.5 dp), plus dp/2.
DamBreakSample measure_dam_break(const Fluid& fluid, double dp);
// Runs to t_end, sampling every `every` seconds (the first sample at t = 0); `frame` is
// called at each sample when given.
std::vector<DamBreakSample> run_dam_break(Fluid& fluid, double dp, double t_end, double every,
                                          const std::function<void(const Fluid&)>& frame = {});

}  // namespace dsdem::sph
