#include "sph/dam_break.hpp"

#include <algorithm>
#include <cmath>

#include "sph/setup.hpp"

namespace dsdem::sph {

FluidParameters dam_break_parameters(const DamBreakSetup& s) {
  FluidParameters p;
  p.dp = s.dp;
  p.h_over_dp = s.h_over_dp;
  p.alpha = s.alpha;
  p.delta = s.delta;
  p.gravity = Vec2(0.0, -s.g);
  const double height = s.n2 * s.a;
  p.c0 = sound_speed_for(height, 2.0 * std::sqrt(s.g * height), s.g);
  return p;
}

Fluid make_dam_break(const DamBreakSetup& s, bool parallel) {
  const FluidParameters p = dam_break_parameters(s);
  const double height = s.n2 * s.a;
  FluidParticles water;
  BoundaryParticles walls;
  fill_rectangle(water, 0.0, 0.0, s.a, height, p, height);
  add_tank_walls(walls, 0.0, 0.0, s.tank_length, 2.0 * height, wall_layers(p), p, height);
  return Fluid(p, std::move(water), std::move(walls), parallel);
}

DamBreakSample measure_dam_break(const Fluid& fluid, double dp) {
  const auto& f = fluid.fluid();
  DamBreakSample s;
  s.t = fluid.time();
  double front = -INFINITY, top = -INFINITY;
  for (std::size_t i = 0; i < f.size(); ++i) {
    front = std::max(front, f.x[i]);
    if (f.x[i] < 1.5 * dp) top = std::max(top, f.y[i]);
  }
  s.front = front + 0.5 * dp;
  s.height = top + 0.5 * dp;
  return s;
}

std::vector<DamBreakSample> run_dam_break(Fluid& fluid, double dp, double t_end, double every,
                                          const std::function<void(const Fluid&)>& frame) {
  std::vector<DamBreakSample> out;
  const int n = static_cast<int>(std::lround(t_end / every));
  out.reserve(static_cast<std::size_t>(n) + 1);
  out.push_back(measure_dam_break(fluid, dp));
  if (frame) frame(fluid);
  for (int k = 1; k <= n; ++k) {
    fluid.advance(k * every - fluid.time());
    out.push_back(measure_dam_break(fluid, dp));
    if (frame) frame(fluid);
  }
  return out;
}

}  // namespace dsdem::sph
