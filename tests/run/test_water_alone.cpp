// Water alone (docs/theory.md §11, §12): a reservoir of moving water held by the faces of a
// continuous zone, with no discrete zone, runs as any scenario; what needs a slide (the impact,
// the slide's speed, Heller & Hager's estimate) is marked not applicable; a reservoir with
// nothing to compute, or water with no face to hold it, is refused at its key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli_util.hpp"
#include "io/scenario.hpp"
#include "run/check.hpp"
#include "run/runner.hpp"
#include "run/summary.hpp"

namespace fs = std::filesystem;
using nlohmann::ordered_json;

namespace {

const std::string kTank = std::string(DSDEM_TEST_DATA_DIR) + "/reservoir/tank.yaml";

std::string prepare_error(const dsdem::io::Scenario& sc) {
  try {
    dsdem::run::prepare_run(sc, dsdem::test::fresh_dir("water_alone_refused").string());
  } catch (const dsdem::io::ScenarioError& e) {
    return e.what();
  }
  return "";
}

// history.csv: the header's names and the rows of numbers.
struct History {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  double at(std::size_t row, const std::string& name) const {
    const auto c = static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
    EXPECT_LT(c, names.size()) << "no column " << name;
    return c < names.size() ? rows[row][c] : NAN;
  }
};

History read_history(const fs::path& file) {
  History h;
  std::istringstream lines(dsdem::test::read_text(file));
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string c; std::getline(row, c, ',');) cells.push_back(c);
    if (h.names.empty()) {
      h.names = cells;
      continue;
    }
    std::vector<double> values;
    for (const std::string& c : cells) values.push_back(std::strtod(c.c_str(), nullptr));
    h.rows.push_back(values);
  }
  return h;
}

}  // namespace

TEST(WaterAlone, AScenarioWithWaterAndWallsButNoDiscreteZoneIsAcceptedAndChecked) {
  const auto sc = dsdem::io::load_scenario(kTank);
  auto run = dsdem::run::prepare_run(sc, dsdem::test::fresh_dir("water_alone_check").string());
  EXPECT_FALSE(run.shore.has_value()) << "no slide, no shore";
  ASSERT_TRUE(run.moving_water.has_value());
  // 0.4 m x 0.2 m at 0.01 m: 40 columns of 20 rows.
  EXPECT_EQ(run.moving_water->fluid.size(), 800u);
  EXPECT_NEAR(run.moving_water->depth, 0.2, 1e-9);
  EXPECT_GT(run.moving_water->walls.size(), 0u) << "the tank's faces carry the walls";
  const std::string report = dsdem::run::check_report(run);
  EXPECT_NE(report.find("water alone"), std::string::npos) << report;
}

// A reservoir at rest with no slide to enter it and no moving water computes nothing.
TEST(WaterAlone, AStillReservoirWithNothingToEnterItIsRefusedAtItsKey) {
  const std::string text =
      "title: nothing to compute\n"
      "mesh: {file: tank.geo, element_size: 0.05}\n"
      "materials:\n"
      "  wall: {E: 1.0e8, nu: 0.25, rho: 2500}\n"
      "regions:\n"
      "  - {group: tank, material: wall, zone: continuous}\n"
      "boundaries:\n"
      "  - {group: tank, type: fixed}\n"
      "reservoir:\n"
      "  level: 0.2\n"
      "  x: [0, 0.4]\n"
      "time: {end: 0.1}\n";
  const std::string file = std::string(DSDEM_TEST_DATA_DIR) + "/reservoir/still_tank.yaml";
  const auto sc = dsdem::io::parse_scenario(text, file);
  const std::string e = prepare_error(sc);
  // File, line (the section's value: line 10, column 3) and key.
  EXPECT_NE(e.find(file + ":10:3: reservoir: the model has no discrete zone"), std::string::npos) << e;
  EXPECT_NE(e.find("without reservoir.sph its water does not move"), std::string::npos) << e;
}

// Water hanging in the middle of the tank, far from every face: the tank's faces are coupled
// only near the water, so nothing would hold it.
TEST(WaterAlone, WaterWithNoFaceToHoldItIsRefusedAtItsKey) {
  const auto sc = dsdem::io::load_scenario(
      kTank, {"reservoir.sph.fill=[{rectangle: [[0.19, 0.3], [0.21, 0.32]], level: 0.32}]", "reservoir.sph.freeboard=0"});
  const std::string e = prepare_error(sc);
  EXPECT_NE(e.find("tank.yaml:18:5: reservoir.sph: no solid face holds the water"), std::string::npos) << e;
}

// The tank at rest stays at rest: 2 s of settle, then 0.5 s (about 2 400 water steps) free.
TEST(WaterAlone, ATankAtRestStaysAtRestWithTheHydrostaticPressureOnItsBed) {
  const fs::path dir = dsdem::test::fresh_dir("water_alone_tank");
  const auto sc = dsdem::io::load_scenario(
      kTank, {"reservoir.sph.pressure=[{name: deep, polyline: [[0.35, 0.05], [0.05, 0.05]]}]"});
  auto prepared = dsdem::run::prepare_run(sc, (dir / "work").string());
  dsdem::run::RunOptions options;
  options.output_dir = (dir / "out").string();
  options.quiet = true;
  options.threads = 1;
  options.write_fields = false;
  dsdem::run::run(prepared, options);
  const ordered_json s = dsdem::run::read_summary(dir / "out");

  // Nothing enters the water: the slide's outputs are marked not applicable, not made up.
  const ordered_json& hh = s["heller_hager"];
  EXPECT_FALSE(hh["applicable"].get<bool>());
  EXPECT_FALSE(hh.contains("impact_time_s"));
  EXPECT_FALSE(hh.contains("slide_speed_mps"));
  EXPECT_FALSE(hh.contains("amplitude_m"));
  EXPECT_FALSE(s["moving_water"].contains("slide_at_gauges_s"));

  const double g = 9.81, H = 0.2, rho = 1000.0, dp = 0.01;
  const double scale = std::sqrt(g * H);
  const ordered_json& mw = s["moving_water"];
  EXPECT_EQ(mw["excluded"]["particles"].get<long>(), 0);
  EXPECT_EQ(mw["escaped_particles"].get<long>(), 0);
  // At rest: no particle faster than 1e-2 sqrt(g H), the bound docs/validation.md §5.6 sets
  // for the ripple the release from the settle leaves on the free surface (here 6.4e-3, the
  // peak at 0.22 s; no higher over 3 s), and the surface within a tenth of a spacing of its
  // level at step 0.
  EXPECT_LT(mw["max_speed"]["speed_mps"].get<double>(), 1e-2 * scale);
  EXPECT_LT(std::abs(s["max_wave_amplitude_m"].get<double>()), 0.1 * dp);

  const History h = read_history(dir / "out" / "history.csv");
  ASSERT_GT(h.rows.size(), 10u);
  const std::size_t last = h.rows.size() - 1;
  // The pressure 0.05 m above the bed, 0.15 m below the level: rho g depth within 2 %
  // (docs/validation.md §5.1: 0.74 % below the first three rows at c0 = 20 sqrt(g H)).
  const double p_deep = rho * g * (H - 0.05);
  EXPECT_NEAR(h.at(last, "deep_peak_pressure_Pa"), p_deep, 0.02 * p_deep);
  EXPECT_NEAR(-h.at(last, "deep_force_y_N_per_m") / 0.3, p_deep, 0.02 * p_deep) << "the mean over the line";
  // The tank carries its own weight and the water's (800 particles of rho dp^2) to 0.5 %.
  const double tank = 2500.0 * g * (0.6 * 0.5 - 0.4 * 0.4), water = 800 * rho * dp * dp * g;
  EXPECT_NEAR(h.at(last, "tank_reaction_y_N_per_m"), tank + water, 0.005 * water);
  EXPECT_NEAR(h.at(last, "tank_reaction_x_N_per_m"), 0.0, 0.005 * water);
}
