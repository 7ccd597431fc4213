#include "io/json_file.hpp"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "io/io_test_util.hpp"

namespace dsdem::io {
namespace {

using nlohmann::ordered_json;
using test::bits;
using test::ScratchDir;

// A summary-like document: keys with units, nested blocks, a value that is not finite.
ordered_json summary_like() {
  ordered_json s;
  s["title"] = "Dr2 \"shear\"\ttab 座滑 ±σ";
  s["steps"] = 3022;
  s["dt_s"] = 0.000595596242563987;
  s["dt_adaptive"] = true;
  s["blocked_time_s"] = std::nan("");
  s["final_energies"] = ordered_json::object();
  s["final_energies"]["unit"] = "J_per_m";
  s["final_energies"]["kinetic"] = 1.0;
  s["final_energies"]["strain"] = -std::numeric_limits<double>::infinity();
  s["gauges"] = ordered_json::array();
  s["gauges"].push_back({{"name", "G1"}, {"final_displacement_m", ordered_json::array({1.5, -0.25})}});
  s["empty"] = ordered_json::array();
  return s;
}

TEST(JsonFile, WritesKeysInInsertionOrderWithUnitsAndNonFiniteAsNull) {
  ScratchDir dir;
  write_json_file(dir / "summary.json", summary_like());
  EXPECT_EQ(test::read_text(dir / "summary.json"),
            "{\n"
            "  \"title\": \"Dr2 \\\"shear\\\"\\ttab 座滑 ±σ\",\n"
            "  \"steps\": 3022,\n"
            "  \"dt_s\": 0.000595596242563987,\n"
            "  \"dt_adaptive\": true,\n"
            "  \"blocked_time_s\": null,\n"
            "  \"final_energies\": {\n"
            "    \"unit\": \"J_per_m\",\n"
            "    \"kinetic\": 1.0,\n"
            "    \"strain\": null\n"
            "  },\n"
            "  \"gauges\": [\n"
            "    {\n"
            "      \"name\": \"G1\",\n"
            "      \"final_displacement_m\": [\n"
            "        1.5,\n"
            "        -0.25\n"
            "      ]\n"
            "    }\n"
            "  ],\n"
            "  \"empty\": []\n"
            "}\n");
  EXPECT_EQ(test::list_dir(dir.path()), std::vector<std::string>{"summary.json"});  // no temporary left
}

TEST(JsonFile, DoublesKeepAPointAndRoundTripBitwise) {
  EXPECT_EQ(ordered_json(1.0).dump(), "1.0");
  EXPECT_EQ(ordered_json(-0.0).dump(), "-0.0");
  EXPECT_EQ(ordered_json(0.1).dump(), "0.1");
  EXPECT_EQ(ordered_json(1e300).dump(), "1e+300");
  EXPECT_EQ(ordered_json(1.5e-5).dump(), "1.5e-05");
  EXPECT_EQ(ordered_json(1e15).dump(), "1e+15");
  EXPECT_EQ(ordered_json(123456789012345.0).dump(), "123456789012345.0");

  ScratchDir dir;
  const std::vector<double> values = {0.1,    1.0 / 3.0, 2.0 / 3.0, std::numbers::pi, 1e-300, 5e-324, DBL_MAX,
                                      DBL_MIN, -1.5e-7,  1e21,      1e22, 123456789012345678.0, 0.30000000000000004,
                                      -2759.7736011814018};
  write_json_file(dir / "values.json", ordered_json(values));
  const auto back = read_json_file(dir / "values.json");
  ASSERT_TRUE(back.is_array());
  ASSERT_EQ(back.size(), values.size());
  for (std::size_t k = 0; k < values.size(); ++k) {
    ASSERT_TRUE(back[k].is_number_float()) << back[k];
    EXPECT_EQ(bits(back[k].get<double>()), bits(values[k])) << back[k];
  }
}

TEST(JsonFile, ReadsBackWhatItWroteInFileOrder) {
  ScratchDir dir;
  write_json_file(dir / "summary.json", summary_like());
  const ordered_json s = read_json_file(dir / "summary.json");
  std::vector<std::string> keys;
  for (const auto& [k, v] : s.items()) keys.push_back(k);
  EXPECT_EQ(keys, (std::vector<std::string>{"title", "steps", "dt_s", "dt_adaptive", "blocked_time_s",
                                            "final_energies", "gauges", "empty"}));
  EXPECT_EQ(s["title"], "Dr2 \"shear\"\ttab 座滑 ±σ");
  EXPECT_TRUE(s["steps"].is_number_integer());
  EXPECT_EQ(s["steps"].get<long>(), 3022);
  EXPECT_EQ(s["dt_s"].get<double>(), 0.000595596242563987);
  EXPECT_TRUE(s["blocked_time_s"].is_null());
  EXPECT_EQ(s["final_energies"]["unit"], "J_per_m");
  EXPECT_EQ(s["gauges"][0]["final_displacement_m"][1].get<double>(), -0.25);
}

TEST(JsonFile, PythonParsesIt) {
  if (!test::python_has("json")) GTEST_SKIP() << "no system Python";
  ScratchDir dir;
  write_json_file(dir / "summary.json", summary_like());
  const std::string cmd =
      std::string(test::kSystemPython) +
      " -c 'import json, sys; d = json.load(open(sys.argv[1], encoding=\"utf-8\")); "
      "assert list(d) == [\"title\", \"steps\", \"dt_s\", \"dt_adaptive\", \"blocked_time_s\", \"final_energies\", "
      "\"gauges\", \"empty\"], d; assert d[\"blocked_time_s\"] is None and d[\"steps\"] == 3022, d; "
      "assert d[\"gauges\"][0][\"final_displacement_m\"] == [1.5, -0.25], d' " +
      (dir / "summary.json").string();
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

TEST(JsonFile, InvalidUtf8IsReplacedNotFatal) {
  ScratchDir dir;
  write_json_file(dir / "bad.json", ordered_json{{"scenario", std::string("caf\xe9.yaml")}});
  EXPECT_EQ(read_json_file(dir / "bad.json")["scenario"], "caf\xef\xbf\xbd.yaml");
}

TEST(JsonFile, ErrorsNameTheFileAndLine) {
  ScratchDir dir;
  const auto missing = dir / "missing" / "summary.json";
  try {
    write_json_file(missing, ordered_json::object());
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(e.what(), missing.string());
  }
  try {
    (void)read_json_file(missing);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(e.what(), missing.string());
  }
  const auto broken = dir / "broken.json";
  std::ofstream(broken) << "{\n  \"steps\": 3,\n  \"dt_s\": ,\n}\n";
  try {
    (void)read_json_file(broken);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(e.what(), broken.string());
    EXPECT_CONTAINS(e.what(), "line 3");
  }
}

}  // namespace
}  // namespace dsdem::io
