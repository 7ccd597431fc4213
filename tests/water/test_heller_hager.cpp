// The Heller & Hager (2010) impulse-wave estimate (docs/theory.md §12) against values worked by
// hand from its equations, and its validity box.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "water/heller_hager.hpp"

using namespace dsdem::water;

namespace {
// A slide of 2 x 0.2 m^2 (rho_s 1600 kg/m^3, 640 kg/m) at 4 m/s into 0.4 m of water down a
// 45-degree plane: a flume case of the experiments' kind.
SlideImpact flume() {
  SlideImpact s;
  s.speed = 4.0;
  s.thickness = 0.2;
  s.mass = 640.0;
  s.slope_deg = 45.0;
  s.depth = 0.4;
  return s;
}
}  // namespace

TEST(HellerHager, ParametersAndWaveFollowTheEquations) {
  const ImpulseWave w = heller_hager(flume());
  const double F = 4.0 / std::sqrt(9.81 * 0.4), S = 0.5, M = 640.0 / (1000.0 * 0.16);
  const double P = F * std::sqrt(S) * std::pow(M, 0.25) * std::sqrt(std::cos(6.0 / 7.0 * M_PI / 4.0));
  EXPECT_NEAR(w.froude, 2.019275, 1e-6);
  EXPECT_DOUBLE_EQ(w.relative_thickness, S);
  EXPECT_DOUBLE_EQ(w.relative_mass, 4.0);
  EXPECT_NEAR(w.impulse_product, P, 1e-14);
  EXPECT_NEAR(w.impulse_product, 1.785468, 1e-6);  // by hand: 2.019275 * 0.707107 * 1.414214 * 0.884212
  EXPECT_NEAR(w.amplitude_m, 4.0 / 9.0 * std::pow(P, 0.8) * 0.4, 1e-14);
  EXPECT_NEAR(w.height_m / w.amplitude_m, 5.0 / 4.0, 1e-14);
  EXPECT_NEAR(w.distance_m, 5.5 * std::sqrt(P) * 0.4, 1e-14);
  EXPECT_TRUE(w.inside_validity());
  // The decay: at x = h the 2D height is 3/4 P^4/5 h, and it falls as x^-4/15.
  EXPECT_NEAR(heller_hager_height_at(w, 0.4, 0.4), 0.75 * std::pow(P, 0.8) * 0.4, 1e-14);
  EXPECT_NEAR(heller_hager_height_at(w, 0.4, 8.0 * 0.4) / heller_hager_height_at(w, 0.4, 0.4), std::pow(8.0, -4.0 / 15.0),
              1e-14);
  // The crest's decay is 4/5 of the height's, as a_M is of H_M; both meet their maxima at
  // x/h = (27/20)^(15/4).
  EXPECT_NEAR(heller_hager_amplitude_at(w, 0.4, 2.0) / heller_hager_height_at(w, 0.4, 2.0), 0.8, 1e-14);
  EXPECT_NEAR(heller_hager_decay_onset(), 3.0814, 1e-4);
  const double onset = heller_hager_decay_onset() * 0.4;
  EXPECT_NEAR(heller_hager_amplitude_at(w, 0.4, onset), w.amplitude_m, 1e-12);
  EXPECT_NEAR(heller_hager_height_at(w, 0.4, onset), w.height_m, 1e-12);
}

TEST(HellerHager, SaysWhichParameterLeavesTheValidityBox) {
  SlideImpact slow = flume();
  slow.speed = 1.0;  // F = 0.50 < 0.86
  const ImpulseWave w = heller_hager(slow);
  EXPECT_FALSE(w.inside_validity());
  EXPECT_FALSE(w.checks[0].inside());
  EXPECT_STREQ(w.checks[0].name, "F");
  EXPECT_TRUE(w.checks[1].inside());
  SlideImpact flat = flume();
  flat.slope_deg = 20.0;  // below the experiments' 30 degrees
  EXPECT_FALSE(heller_hager(flat).checks[4].inside());
}

TEST(HellerHager, RejectsImpossibleInputs) {
  for (auto bad : {&SlideImpact::speed, &SlideImpact::thickness, &SlideImpact::mass, &SlideImpact::depth}) {
    SlideImpact s = flume();
    s.*bad = 0.0;
    EXPECT_THROW(heller_hager(s), std::invalid_argument);
  }
  SlideImpact s = flume();
  s.slope_deg = 95.0;
  EXPECT_THROW(heller_hager(s), std::invalid_argument);
  EXPECT_THROW(heller_hager_height_at(heller_hager(flume()), 0.4, 0.0), std::invalid_argument);
  EXPECT_THROW(heller_hager_amplitude_at(heller_hager(flume()), 0.4, -1.0), std::invalid_argument);
}
