// The water's surface measurements (docs/theory.md §12): gauges, the highest point, run-up,
// the volume past a crest, the period at a gauge, on particle layouts whose answer is known.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "sph/surface.hpp"

using namespace dsdem;
using namespace dsdem::sph;

namespace {

constexpr double kDp = 0.1, kH = 1.5 * kDp, kRho = 1000.0;

// Particles dp apart, centres at ((i + 1/2) dp, (k + 1/2) dp), wherever the centre is
// below surface(x) (the water stands for the cells, up to the top row's upper edge).
FluidParticles water_under(double x0, double x1, const std::function<double(double)>& surface) {
  FluidParticles f;
  f.mass = kRho * kDp * kDp;
  for (double x = x0 + 0.5 * kDp; x < x1; x += kDp)
    for (double y = 0.5 * kDp; y < surface(x); y += kDp) f.add(x, y, kRho);
  return f;
}

}  // namespace

TEST(FreeSurface, StillWaterReadsItsDepthAndADryColumnNothing) {
  const double depth = 1.0;  // 10 rows: the top row's upper edge at 1.0 m
  const FluidParticles f = water_under(0.0, 4.0, [&](double) { return depth; });
  const std::vector<double> xs{0.8, 1.55, 2.0, 3.2, 6.0};
  const std::vector<double> y = free_surface_elevations(f, xs, kH, kDp / 50);
  for (std::size_t k = 0; k + 1 < xs.size(); ++k) EXPECT_NEAR(y[k], depth, 0.1 * kDp) << "x = " << xs[k];
  EXPECT_TRUE(std::isnan(y.back())) << "a dry column reads no surface";
  // Inside the water the fluid fraction is 1 within the lattice's Shepard error.
  std::vector<std::int32_t> all(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) all[i] = static_cast<std::int32_t>(i);
  EXPECT_NEAR(fluid_fraction(f, all, 2.0, 0.5, kH), 1.0, 0.01);
}

TEST(FreeSurface, FollowsASlopeAndIgnoresADroplet) {
  auto line = [](double x) { return 0.6 + 0.1 * x; };
  FluidParticles f = water_under(0.0, 4.0, line);
  f.add(2.05, 2.5, kRho);  // a lone droplet far above the surface
  const std::vector<double> xs{1.0, 2.05, 3.0};
  const std::vector<double> y = free_surface_elevations(f, xs, kH, kDp / 50);
  // The particles stand for the surface to within one row (the staircase of the layout).
  for (std::size_t k = 0; k < xs.size(); ++k) EXPECT_NEAR(y[k], line(xs[k]), 0.6 * kDp) << "x = " << xs[k];
  const SurfacePeak peak = highest_surface(f, 0.5, 3.5, kDp, kH, kDp / 50);
  EXPECT_NEAR(peak.x, 3.5, 2 * kDp);
  EXPECT_NEAR(peak.y, line(3.5), 0.6 * kDp);
}

// Spray, a blob of a few particles thrown above the water, reads as the surface when any
// water counts, and is stepped over when the surface must stand on water 2 dp deep; a crest
// of the water body itself is kept.
TEST(FreeSurface, SprayIsSteppedOverWhenTheWaterMustBeDeep) {
  FluidParticles f = water_under(0.0, 4.0, [](double x) { return x > 2.8 && x < 3.2 ? 1.3 : 1.0; });
  for (double dx : {-0.5, 0.5})
    for (double dy : {-0.5, 0.5}) f.add(1.5 + dx * kDp, 1.8 + dy * kDp, kRho);  // a 2 x 2 blob at 1.8 m
  const std::vector<double> xs{1.5, 3.0};
  const std::vector<double> any = free_surface_elevations(f, xs, kH, kDp / 50);
  EXPECT_GT(any[0], 1.7) << "the blob counts as water";
  const std::vector<double> deep = free_surface_elevations(f, xs, kH, kDp / 50, 2.0 * kDp);
  EXPECT_NEAR(deep[0], 1.0, 0.1 * kDp) << "the water's own surface under the spray";
  EXPECT_NEAR(deep[1], any[1], 1e-12) << "a crest of the water body stays";
  EXPECT_GT(deep[1], 1.2);
}

TEST(FreeSurface, AHumpIsFoundWhereItIs) {
  // A crest 0.3 m high at x = 2.5 m on water 0.8 m deep.
  auto surface = [](double x) { return 0.8 + 0.3 * std::exp(-std::pow((x - 2.5) / 0.4, 2)); };
  const FluidParticles f = water_under(0.0, 5.0, surface);
  const SurfacePeak peak = highest_surface(f, 0.0, 5.0, 0.05, kH, kDp / 50);
  EXPECT_NEAR(peak.x, 2.5, 0.15);
  EXPECT_NEAR(peak.y, 1.1, 0.6 * kDp);
}

TEST(Runup, TheHighestWaterOnTheBank) {
  // A bank rising at 1:1 from (3, 0): water 0.7 m deep against it.
  const std::vector<Vec2> bank{{3.0, 0.0}, {5.0, 2.0}};
  const FluidParticles f = water_under(0.0, 6.0, [](double) { return 0.7; });
  // The water is above the bank line y = x - 3 (half a spacing off it).
  FluidParticles wet;
  wet.mass = f.mass;
  for (std::size_t j = 0; j < f.size(); ++j)
    if (f.y[j] > f.x[j] - 3.0 + 0.5 * kDp) wet.add(f.x[j], f.y[j], kRho);
  const double r = runup_on_polyline(wet, bank, 1.5 * kDp, kDp);
  EXPECT_NEAR(r, 0.7, kDp);
  EXPECT_TRUE(std::isnan(runup_on_polyline(wet, std::vector<Vec2>{{10.0, 0.0}, {12.0, 2.0}}, kDp, kDp)));
}

TEST(Runup, ATongueJoinedToTheWaterCountsAndSprayAboveItDoesNot) {
  // Water 0.7 m deep against a bank rising at 1:1 from (3, 0), drawn from under the water.
  const std::vector<Vec2> bank{{2.0, -1.0}, {3.0, 0.0}, {6.0, 3.0}};
  const FluidParticles f = water_under(0.0, 6.0, [](double) { return 0.7; });
  FluidParticles wet;
  wet.mass = f.mass;
  for (std::size_t j = 0; j < f.size(); ++j)
    if (f.y[j] > f.x[j] - 3.0 + 0.5 * kDp) wet.add(f.x[j], f.y[j], kRho);
  const double still = runup_on_polyline(wet, bank, kDp, kDp);
  EXPECT_NEAR(still, 0.7, kDp);
  // A one-particle film up the bank to z = 1.5, a particle missing half way: the run-up.
  const double n = std::sqrt(0.5) * 0.5 * kDp;  // half a spacing off the bank, normal to it
  for (double z = 0.7; z <= 1.5 + 1e-9; z += kDp / std::sqrt(2.0))
    if (std::abs(z - 1.1) > 0.4 * kDp) wet.add(3.0 + z - n, z + n, kRho);
  EXPECT_NEAR(runup_on_polyline(wet, bank, kDp, kDp), 1.5 + 0.5 * kDp, 0.5 * kDp);
  // Spray: two drops on the bank at z = 2.5, 1 m above the film's end, are not the run-up.
  wet.add(3.0 + 2.5 - n, 2.5 + n, kRho);
  wet.add(3.0 + 2.6 - n, 2.6 + n, kRho);
  EXPECT_NEAR(runup_on_polyline(wet, bank, kDp, kDp), 1.5 + 0.5 * kDp, 0.5 * kDp);
}

TEST(Overtopping, TheWaterPastACrest) {
  const FluidParticles f = water_under(0.0, 3.0, [](double) { return 1.0; });
  // Past x = 2 (1 m of the 3 m wide pool), above y = 0.5: 1 m x 0.5 m.
  EXPECT_NEAR(volume_beyond(f, 2.0, +1, 0.5), 0.5, 1e-9);
  EXPECT_NEAR(volume_beyond(f, 2.0, -1, 0.0), 2.0, 1e-9);
  EXPECT_EQ(volume_beyond(f, 3.5, +1, 0.0), 0.0);
}

TEST(WavePeriod, ASinesPeriodFromItsCrests) {
  std::vector<double> t, eta;
  const double period = 3.7;
  for (int k = 0; k <= 4000; ++k) {
    t.push_back(0.005 * k);
    eta.push_back(837.0 + 2.0 * std::sin(2 * kPi * t.back() / period + 0.3));
  }
  EXPECT_NEAR(mean_crest_period(t, eta, 0.5), period, 0.005 / 4);
  const std::vector<double> crests = crest_times(t, eta, 0.5);
  ASSERT_EQ(crests.size(), 6u);  // 20 s of a 3.7 s wave, its first crest at 0.75 s
  EXPECT_NEAR(crests.front(), period * (0.25 - 0.3 / (2 * kPi)), 0.005);
  EXPECT_TRUE(std::isnan(mean_crest_period(t, std::vector<double>(t.size(), 837.0), 0.5)));
}

TEST(WavePeriod, RipplesUnderTheBandAndARisingLevelDoNotHideTheWaves) {
  // A wave of period 3.7 s and amplitude 2 m, with a ripple of 0.3 m and period 0.23 s on it,
  // on a level that rises by 3 m over the record (a deposit filling the pool): with a band of
  // 0.8 m (above the ripple's height) only the waves' crests count.
  std::vector<double> t, eta;
  const double period = 3.7;
  for (int k = 0; k <= 8000; ++k) {
    t.push_back(0.0025 * k);
    eta.push_back(837.0 + 3.0 * k / 8000.0 + 2.0 * std::sin(2 * kPi * t.back() / period) +
                  0.3 * std::sin(2 * kPi * t.back() / 0.23));
  }
  EXPECT_LT(mean_crest_period(t, eta, 0.1), 0.5);  // a band under the ripple counts the ripple
  EXPECT_NEAR(mean_crest_period(t, eta, 0.8), period, 0.05 * period);
  // Still water with the ripple alone: no wave, no period.
  std::vector<double> ripple(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) ripple[k] = 837.0 + 0.3 * std::sin(2 * kPi * t[k] / 0.23);
  EXPECT_TRUE(std::isnan(mean_crest_period(t, ripple, 0.8)));
}

TEST(PrimaryWave, TheFirstCrestAfterTheEntryAndTheTroughThatFollowsIt) {
  // Still water with a 2 mm ripple, a solitary-like crest of 0.15 m at t = 1.2 s, a trough of
  // -0.06 m at 1.7 s, then a smaller second crest; the slide entered at t = 0.8 s.
  std::vector<double> t, eta;
  for (int k = 0; k <= 300; ++k) {
    const double s = 0.01 * k;
    t.push_back(s);
    eta.push_back(0.002 * std::sin(2 * kPi * s / 0.07) + 0.15 * std::exp(-std::pow((s - 1.2) / 0.12, 2)) -
                  0.06 * std::exp(-std::pow((s - 1.7) / 0.15, 2)) + 0.05 * std::exp(-std::pow((s - 2.3) / 0.12, 2)));
  }
  const PrimaryWave w = primary_wave(t, eta, 0.8, 0.01);
  EXPECT_NEAR(w.crest, 0.15, 0.003);
  EXPECT_NEAR(w.crest_t, 1.2, 0.011);
  // The trough is the series' lowest sample between the two crests (near 1.7 s: the crests'
  // tails lift it a little).
  std::size_t low = 130;
  for (std::size_t k = 130; k < 230; ++k)
    if (eta[k] < eta[low]) low = k;
  EXPECT_EQ(w.trough, eta[low]);
  EXPECT_EQ(w.trough_t, t[low]);
  EXPECT_NEAR(w.trough, -0.06, 0.003);
  EXPECT_NEAR(w.trough_t, 1.7, 0.03);
  EXPECT_NEAR(w.height(), 0.21, 0.005);
  // From after the first crest on, the primary wave is the second one; it has no trough
  // confirmed before the record ends.
  const PrimaryWave later = primary_wave(t, eta, 1.5, 0.01);
  EXPECT_NEAR(later.crest, 0.05, 0.003);
  EXPECT_TRUE(std::isnan(later.trough));
  EXPECT_TRUE(std::isnan(later.height()));
  // Nothing but the ripple: no wave.
  const std::vector<double> ripple(eta.size(), 0.001);
  EXPECT_TRUE(std::isnan(primary_wave(t, ripple, 0.0, 0.01).crest));
}

// A solitary-like crest with a trough shallower than the band (as at the flume's far gauges):
// the surface dips 6 mm below the still level and comes back 7 mm above it, never turning up
// by the band of 17 mm. The zero up-crossing ends the wave: the trough is the dip. A dip within
// the quarter band (ripples) ends nothing.
TEST(PrimaryWave, AZeroUpCrossingEndsAShallowTrough) {
  std::vector<double> t;
  for (int k = 0; k <= 400; ++k) t.push_back(0.01 * k);
  auto series = [&](double dip) {
    std::vector<double> eta;
    for (const double s : t)
      eta.push_back(0.1 * std::exp(-std::pow((s - 1.5) / 0.2, 2)) - dip * std::exp(-std::pow((s - 2.2) / 0.2, 2)) +
                    0.007 * std::exp(-std::pow((s - 2.9) / 0.2, 2)));
    return eta;
  };
  const double band = 0.0167;
  const std::vector<double> eta = series(0.006);
  const PrimaryWave w = primary_wave(t, eta, 0.5, band);
  EXPECT_NEAR(w.crest, 0.1, 1e-3);
  EXPECT_NEAR(w.trough, -0.006, 5e-4);
  EXPECT_NEAR(w.trough_t, 2.2, 0.03);
  EXPECT_NEAR(w.height(), 0.106, 1e-3);
  // Turning points alone do not see that trough.
  EXPECT_EQ(turning_points(t, eta, band).size(), 1u);
  // A dip of 3 mm, within the quarter band: no trough before the record ends.
  EXPECT_TRUE(std::isnan(primary_wave(t, series(0.003), 0.5, band).trough));
}

TEST(PrimaryWave, TurningPointsAlternateAndKeepTheCrestTimes) {
  std::vector<double> t, eta;
  for (int k = 0; k <= 2000; ++k) {
    t.push_back(0.005 * k);
    eta.push_back(std::sin(2 * kPi * t.back() / 2.5));
  }
  const std::vector<TurningPoint> p = turning_points(t, eta, 0.2);
  ASSERT_EQ(p.size(), 8u);  // 10 s of a 2.5 s wave: four crests, four troughs
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(p[i].crest, i % 2 == 0);
    EXPECT_NEAR(p[i].eta, i % 2 == 0 ? 1.0 : -1.0, 1e-4);
    EXPECT_NEAR(p[i].t, 0.625 + 1.25 * static_cast<double>(i), 0.005);
  }
  const std::vector<double> crests = crest_times(t, eta, 0.2);
  ASSERT_EQ(crests.size(), 4u);
  EXPECT_EQ(crests[1], p[2].t);
}
