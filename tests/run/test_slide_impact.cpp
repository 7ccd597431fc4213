// A slide entering a reservoir (docs/theory.md §12): a block sliding without friction down a
// 45-degree bank is measured where it meets the still level (time, speed, thickness,
// mass, the bank's angle, the depth) against its closed form, and a restart before or
// after the impact keeps the same record; a reservoir with no bank is an error at its key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli_util.hpp"
#include "io/scenario.hpp"
#include "run/runner.hpp"
#include "run/summary.hpp"
#include "water/heller_hager.hpp"

namespace fs = std::filesystem;
using nlohmann::ordered_json;

namespace {

const std::string kBank = std::string(DSDEM_TEST_DATA_DIR) + "/reservoir/bank.yaml";

ordered_json run_bank(const fs::path& dir, long stop_at_step = 0, const std::string& restart = "") {
  auto sc = dsdem::io::load_scenario(kBank, {});
  auto prepared = dsdem::run::prepare_run(sc, (dir / "work").string());
  dsdem::run::RunOptions options;
  options.output_dir = (dir / "out").string();
  options.quiet = true;
  options.threads = 1;
  options.write_fields = false;
  options.stop_at_step = stop_at_step;
  options.restart_from = restart;
  dsdem::run::run(prepared, options);
  return dsdem::run::read_summary(dir / "out")["heller_hager"];
}

}  // namespace

TEST(SlideImpact, BlockOnABankEntersTheReservoirAsTheClosedFormSays) {
  const ordered_json h = run_bank(dsdem::test::fresh_dir("slide_impact"));
  const double g = 9.81, sin45 = std::sqrt(0.5);
  // The block's lower corner starts at z = 8 - sqrt(2) m, 4 m is the level.
  const double travel = (8.0 - std::sqrt(2.0) - 4.0) / sin45;
  const double t_exact = std::sqrt(2.0 * travel / (g * sin45));
  ASSERT_TRUE(h["slide_entered_water"].get<bool>());
  EXPECT_DOUBLE_EQ(h["depth_m"].get<double>(), 4.0);
  EXPECT_NEAR(h["bank_slope_deg"].get<double>(), 45.0, 1e-9);
  EXPECT_NEAR(h["shoreline_m"][0].get<double>(), 6.0, 1e-9);
  // Seen at the first history row (every 5 ms) after the corner crosses the level; the
  // contact springs lag the rigid block by a few ms.
  const double t = h["impact_time_s"].get<double>();
  EXPECT_GE(t, t_exact);
  EXPECT_LT(t, t_exact + 0.015);
  EXPECT_NEAR(h["slide_speed_mps"].get<double>(), g * sin45 * t, 0.02 * g * sin45 * t);
  EXPECT_NEAR(h["slide_thickness_m"].get<double>(), 1.0, 0.02);
  EXPECT_NEAR(h["slide_mass_kg_per_m"].get<double>(), 2500.0 * 2.0, 1e-9);
  // The estimate is Heller & Hager's of the measured slide.
  dsdem::water::SlideImpact s;
  s.speed = h["slide_speed_mps"].get<double>();
  s.thickness = h["slide_thickness_m"].get<double>();
  s.mass = h["slide_mass_kg_per_m"].get<double>();
  s.slope_deg = 45.0;
  s.depth = 4.0;
  const dsdem::water::ImpulseWave w = dsdem::water::heller_hager(s);
  EXPECT_NEAR(h["amplitude_m"].get<double>(), w.amplitude_m, 1e-9);
  EXPECT_EQ(h["inside_validity"].get<bool>(), w.inside_validity());
}

TEST(SlideImpact, ARestartBeforeOrAfterTheImpactKeepsItsRecord) {
  const ordered_json whole = run_bank(dsdem::test::fresh_dir("slide_impact_whole"));
  for (long stop : {3000L, 3600L}) {  // t = 0.91 s before the impact, 1.09 s after it
    const fs::path dir = dsdem::test::fresh_dir("slide_impact_restart_" + std::to_string(stop));
    const ordered_json first = run_bank(dir, stop);
    EXPECT_EQ(first["slide_entered_water"].get<bool>(), stop == 3600L);
    const ordered_json rest = run_bank(dir, 0, (dir / "out" / "checkpoint.h5").string());
    EXPECT_EQ(rest.dump(), whole.dump()) << "stopped at step " << stop;
  }
}

TEST(SlideImpact, AReservoirWithoutABankIsAnErrorAtItsKey) {
  auto sc = dsdem::io::load_scenario(kBank, {"reservoir.x=[12, 20]", "reservoir.level=-1"});
  try {
    dsdem::run::prepare_run(sc, dsdem::test::fresh_dir("slide_impact_bad").string());
    FAIL() << "a level below the bed must be an error";
  } catch (const dsdem::io::ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("reservoir"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no bed below the level -1 m"), std::string::npos) << e.what();
  }
}
