#include <gtest/gtest.h>

#include <cmath>

#include "model/types.hpp"
#include "seismic/design_spectrum.hpp"

using namespace dsdem;
using namespace dsdem::seismic;

// docs/theory.md §5: beta = 1 + 10(bmax - 1)T to 0.1 s, bmax to Tg, bmax (Tg/T)^0.6 after,
// floor 0.2 bmax. Reference values computed by hand (bmax 2.25, Tg 0.35 s).
TEST(DesignSpectrum, HydraulicBetaBranches) {
  EXPECT_DOUBLE_EQ(hydraulic_beta(0.0, 2.25, 0.35), 1.0);
  EXPECT_NEAR(hydraulic_beta(0.05, 2.25, 0.35), 1.625, 1e-15);
  EXPECT_NEAR(hydraulic_beta(0.1, 2.25, 0.35), 2.25, 1e-15);
  EXPECT_DOUBLE_EQ(hydraulic_beta(0.2, 2.25, 0.35), 2.25);
  EXPECT_DOUBLE_EQ(hydraulic_beta(0.35, 2.25, 0.35), 2.25);
  EXPECT_NEAR(hydraulic_beta(0.7, 2.25, 0.35), 2.25 * 0.6597539553864471, 1e-12);  // 0.5^0.6
  // The floor 0.45 is reached at T = 0.35 / 0.2^(1/0.6) = 5.117 s.
  EXPECT_GT(hydraulic_beta(5.0, 2.25, 0.35), 0.45);
  EXPECT_DOUBLE_EQ(hydraulic_beta(5.2, 2.25, 0.35), 0.45);
  EXPECT_DOUBLE_EQ(hydraulic_beta(6.0, 2.25, 0.35), 0.45);
}

TEST(DesignSpectrum, Gb50011Coefficients) {
  const Gb50011Coefficients c5 = gb50011_coefficients(0.05);
  EXPECT_DOUBLE_EQ(c5.gamma, 0.9);
  EXPECT_DOUBLE_EQ(c5.eta1, 0.02);
  EXPECT_DOUBLE_EQ(c5.eta2, 1.0);
  const Gb50011Coefficients c2 = gb50011_coefficients(0.02);
  EXPECT_NEAR(c2.gamma, 0.9 + 0.03 / 0.42, 1e-15);
  EXPECT_NEAR(c2.eta1, 0.02 + 0.03 / 4.64, 1e-15);
  EXPECT_NEAR(c2.eta2, 1.0 + 0.03 / 0.112, 1e-15);
  const Gb50011Coefficients c50 = gb50011_coefficients(0.5);  // both limits active
  EXPECT_EQ(c50.eta1, 0.0);
  EXPECT_EQ(c50.eta2, 0.55);
}

// GB 50011 at 5%: 0.45 amax at 0, linear to amax at 0.1 s, flat to Tg, (Tg/T)^0.9 to
// 5 Tg, then 0.2^0.9 - 0.02 (T - 5Tg); continuous at 5 Tg.
TEST(DesignSpectrum, Gb50011AlphaBranches) {
  const double am = 0.1125, Tg = 0.35;
  EXPECT_NEAR(gb50011_alpha(0.0, am, Tg, 0.05), 0.45 * am, 1e-15);
  EXPECT_NEAR(gb50011_alpha(0.05, am, Tg, 0.05), 0.725 * am, 1e-15);
  EXPECT_NEAR(gb50011_alpha(0.1, am, Tg, 0.05), am, 1e-15);
  EXPECT_NEAR(gb50011_alpha(0.3, am, Tg, 0.05), am, 1e-15);
  EXPECT_NEAR(gb50011_alpha(0.7, am, Tg, 0.05), std::pow(0.5, 0.9) * am, 1e-15);
  const double at5 = std::pow(0.2, 0.9) * am;
  EXPECT_NEAR(gb50011_alpha(5 * Tg, am, Tg, 0.05), at5, 1e-15);
  EXPECT_NEAR(gb50011_alpha(5 * Tg + 1e-9, am, Tg, 0.05), at5, 1e-10);
  EXPECT_NEAR(gb50011_alpha(6.0, am, Tg, 0.05), (std::pow(0.2, 0.9) - 0.02 * 4.25) * am, 1e-15);
  EXPECT_NEAR(gb50011_alpha(8.0, am, Tg, 0.05), gb50011_alpha(6.0, am, Tg, 0.05), 1e-15);
}

TEST(DesignSpectrum, AnchoredAtPga) {
  DesignSpectrum s;  // paper's case: 0.05 g, Tg 0.35 s, beta_max 2.25
  const double pga = 0.05 * kStandardGravity;
  EXPECT_NEAR(s.sa(0.0), pga, 1e-15);
  EXPECT_NEAR(s.sa(0.2), 2.25 * pga, 1e-15);
  s.kind = DesignSpectrumKind::Gb50011Alpha;
  EXPECT_NEAR(s.sa(0.0), 0.45 * 2.25 * pga, 1e-15);  // 1.0125 PGA
  EXPECT_NEAR(s.sa(0.2), 2.25 * pga, 1e-15);
  EXPECT_NO_THROW(s.validate());
  s.damping = 0.02;
  EXPECT_NO_THROW(s.validate());
  EXPECT_NEAR(s.sa(0.2), 2.25 * pga * (1.0 + 0.03 / 0.112), 1e-12);
}

TEST(DesignSpectrum, ValidationAndKeys) {
  DesignSpectrum s;
  s.damping = 0.02;  // hydraulic beta is a 5% spectrum
  EXPECT_THROW(s.validate(), std::runtime_error);
  s = DesignSpectrum{};
  s.pga = -1;
  EXPECT_THROW(s.validate(), std::runtime_error);
  s = DesignSpectrum{};
  s.Tg = 0.05;
  EXPECT_THROW(s.validate(), std::runtime_error);
  EXPECT_EQ(parse_design_spectrum_kind("beta"), DesignSpectrumKind::HydraulicBeta);
  EXPECT_EQ(parse_design_spectrum_kind("GB50011"), DesignSpectrumKind::Gb50011Alpha);
  try {
    parse_design_spectrum_kind("eurocode");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("valid: beta, hydraulic, alpha, gb50011"), std::string::npos);
  }
}
