#pragma once
// What engineers read off the water (docs/theory.md §12): the free-surface elevation at a gauge,
// the surface along the reservoir (the wave's amplitude, where and when), the run-up on a
// bank, the volume that has passed a crest, the wave period at a gauge. Measured on the
// fluid particles at output times, never in the time loop: each call scans the particles
// once (O(N)) and allocates only its scratch.
//
// The free surface is where the SPH fluid fraction c(x, y) = sum_j V_j W(|x - x_j|, h)
// (the Shepard sum of the particles' volumes: 1 inside the water) falls to 1/2: at a flat
// surface of particles laid dp apart the kernel's half-support reaches dp/2 above the top
// row, the surface of the water the particles stand for. A lone droplet (c <= V W(0) =
// 0.25 at h = 1.5 dp) is not surface.
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "model/types.hpp"
#include "sph/particles.hpp"

namespace dsdem::sph {

// c(x, y) over the particles listed in `near` (indices into f, those within 2h of the point
// or more).
double fluid_fraction(const FluidParticles& f, std::span<const std::int32_t> near, double x, double y, double h);

// The free-surface elevation at each x of `xs` (m): the highest y where c(x, y) = 1/2,
// found to within `resolution` (m; dp/20 is plenty), on water at least `thickness` m deep
// below it or reaching the column's bottom (2 dp steps over spray; 0 takes any water);
// NaN where the column is dry. Particles are binned once into columns 2h wide.
std::vector<double> free_surface_elevations(const FluidParticles& f, std::span<const double> xs, double h,
                                            double resolution, double thickness = 0.0);

// The highest point of the surface over [x0, x1] sampled every `spacing` m: its x and y.
// y is NaN when the whole span is dry.
struct SurfacePeak {
  double x = 0.0, y = 0.0;
};
SurfacePeak highest_surface(const FluidParticles& f, double x0, double x1, double spacing, double h, double resolution);

// The run-up on a bank given as a polyline (m): the highest elevation of the water's edge
// on it joined to the body of water. The particles within `reach` of the polyline (dp is
// the usual reach: the first row of water on the bank) wet it; the run-up is the highest
// of those on the unbroken wet stretch through the curve's lowest wet point (gaps under
// about dp bridged), plus half a particle spacing `dp / 2` (the water the particle stands
// for reaches that far). Spray that lands on the bank above the tongue is not counted. A
// single point gives the highest particle within reach of it. NaN when no particle is that
// close.
double runup_on_polyline(const FluidParticles& f, std::span<const Vec2> polyline, double reach, double dp);

// The water beyond a vertical line x = x_line on the side `direction` (+1: x > x_line, -1:
// x < x_line) and above y_min (m): its area per unit width, m^2/m (mass / density of each
// particle). The overtopping volume of a crest at (x_line, y_min) is its growth from the
// start.
double volume_beyond(const FluidParticles& f, double x_line, int direction, double y_min);

// The turning points of the series eta(t) (a gauge's surface), in time order: its crests,
// maxima after which it falls at least `band` (m, > 0: the surface's resolution), and its
// troughs, minima after which it rises at least `band`; so ripples under the band are not
// waves, and a level that shifts (a slide deposit raising the pool) does not hide them. NaN
// samples (a dry gauge) are passed over. A first extreme the series did not move `band`
// toward is none.
struct TurningPoint {
  double t = 0.0, eta = 0.0;  // s, m
  bool crest = false;
};
std::vector<TurningPoint> turning_points(std::span<const double> t, std::span<const double> eta, double band);

// The times (s) of the crests of turning_points.
std::vector<double> crest_times(std::span<const double> t, std::span<const double> eta, double band);

// The primary wave at a gauge from time t_from on: its first crest and the trough that
// follows it (Heller & Hager's crest amplitude a_c and trough amplitude a_t, H = a_c + a_t,
// when eta is measured from the still level). The trough ends at the next turning point or
// where the surface crosses the still level upward, from below -band/4 to above +band/4 (the
// zero up-crossing that ends a wave). NaN values when the series has no crest
// from t_from on, or no trough after it before its end.
struct PrimaryWave {
  double crest = std::numeric_limits<double>::quiet_NaN(), crest_t = std::numeric_limits<double>::quiet_NaN();
  double trough = std::numeric_limits<double>::quiet_NaN(), trough_t = std::numeric_limits<double>::quiet_NaN();
  double height() const { return crest - trough; }
};
PrimaryWave primary_wave(std::span<const double> t, std::span<const double> eta, double t_from, double band);

// The mean period between successive crests (s): NaN with fewer than two.
double mean_crest_period(std::span<const double> t, std::span<const double> eta, double band);

}  // namespace dsdem::sph
