#pragma once
// SPH particles as structures of arrays (docs/developer-guide.md §7, docs/theory.md §11). Fluid particles move with the
// flow; boundary particles make the walls and, when coupled, sit on a solid triangle's
// exposed edge at a parametric position and move with it through its shape functions.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "model/types.hpp"

namespace dsdem::sph {

struct FluidParticles {
  std::vector<double> x, y;      // m
  std::vector<double> vx, vy;    // m/s
  std::vector<double> rho;       // kg/m^3
  std::vector<double> p;         // Pa, from rho through the equation of state
  std::vector<double> vol;       // m^2 (per unit width): mass / rho
  std::vector<double> ax, ay;    // m/s^2, the last force evaluation's
  std::vector<double> drho;      // kg/m^3/s, the last density rate
  std::vector<double> gx, gy;    // kg/m^4: the renormalised density gradient of the last force evaluation
  std::vector<std::int32_t> id;  // the creation order, kept through the re-sorts
  double mass = 0.0;             // kg/m (per unit width), the same for every particle

  std::size_t size() const { return x.size(); }
  void reserve(std::size_t n);
  // A particle at rest at (px, py) with density rho0 (p, a, drho zero).
  void add(double px, double py, double density);
};

struct BoundaryParticles {
  std::vector<double> x, y;           // m
  std::vector<double> vx, vy;         // m/s, the wall's velocity at the particle
  std::vector<double> rho, p;         // kg/m^3, Pa: the dynamic boundary's density and pressure
  std::vector<double> drho;           // kg/m^3/s
  std::vector<double> nx, ny;         // the wall's unit normal, into the fluid
  std::vector<double> wall_distance;  // m: from the particle to the wall face along n (> 0)
  // Where the particle rides: the solid edge (kNoIndex: fixed in space) and the parametric
  // position s in [0, 1] along it.
  std::vector<Index> edge;
  std::vector<double> s;
  double mass = 0.0;  // kg/m

  std::size_t size() const { return x.size(); }
  void reserve(std::size_t n);
  // A fixed particle at (px, py) with density `density`, behind the wall face whose normal
  // (into the fluid) is n, at distance d.
  void add_fixed(double px, double py, double density, Vec2 n, double d);
};

inline void FluidParticles::reserve(std::size_t n) {
  for (auto* a : {&x, &y, &vx, &vy, &rho, &p, &ax, &ay, &drho, &gx, &gy, &vol}) a->reserve(n);
  id.reserve(n);
}
inline void FluidParticles::add(double px, double py, double density) {
  id.push_back(static_cast<std::int32_t>(x.size()));
  x.push_back(px);
  y.push_back(py);
  rho.push_back(density);
  for (auto* a : {&vx, &vy, &p, &ax, &ay, &drho, &gx, &gy, &vol}) a->push_back(0.0);
}
inline void BoundaryParticles::reserve(std::size_t n) {
  for (auto* a : {&x, &y, &vx, &vy, &rho, &p, &drho, &nx, &ny, &wall_distance, &s}) a->reserve(n);
  edge.reserve(n);
}
inline void BoundaryParticles::add_fixed(double px, double py, double density, Vec2 n, double d) {
  x.push_back(px);
  y.push_back(py);
  rho.push_back(density);
  nx.push_back(n.x());
  ny.push_back(n.y());
  wall_distance.push_back(d);
  edge.push_back(kNoIndex);
  s.push_back(0.0);
  for (auto* a : {&vx, &vy, &p, &drho}) a->push_back(0.0);
}

}  // namespace dsdem::sph
