// dsdem run / render / report of a run with moving (SPH) water: the water's plots, the water
// drawn with the rock in the renders (matched by time), the report's reservoir wave section
// with the numbers of summary.json beside the Heller & Hager estimate, and the estimate-only
// section of a dry reservoir.
#include <gtest/gtest.h>

#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "cli_util.hpp"

using namespace dsdem::test;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

bool is_png(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  return in.gcount() == 8 && std::string(sig, 8) == std::string("\x89PNG\r\n\x1a\n", 8) &&
         fs::file_size(p) > 2000;
}

// A number as the report prints it (dsdem_plotlib.fmt_num, for 1e-3 <= |v| < 1e6): four
// significant digits in fixed point, integer digits never rounded away, trailing zeros dropped.
std::string report_number(double v) {
  const int decimals = std::max(0, 3 - static_cast<int>(std::floor(std::log10(std::fabs(v)))));
  std::string s = fmt::format("{:.{}f}", v, decimals);
  if (s.find('.') != std::string::npos) {
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

std::string cell(double v) { return "<td class=\"num\">" + report_number(v) + "</td>"; }

// The <section> of the report with this id, "" if absent.
std::string section(const std::string& html, const std::string& id) {
  const auto a = html.find("<section id=\"" + id + "\">");
  if (a == std::string::npos) return "";
  return html.substr(a, html.find("</section>", a) - a);
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + what.size())) ++n;
  return n;
}

json read_json(const fs::path& p) { return json::parse(read_text(p)); }
void write_json(const fs::path& p, const json& j) { std::ofstream(p) << j.dump(2); }

fs::path copy_of(const fs::path& out, const std::string& name) {
  const fs::path dir = fresh_dir(name);
  fs::copy(out, dir, fs::copy_options::recursive);
  fs::remove_all(dir / "render");
  return dir;
}

// The block sliding into the flume of tests/data/reservoir (moving water, 7 frames); one per
// test process.
class WaterPost : public ::testing::Test {
 protected:
  static inline fs::path out_;
  static void SetUpTestSuite() {
    out_ = fresh_dir("post_water");
    const auto c = run_dsdem("run " + std::string(DSDEM_TEST_DATA_DIR) + "/reservoir/flume.yaml -o " +
                             out_.string() + " --threads 1 -q --no-plots");
    ASSERT_EQ(c.exit_code, 0) << c.output;
  }
  static void TearDownTestSuite() { fs::remove_all(out_); }

  // Renders frame `frame` of `out` with and without the water, and checks with
  // check_water_render.py that the water sits where its particles are.
  static void expect_water_drawn(const fs::path& out, int frame) {
    SCOPED_TRACE(out.string() + " frame " + std::to_string(frame));
    const std::string f = std::to_string(frame);
    const fs::path png = out / "render" / fmt::format("velocity_{:06d}.png", frame);
    auto c = run_dsdem("render " + out.string() + " --frames " + f + " --water none -q --jobs 1");
    ASSERT_EQ(c.exit_code, 0) << c.output;
    const fs::path dry = out / "without_water.png";
    fs::rename(png, dry);
    c = run_dsdem("render " + out.string() + " --frames " + f + " -q --jobs 1");
    ASSERT_EQ(c.exit_code, 0) << c.output;
    ASSERT_TRUE(is_png(png));
    c = run_command("/usr/bin/python3 " + std::string(DSDEM_SOURCE_DIR) + "/tests/app/check_water_render.py " +
                    out.string() + " " + f + " " + png.string() + " " + dry.string());
    EXPECT_EQ(c.exit_code, 0) << c.output;
    EXPECT_NE(c.output.find("OK"), std::string::npos) << c.output;
  }
};

}  // namespace

// dsdem plot (which `dsdem run` calls at its end) and dsdem report.
TEST_F(WaterPost, PlotsAndReportShowTheReservoirWaveBesideHellerHager) {
  auto c = run_dsdem("plot " + out_.string() + " -q");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  for (const char* f : {"water_surface.png", "wave_amplitude.png", "wave_decay.png", "water_runup.png",
                        "water_forces.png"})
    EXPECT_TRUE(is_png(out_ / "plots" / f)) << f;
  // Every water column has its figure: none is left over for the catch-all.
  EXPECT_FALSE(fs::exists(out_ / "plots" / "other.png"));

  c = run_dsdem("report " + out_.string() + " -q");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const std::string html = read_text(out_ / "report.html");
  const std::string wave = section(html, "reservoir-wave");
  ASSERT_FALSE(wave.empty()) << "no reservoir wave section";
  EXPECT_NE(wave.find("<h2>Reservoir wave</h2>"), std::string::npos);
  EXPECT_TRUE(section(html, "wave").empty()) << "the estimate-only section is for dry reservoirs";

  const json s = read_json(out_ / "summary.json");
  const json& mw = s["moving_water"];
  const json& hh = s["heller_hager"];
  const double a = s["max_wave_amplitude_m"], a_hh = hh["amplitude_m"];
  ASSERT_TRUE(hh["inside_validity"].get<bool>());  // the flume's slide is inside H&H's range
  // The computed maximum, where and when, beside the estimate and their ratio.
  EXPECT_NE(wave.find(cell(a) + cell(a_hh) + cell(a / a_hh)), std::string::npos) << a << " " << a_hh;
  EXPECT_NE(wave.find(cell(hh["height_m"])), std::string::npos);
  EXPECT_NE(wave.find(cell(mw["max_wave_amplitude"]["x_m"])), std::string::npos);
  EXPECT_NE(wave.find(cell(mw["max_wave_amplitude"]["time_s"])), std::string::npos);
  EXPECT_NE(wave.find("Inside the range of Heller &amp; Hager"), std::string::npos);
  // Run-up, overtopping, force, energy, each with its number.
  EXPECT_NE(wave.find("<b>wall</b></td>" + cell(mw["runup"]["wall"]["elevation_m"])), std::string::npos);
  EXPECT_NE(wave.find(cell(s["max_runup_m"]["wall"])), std::string::npos);
  EXPECT_NE(wave.find("<b>wall_top</b>"), std::string::npos);
  EXPECT_NE(wave.find("<b>wall_face</b></td>" + cell(mw["force_on_curves"]["wall_face"]["max_force_N_per_m"])),
            std::string::npos);
  EXPECT_NE(wave.find(cell(mw["energy_gain_J_per_m"])), std::string::npos);
  EXPECT_NE(wave.find("<b>mid</b>"), std::string::npos);  // the gauge and its period
  // The five water plots are in the section (and only there).
  EXPECT_EQ(count(wave, "src=\"data:image/png;base64,"), 5u);
  EXPECT_EQ(count(section(html, "plots"), "water_surface.png"), 0u);
  // The snapshot the report rendered: the last frame, with the water.
  EXPECT_TRUE(is_png(out_ / "render" / "velocity_000006.png"));
}

TEST_F(WaterPost, RenderDrawsTheWaterMatchedByTime) {
  expect_water_drawn(out_, 6);  // after the block entered the water

  // The water frames numbered unlike the field frames: the render finds the water of the
  // same moment by time, not by number.
  const fs::path out = copy_of(out_, "post_water_renumbered");
  std::string pvd = read_text(out / "water.pvd");
  for (int i = 6; i >= 0; --i) {
    const std::string from = fmt::format("water_{:06d}.vtu", i), to = fmt::format("water_{:06d}.vtu", i + 40);
    fs::rename(out / "water" / from, out / "water" / to);
    pvd = std::regex_replace(pvd, std::regex(from), to);
  }
  std::ofstream(out / "water.pvd") << pvd;
  expect_water_drawn(out, 4);

  auto c = run_dsdem("render " + out.string() + " --frames last --water pressure -q --jobs 1");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_TRUE(is_png(out / "render" / "velocity_000006.png"));
  c = run_dsdem("render " + out.string() + " --frames last --water colour");
  EXPECT_NE(c.exit_code, 0);
  EXPECT_NE(c.output.find("--water"), std::string::npos) << c.output;
  c = run_dsdem("render " + out.string() + " --frames last --water-clim 5,1");
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("--water-clim 5,1"), std::string::npos) << c.output;
  fs::remove_all(out);
}

// The computed H_M is one wave's crest to its trough, as Heller & Hager measure it: the
// largest primary wave among the gauges beyond the shoreline, named; none seen, a note says so.
TEST_F(WaterPost, ReportsTheLargestPrimaryWaveAsTheComputedHeight) {
  const fs::path out = copy_of(out_, "post_water_height");
  ASSERT_EQ(run_dsdem("plot " + out.string() + " -q").exit_code, 0);
  json s = read_json(out / "summary.json");
  ASSERT_TRUE(s["heller_hager"]["slide_entered_water"].get<bool>());
  const double H_hh = s["heller_hager"]["height_m"];
  auto gauge = [](const char* name, json height, double x) {
    return json::object({{"name", name}, {"height_m", height}, {"distance_m", x}});
  };
  s["heller_hager"]["gauges"] =
      json::array({gauge("near", 0.0312, 1.5), gauge("far", 0.0451, 3.25), gauge("end", nullptr, 6.0)});
  write_json(out / "summary.json", s);
  auto c = run_dsdem("report " + out.string() + " -q --no-render");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  std::string wave = section(read_text(out / "report.html"), "reservoir-wave");
  const auto row = wave.find("maximum wave height H_M");
  ASSERT_NE(row, std::string::npos) << wave.substr(0, 2000);
  const std::string cells = wave.substr(row, wave.find("</tr>", row) - row);
  EXPECT_NE(cells.find("(far)"), std::string::npos) << cells;
  EXPECT_NE(cells.find(cell(0.0451) + cell(H_hh) + cell(0.0451 / H_hh)), std::string::npos) << cells;
  EXPECT_EQ(wave.find("No gauge beyond the shoreline saw a whole primary wave"), std::string::npos);
  // Where: its gauge's distance from the shoreline, beside Heller & Hager's x_M.
  const auto where = wave.find("distance of H_M from the shoreline");
  ASSERT_NE(where, std::string::npos);
  EXPECT_NE(wave.find(cell(3.25) + cell(s["heller_hager"]["distance_of_max_height_m"]), where), std::string::npos);

  s["heller_hager"]["gauges"] = json::array({gauge("end", nullptr, 6.0)});
  write_json(out / "summary.json", s);
  c = run_dsdem("report " + out.string() + " -q --no-render");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  wave = section(read_text(out / "report.html"), "reservoir-wave");
  EXPECT_NE(wave.find("No gauge beyond the shoreline saw a whole primary wave"), std::string::npos);
  fs::remove_all(out);
}

// Why the comparison is missing; and a reservoir without moving water: the Heller & Hager
// estimate alone, as before.
TEST_F(WaterPost, ReportSaysWhyThereIsNoEstimateAndKeepsTheDryReservoirSection) {
  const fs::path out = copy_of(out_, "post_water_variants");
  ASSERT_EQ(run_dsdem("plot " + out.string() + " -q").exit_code, 0);  // once, for the three reports
  const json run = read_json(out / "summary.json");
  json s = run;
  // The largest amplitude against a wall is said to be the reflection there (only then).
  ASSERT_GT(s["moving_water"]["max_wave_amplitude"]["amplitude_m"].get<double>(), 0.0);
  for (const bool at_wall : {true, false}) {
    s["moving_water"]["max_wave_amplitude"]["at_wall"] = at_wall;
    write_json(out / "summary.json", s);
    ASSERT_EQ(run_dsdem("report " + out.string() + " -q --no-render").exit_code, 0);
    const std::string w = section(read_text(out / "report.html"), "reservoir-wave");
    EXPECT_EQ(w.find("stands against a wall") != std::string::npos, at_wall) << at_wall;
  }
  // Particles taken out of the water are said (only when there are some).
  ASSERT_EQ(s["moving_water"]["excluded"]["particles"].get<int>(), 0);
  EXPECT_EQ(section(read_text(out / "report.html"), "reservoir-wave").find("taken out of the water"), std::string::npos);
  s["moving_water"]["excluded"]["particles"] = 3;
  s["moving_water"]["excluded"]["fraction"] = 0.0075;
  s["moving_water"]["excluded"]["first"] = json::object({{"id", 7}, {"time_s", 1.25}});
  write_json(out / "summary.json", s);
  ASSERT_EQ(run_dsdem("report " + out.string() + " -q --no-render").exit_code, 0);
  const std::string ex = section(read_text(out / "report.html"), "reservoir-wave");
  EXPECT_NE(ex.find("3 water particles (0.75 % of the water) left its weakly compressible range"), std::string::npos)
      << ex.substr(0, 3000);
  EXPECT_NE(ex.find("the first at t = 1.25 s"), std::string::npos);
  s = run;
  s["heller_hager"] = json::object({{"still_level_m", 2.0}, {"depth_m", 2.0}, {"slide_entered_water", false}});
  write_json(out / "summary.json", s);
  auto c = run_dsdem("report " + out.string() + " -q --no-render");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  std::string wave = section(read_text(out / "report.html"), "reservoir-wave");
  EXPECT_NE(wave.find("did not enter the reservoir"), std::string::npos) << wave.substr(0, 2000);
  EXPECT_NE(wave.find(cell(s["max_wave_amplitude_m"])), std::string::npos);

  s.erase("heller_hager");
  write_json(out / "summary.json", s);
  c = run_dsdem("report " + out.string() + " -q --no-render");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  wave = section(read_text(out / "report.html"), "reservoir-wave");
  EXPECT_NE(wave.find("has no heller_hager block"), std::string::npos) << wave.substr(0, 2000);

  s = run;
  for (const char* k : {"moving_water", "max_wave_amplitude_m", "max_runup_m"}) s.erase(k);
  write_json(out / "summary.json", s);
  c = run_dsdem("report " + out.string() + " -q --no-render");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const std::string html = read_text(out / "report.html");
  EXPECT_TRUE(section(html, "reservoir-wave").empty());
  const std::string est = section(html, "wave");
  ASSERT_FALSE(est.empty());
  EXPECT_NE(est.find("Impulse wave (Heller &amp; Hager estimate)"), std::string::npos);
  EXPECT_NE(est.find(cell(s["heller_hager"]["amplitude_m"])), std::string::npos);
  fs::remove_all(out);
}
