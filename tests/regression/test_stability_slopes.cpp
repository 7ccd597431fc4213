// `dsdem stability` on the shipped slopes (docs/validation.md §6): the homogeneous slope
// (examples/homogeneous_slope, crossed triangles at h = 0.5 m, E = 100 MPa) against the
// published strength-reduction factor 1.54 (code_aster SSNP006 / Plaxis2D) within 3 %, and
// a bisection's trials identical on one and two threads.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "app/cli_util.hpp"

using dsdem::test::example;
using dsdem::test::fresh_dir;
using dsdem::test::run_dsdem;
namespace fs = std::filesystem;

namespace {

nlohmann::json stability(const std::string& scenario, const std::string& args, const std::string& name) {
  const fs::path out = fresh_dir(name);
  const auto c = run_dsdem("stability " + scenario + args + " -q --no-plots -o " + out.string());
  EXPECT_EQ(c.exit_code, 0) << c.output;
  std::ifstream in(out / "summary.json");
  nlohmann::json s = nlohmann::json::parse(in, nullptr, false);
  fs::remove_all(out);
  return s;
}

}  // namespace

// The slope stands at 0.97 x 1.54 and fails at 1.03 x 1.54 (dsdem's bisection: 1.5586).
TEST(StabilityRegression, HomogeneousSlopeWithinThreePercentOfTheStrengthReductionReference) {
  char bounds[96];
  std::snprintf(bounds, sizeof bounds, " --bounds %.6f %.6f --tolerance 1 --threads 2", 1.54 * 0.97, 1.54 * 1.03);
  const auto s = stability(example("homogeneous_slope/scenario.yaml"), bounds, "stab_homogeneous");
  ASSERT_TRUE(s.is_object());
  ASSERT_EQ(s["trials"].size(), 2u);
  EXPECT_EQ(s["trials"][0]["result"], "equilibrium") << s["trials"][0]["reason"];
  EXPECT_EQ(s["trials"][1]["result"], "failed") << s["trials"][1]["reason"];
}

// The same trials, step for step and bit for bit, on one and two threads (the vertical cut:
// 2400 triangles, enough for the execution layer to run the step on both).
TEST(StabilityRegression, TrialsAreTheSameOnOneAndTwoThreads) {
  const std::string args = " --bounds 1.5 1.65 --tolerance 1 --threads ";
  const auto one = stability(example("vertical_cut/scenario.yaml"), args + "1", "stab_threads1");
  const auto two = stability(example("vertical_cut/scenario.yaml"), args + "2", "stab_threads2");
  ASSERT_TRUE(one.is_object());
  ASSERT_TRUE(two.is_object());
  ASSERT_EQ(one["trials"].size(), two["trials"].size());
  for (std::size_t k = 0; k < one["trials"].size(); ++k) {
    EXPECT_EQ(one["trials"][k]["result"], two["trials"][k]["result"]) << k;
    EXPECT_EQ(one["trials"][k]["steps"], two["trials"][k]["steps"]) << k;
    EXPECT_EQ(one["trials"][k]["max_displacement_m"].get<double>(), two["trials"][k]["max_displacement_m"].get<double>())
        << k;
    EXPECT_EQ(one["trials"][k]["unbalanced_ratio"].get<double>(), two["trials"][k]["unbalanced_ratio"].get<double>())
        << k;
  }
  EXPECT_EQ(one["factor_of_safety"].get<double>(), two["factor_of_safety"].get<double>());
}

// The vertical cut with Drucker-Prager (phi = 0: von Mises with k = c, which in plane
// strain is Tresca's c): the factor of safety of the Mohr-Coulomb material, 1.578 on
// cut_h1.msh. It stands at 1.5625 and fails at 1.59375 (the Mohr-Coulomb bisection's
// neighbouring trials; the Drucker-Prager bisection ends at 1.578125 as well).
TEST(StabilityRegression, VerticalCutWithDruckerPragerHasTheMohrCoulombFactorOfSafety) {
  const auto s = stability(example("vertical_cut/scenario.yaml"),
                           " --set materials.clay.model=drucker_prager --set stability.failure_displacement=0.1"
                           " --bounds 1.5625 1.59375 --tolerance 1 --threads 1",
                           "stab_cut_dp");
  ASSERT_TRUE(s.is_object());
  ASSERT_EQ(s["trials"].size(), 2u);
  EXPECT_EQ(s["trials"][0]["result"], "equilibrium") << s["trials"][0]["reason"];
  EXPECT_EQ(s["trials"][1]["result"], "failed") << s["trials"][1]["reason"];
}
