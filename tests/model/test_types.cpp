#include <gtest/gtest.h>

#include "model/model.hpp"

using namespace dsdem;

TEST(Material, PlaneStrainAndPlaneStressModuli) {
  Material m;
  m.E = 10e9;
  m.nu = 0.25;
  m.rho = 2500;
  // Plane strain P-wave modulus: E(1-nu)/((1+nu)(1-2nu)).
  EXPECT_NEAR(m.p_wave_modulus(), 10e9 * 0.75 / (1.25 * 0.5), 1e-3);
  m.plane_stress = true;
  EXPECT_NEAR(m.p_wave_modulus(), 10e9 / (1 - 0.0625), 1e-3);
}
