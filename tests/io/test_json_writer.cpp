#include "io/json_writer.hpp"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "io/io_test_util.hpp"

namespace dsdem::io {
namespace {

using test::bits;
using test::ScratchDir;

TEST(JsonWriter, EscapesStrings) {
  EXPECT_EQ(json_string("plain"), "\"plain\"");
  EXPECT_EQ(json_string("quote\" backslash\\ slash/"), R"("quote\" backslash\\ slash/")");
  EXPECT_EQ(json_string("tab\tnl\ncr\rbs\bff\f"), R"("tab\tnl\ncr\rbs\bff\f")");
  EXPECT_EQ(json_string(std::string("nul\0x\x01\x1f", 7)), R"("nul\u0000x\u0001\u001f")");
  EXPECT_EQ(json_string("座滑 ±σ"), "\"座滑 ±σ\"");  // UTF-8 passes through
}

TEST(JsonWriter, ScalarsAndNonFiniteAsNull) {
  EXPECT_EQ(Json().dump(), "null");
  EXPECT_EQ(Json(true).dump(), "true");
  EXPECT_EQ(Json(false).dump(), "false");
  EXPECT_EQ(Json(42).dump(), "42");
  EXPECT_EQ(Json(std::int64_t{-9007199254740993}).dump(), "-9007199254740993");
  EXPECT_EQ(Json(1.0).dump(), "1.0");
  EXPECT_EQ(Json(-0.0).dump(), "-0.0");
  EXPECT_EQ(Json(0.1).dump(), "0.1");
  EXPECT_EQ(Json(1e300).dump(), "1e+300");
  EXPECT_EQ(Json(std::nan("")).dump(), "null");
  EXPECT_EQ(Json(std::numeric_limits<double>::infinity()).dump(), "null");
  EXPECT_EQ(Json(-std::numeric_limits<double>::infinity()).dump(), "null");
  EXPECT_EQ(Json("text").dump(), "\"text\"");
  EXPECT_EQ(Json(std::string("s")).dump(), "\"s\"");
}

TEST(JsonWriter, DoublesRoundTripBitwise) {
  const std::vector<double> values = {0.1,     1.0 / 3.0, 2.0 / 3.0, std::numbers::pi, 1e-300,
                                      5e-324,  DBL_MAX,   DBL_MIN,   -1.5e-7,          1e21,
                                      1e22,    123456789012345678.0, 0.30000000000000004};
  Json a = Json::array();
  for (double v : values) a.push_back(v);
  std::string text = a.dump(-1);
  ASSERT_EQ(text.front(), '[');
  ASSERT_EQ(text.back(), ']');
  const auto parts = test::split(text.substr(1, text.size() - 2), ',');
  ASSERT_EQ(parts.size(), values.size());
  for (std::size_t k = 0; k < values.size(); ++k)
    EXPECT_EQ(bits(std::strtod(parts[k].c_str(), nullptr)), bits(values[k])) << parts[k];
}

TEST(JsonWriter, NestedStructuresCompactAndPretty) {
  Json s = Json::object();
  s["scenario"] = "dr2 \"shear\"";
  s["max_displacement_m"] = 163.25;
  s["blocked"] = true;
  s["blocked_time_s"] = std::nan("");
  s["gauges"].push_back(Json::object({{"name", "G1"}, {"peak_velocity_m_per_s", 22.0}}));
  s["gauges"].push_back(Json::object({{"name", "G2"}, {"history", Json::array({1, 2.5, nullptr})}}));
  s["empty_array"] = Json::array();
  s["empty_object"] = Json::object();
  s["max_displacement_m"] = 170.5;  // replaces in place, order kept

  EXPECT_EQ(s.dump(-1),
            R"({"scenario":"dr2 \"shear\"","max_displacement_m":170.5,"blocked":true,)"
            R"("blocked_time_s":null,"gauges":[{"name":"G1","peak_velocity_m_per_s":22.0},)"
            R"({"name":"G2","history":[1,2.5,null]}],"empty_array":[],"empty_object":{}})");

  Json small = Json::object({{"a", Json::array({1, Json::object({{"b", false}})})}, {"c", "d"}});
  EXPECT_EQ(small.dump(2),
            "{\n"
            "  \"a\": [\n"
            "    1,\n"
            "    {\n"
            "      \"b\": false\n"
            "    }\n"
            "  ],\n"
            "  \"c\": \"d\"\n"
            "}");
}

TEST(JsonWriter, WrongContainerUseThrows) {
  Json a = Json::array();
  EXPECT_THROW(a["key"], std::logic_error);
  Json o = Json::object();
  EXPECT_THROW(o.push_back(1), std::logic_error);
  Json n = 3.5;
  EXPECT_THROW(n["key"], std::logic_error);
}

TEST(JsonWriter, WritesFileAtomicallyAndPythonParsesIt) {
  ScratchDir dir;
  Json s = Json::object({{"name", "tab\there \u00e9"},
                         {"values", Json::array({0.1, 1.0 / 3.0, std::nan(""), 7})},
                         {"nested", Json::object({{"ok", true}})}});
  write_json_file(dir / "summary.json", s);
  EXPECT_EQ(test::read_text(dir / "summary.json"), s.dump() + "\n");
  EXPECT_EQ(test::list_dir(dir.path()), std::vector<std::string>{"summary.json"});

  if (!test::python_has("json")) GTEST_SKIP() << "no system Python";
  const std::string cmd =
      std::string(test::kSystemPython) +
      " -c 'import json, sys; d = json.load(open(sys.argv[1], encoding=\"utf-8\")); "
      "assert d == {\"name\": \"tab\\there \\u00e9\", \"values\": [0.1, 1/3, None, 7], "
      "\"nested\": {\"ok\": True}}, d' " +
      (dir / "summary.json").string();
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

TEST(JsonWriter, UnwritableDirectoryThrowsWithPath) {
  ScratchDir dir;
  const auto path = dir / "missing" / "summary.json";
  try {
    write_json_file(path, Json::object());
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(e.what(), path.string());
  }
}

}  // namespace
}  // namespace dsdem::io
