// The scenario's water (docs/theory.md §8) end to end: a wet slope's outputs carry the pore
// pressure and the water's work; bad water input stops before step 0 with file, line
// and key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli_util.hpp"
#include "io/scenario.hpp"
#include "run/runner.hpp"
#include "run/summary.hpp"
#include "run/water.hpp"

namespace fs = std::filesystem;

namespace {

const std::string kSlope = std::string(DSDEM_SOURCE_DIR) + "/examples/elastic_slope/scenario.yaml";

// The error text of preparing the slope with these overrides ("" if it prepares).
std::string prepare_error(const std::vector<std::string>& overrides) {
  const fs::path dir = dsdem::test::fresh_dir("water_input");
  try {
    auto sc = dsdem::io::load_scenario(kSlope, overrides);
    dsdem::run::prepare_run(sc, (dir / "work").string());
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// The elastic slope (x 0-100 m, toe at 15 m, crest at 40 m) with a pool at 25 m: the
// history has the water's work, the summary its final value, the frames the pore pressure.
TEST(WaterInput, WetSlopeWritesPorePressureAndTheWaterWork) {
  const fs::path dir = dsdem::test::fresh_dir("water_run");
  auto sc = dsdem::io::load_scenario(kSlope, {"time.end=0.02", "water.level=25"});
  auto prepared = dsdem::run::prepare_run(sc, (dir / "work").string());
  dsdem::run::RunOptions options;
  options.output_dir = (dir / "out").string();
  options.quiet = true;
  options.threads = 1;
  const auto result = dsdem::run::run(prepared, options);
  EXPECT_LT(result.energy_balance_error, 1e-2);
  std::ifstream h(dir / "out" / "history.csv");
  std::string header;
  std::getline(h, header);
  EXPECT_NE(header.find("water_work"), std::string::npos) << header;
  const nlohmann::ordered_json s = dsdem::run::read_summary(dir / "out");
  EXPECT_NE(s["final_energies"]["water_work"].get<double>(), 0.0);
  std::ifstream f(dir / "out" / "fields" / "fields_000000.vtu");
  std::stringstream vtu;
  vtu << f.rdbuf();
  EXPECT_NE(vtu.str().find("pore_pressure"), std::string::npos);
}

TEST(WaterInput, ALineThatDoesNotSpanTheModelIsAnError) {
  const std::string e = prepare_error({"water.line=[[10, 30], [90, 20]]"});
  EXPECT_NE(e.find("water.line"), std::string::npos) << e;
  EXPECT_NE(e.find("spans x = 10 to 90 m"), std::string::npos) << e;
}

TEST(WaterInput, BadWaterValuesAreErrorsWithTheirKey) {
  EXPECT_NE(prepare_error({"water.level=20", "water.density=0"}).find("water.density"), std::string::npos);
  EXPECT_NE(prepare_error({"water.line=[[0, 30], [0, 20]]"}).find("x must increase"), std::string::npos);
  EXPECT_NE(prepare_error({"water.density=1000"}).find("missing level"), std::string::npos);
  EXPECT_NE(prepare_error({"water.level=20", "water.line=[[0, 1], [100, 2]]"}).find("give one of level, line and ru"),
            std::string::npos);
  const std::string crack = prepare_error({"water.level=20", "water.cracks=[{curve: back, level: 30}]"});
  EXPECT_NE(crack.find("water.cracks[0].curve"), std::string::npos) << crack;
  EXPECT_NE(crack.find("no mesh curve 'back'"), std::string::npos) << crack;
  // A dry section keeps its values checked: a bad one is still an error.
  EXPECT_NE(prepare_error({"water.dry=true", "water.density=-1"}).find("water.density"), std::string::npos);
  EXPECT_EQ(prepare_error({"water.dry=true", "water.level=20"}), "");
}

// A pore-pressure ratio: the line is the ground surface of the slope (toe at 15 m, the
// face rising at 45 degrees to the crest at 40 m), the pressure ru rho g times the depth.
TEST(WaterInput, PorePressureRatioActsBelowTheGroundSurface) {
  const fs::path dir = dsdem::test::fresh_dir("water_ru");
  auto sc = dsdem::io::load_scenario(kSlope, {"water.ru=0.3"});
  const auto prepared = dsdem::run::prepare_run(sc, (dir / "work").string());
  const auto& model = prepared.model;
  const auto w = dsdem::run::water_setup(sc.stages.front().water, model, sc.gravity);
  for (const auto& [x, z] : {std::pair{10.0, 15.0}, std::pair{47.5, 27.5}, std::pair{80.0, 40.0}, std::pair{100.0, 40.0}})
    EXPECT_NEAR(w.line.elevation(x), z, 1e-9) << x;
  EXPECT_NEAR(w.unit_weight(0), 0.3 * 2650.0 * 9.81, 1e-9);
  EXPECT_NE(prepare_error({"water.ru=0.3", "water.level=20"}).find("give one of level, line and ru"), std::string::npos);
  EXPECT_NE(prepare_error({"water.ru=1.5"}).find("water.ru"), std::string::npos);
}
