// dsdem plot / render / report (post-processing): the pictures, curves and report
// a user gets from an output folder, on a real (short) run and on a synthetic fixture that
// has the files and columns later solver versions add (cracks, broken joints, fragments,
// contacts, plate reaction, two stages).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <regex>

#include "cli_util.hpp"
// The helpers of the post commands live in the dsdem executable, not in the library:
// compile them into this test too, to test run_plot() in-process.
#include "app/post_commands.cpp"  // NOLINT(bugprone-suspicious-include)

using namespace dsdem::test;
namespace fs = std::filesystem;

namespace {

bool is_png(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  return in.gcount() == 8 && std::string(sig, 8) == std::string("\x89PNG\r\n\x1a\n", 8) &&
         fs::file_size(p) > 2000;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + what.size())) ++n;
  return n;
}

bool have_ffmpeg() { return std::system("command -v ffmpeg > /dev/null 2>&1") == 0; }

// Fails clearly (instead of with a CLI11 parse error) while main.cpp does not register the
// post commands yet.
void expect_registered(const Command& c, const std::string& sub) {
  ASSERT_EQ(c.output.find("was not expected"), std::string::npos)
      << "dsdem has no '" << sub << "' subcommand: main.cpp must call add_post_commands(app)\n" << c.output;
}

// A short elastic-slope run (3 field frames), one per test process.
class PostRun : public ::testing::Test {
 protected:
  static inline fs::path out_;
  static void SetUpTestSuite() {
    out_ = fresh_dir("post_run");
    const auto c = run_dsdem("run " + example("elastic_slope/scenario.yaml") + " -o " + out_.string() +
                             " --set time.end=0.02 --set output.field_interval=0.01 --threads 1 -q");
    ASSERT_EQ(c.exit_code, 0) << c.output;
  }
  static void TearDownTestSuite() { fs::remove_all(out_); }
};

// A copy of tests/data/post/fractured (the commands write into the folder).
fs::path fractured_copy(const std::string& name) {
  const fs::path dir = fresh_dir(name);
  fs::create_directories(dir);
  fs::copy(fs::path(DSDEM_TEST_DATA_DIR) / "post" / "fractured", dir, fs::copy_options::recursive);
  return dir;
}

// A 12 x 6 x 6 m block of tetrahedra (371 of them) settling on a fixed base: 3 field frames of a
// 3D run in under a second, written and run by the test.
const char* kBlockGeo = R"(SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 12, 6, 6};
Physical Volume("rock") = {1};
MeshSize{ PointsOf{ Volume{1}; } } = 2.2;
e = 1e-3;
Physical Surface("base") = Surface In BoundingBox{-e, -e, -e, 12 + e, 6 + e, e};
)";

const char* kBlockScenario = R"(title: block of tetrahedra settling
mesh: {file: block.geo, element_size: 2.2}
materials:
  rock: {E: 1.0e8, nu: 0.25, rho: 2000}
regions:
  - {group: rock, material: rock}
gravity: [0, 0, -9.81]
time: {safety: 0.3}
stages:
  - name: gravity
    duration: 0.2
    boundaries:
      - {group: base, type: fixed}
output: {field_interval: 0.1, history_interval: 0.01}
)";

class PostRun3D : public ::testing::Test {
 protected:
  static inline fs::path dir_, out_;
  static void SetUpTestSuite() {
    dir_ = fresh_dir("post_run3d");
    fs::create_directories(dir_);
    std::ofstream(dir_ / "block.geo") << kBlockGeo;
    std::ofstream(dir_ / "scenario.yaml") << kBlockScenario;
    out_ = dir_ / "out";
    const auto c = run_dsdem("run " + (dir_ / "scenario.yaml").string() + " -o " + out_.string() + " --threads 1 -q");
    ASSERT_EQ(c.exit_code, 0) << c.output;
    ASSERT_TRUE(fs::exists(out_ / "fields" / "fields_000002.vtu")) << c.output;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
};

}  // namespace

TEST_F(PostRun, PlotWritesGaugeAndEnergyPngsAndListsThem) {
  const auto c = run_dsdem("plot " + out_.string() + " --no-show-stages");
  expect_registered(c, "plot");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  for (const char* f : {"gauge_displacement.png", "gauge_velocity.png", "energies.png"}) {
    EXPECT_TRUE(is_png(out_ / "plots" / f)) << f;
    EXPECT_NE(c.output.find(f), std::string::npos) << c.output;
  }
  // No joint breaks and no contact in this run: no fracture plot. The supports' reactions
  // (the slope's weight on its base) are loads.
  EXPECT_FALSE(fs::exists(out_ / "plots" / "fracture.png"));
  EXPECT_TRUE(is_png(out_ / "plots" / "loads.png"));
}

// Through run_plot(), the helper `dsdem run` calls at the end of a run.
TEST(PostFixture, RunPlotFindsNewColumnsByName) {
  const fs::path out = fractured_copy("post_fx_plot");
  ASSERT_EQ(dsdem::app::run_plot(out.string(), true), 0);
  for (const char* f : {"gauge_displacement.png", "gauge_velocity.png", "energies.png", "fracture.png",
                        "contacts.png", "loads.png", "load_displacement.png", "other.png"})
    EXPECT_TRUE(is_png(out / "plots" / f)) << f;
  EXPECT_EQ(dsdem::app::run_plot((out / "missing").string(), true), 2);
  fs::remove_all(out);
}

TEST_F(PostRun, RenderLastFrameWritesOnePng) {
  const auto c = run_dsdem("render " + out_.string() + " --frames last");
  expect_registered(c, "render");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_TRUE(is_png(out_ / "render" / "velocity_000002.png")) << c.output;
  EXPECT_FALSE(fs::exists(out_ / "render" / "velocity_000000.png"));
}

TEST(PostFixture, RenderDrawsCracksForMaterialAndDamage) {
  const fs::path out = fractured_copy("post_fx_render");
  for (const char* field : {"material", "damage"}) {
    const auto c = run_dsdem("render " + out.string() + " --field " + field + " --frames 1,2 --jobs 1");
    expect_registered(c, "render");
    ASSERT_EQ(c.exit_code, 0) << field << "\n" << c.output;
    EXPECT_TRUE(is_png(out / "render" / (std::string(field) + "_000001.png"))) << field;
    EXPECT_TRUE(is_png(out / "render" / (std::string(field) + "_000002.png"))) << field;
    EXPECT_FALSE(fs::exists(out / "render" / (std::string(field) + "_000000.png"))) << field;
  }
  fs::remove_all(out);
}

TEST_F(PostRun, RenderMovieWritesMp4) {
  if (!have_ffmpeg()) GTEST_SKIP() << "ffmpeg is not installed";
  const auto c = run_dsdem("render " + out_.string() + " --field stress --movie --fps 5 --jobs 1");
  expect_registered(c, "render");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const fs::path mp4 = out_ / "render" / "stress.mp4";
  ASSERT_TRUE(fs::exists(mp4)) << c.output;
  EXPECT_GT(fs::file_size(mp4), 1000u);
  const std::string head = read_text(mp4).substr(0, 12);
  EXPECT_EQ(head.substr(4, 4), "ftyp");  // an MP4 container
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(is_png(out_ / "render" / ("stress_00000" + std::to_string(i) + ".png")));
}

TEST_F(PostRun, ReportIsSelfContainedWithSummaryValuesAndImages) {
  const auto c = run_dsdem("report " + out_.string());
  expect_registered(c, "report");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const std::string html = read_text(out_ / "report.html");
  ASSERT_FALSE(html.empty());
  const std::string summary = read_text(out_ / "summary.json");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(summary, m, std::regex("\"elements\": (\\d+)")));
  EXPECT_NE(html.find("<td class=\"num\">" + m[1].str() + "</td>"), std::string::npos) << "elements " << m[1];
  ASSERT_TRUE(std::regex_search(summary, m, std::regex("\"steps\": (\\d+)")));
  EXPECT_NE(html.find("<td class=\"num\">" + m[1].str() + "</td>"), std::string::npos) << "steps " << m[1];
  EXPECT_NE(html.find("Elastic slope settling under gravity"), std::string::npos);
  EXPECT_NE(html.find("crest"), std::string::npos);                 // gauge table
  EXPECT_NE(html.find("max displacement (m)"), std::string::npos);  // units from key suffixes
  EXPECT_NE(html.find("limestone"), std::string::npos);             // the scenario YAML
  // Plots (made by the report since OUT/plots was missing) and a snapshot, all embedded.
  EXPECT_GE(count(html, "src=\"data:image/png;base64,"), 4u);
  EXPECT_TRUE(fs::exists(out_ / "plots" / "energies.png"));
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
}

TEST(PostCommands, MissingOutputFolderExitsWith2NamingIt) {
  const fs::path missing = fresh_dir("post_missing") / "no_such_out";
  for (const char* sub : {"plot", "render", "report"}) {
    const auto c = run_dsdem(std::string(sub) + " " + missing.string());
    expect_registered(c, sub);
    EXPECT_EQ(c.exit_code, 2) << sub << "\n" << c.output;
    EXPECT_NE(c.output.find(missing.string()), std::string::npos) << sub << "\n" << c.output;
  }
}

TEST(PostCommands, MissingFilesAndBadOptionsExitWith2) {
  const fs::path dir = fresh_dir("post_empty");
  fs::create_directories(dir);
  auto c = run_dsdem("plot " + dir.string());
  expect_registered(c, "plot");
  EXPECT_EQ(c.exit_code, 2);
  EXPECT_NE(c.output.find((dir / "history.csv").string()), std::string::npos) << c.output;
  c = run_dsdem("render " + dir.string());
  EXPECT_EQ(c.exit_code, 2);
  EXPECT_NE(c.output.find((dir / "fields.pvd").string()), std::string::npos) << c.output;
  c = run_dsdem("report " + dir.string());
  EXPECT_EQ(c.exit_code, 2);
  EXPECT_NE(c.output.find((dir / "summary.json").string()), std::string::npos) << c.output;
  fs::remove_all(dir);

  const fs::path out = fractured_copy("post_fx_bad");
  c = run_dsdem("render " + out.string() + " --field no_such_array --frames last");
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("no_such_array"), std::string::npos) << c.output;
  c = run_dsdem("render " + out.string() + " --frames 7");
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("frames 0..2"), std::string::npos) << c.output;
  fs::remove_all(out);
}

TEST(PostCommands, ScriptsDirCanBeOverriddenByEnvironment) {
  EXPECT_EQ(dsdem::app::scripts_dir(), std::string(DSDEM_SOURCE_DIR) + "/scripts");
  ::setenv("DSDEM_SCRIPTS_DIR", "/nonexistent/dsdem-scripts", 1);
  EXPECT_EQ(dsdem::app::scripts_dir(), "/nonexistent/dsdem-scripts");
  testing::internal::CaptureStderr();
  EXPECT_EQ(dsdem::app::run_python_script("plot_history.py", {"x"}), 1);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("/nonexistent/dsdem-scripts/plot_history.py"), std::string::npos) << err;
  ::unsetenv("DSDEM_SCRIPTS_DIR");
}

// A 3D run: per frame the model in perspective and the section through its centre (normal y),
// each frame's time and the plane in the PNG's text.
TEST_F(PostRun3D, RenderWritesThePerspectiveAndTheSectionOfEachChosenFrame) {
  const auto c = run_dsdem("render " + out_.string() + " --frames 1,2 --jobs 1");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  for (const char* f : {"velocity_000001.png", "velocity_section_000001.png", "velocity_000002.png",
                        "velocity_section_000002.png"}) {
    EXPECT_TRUE(is_png(out_ / "render" / f)) << f << "\n" << c.output;
    EXPECT_NE(c.output.find(f), std::string::npos) << c.output;
  }
  EXPECT_FALSE(fs::exists(out_ / "render" / "velocity_000000.png"));
  EXPECT_FALSE(fs::exists(out_ / "render" / "velocity_section_000000.png"));
  const std::string section = read_text(out_ / "render" / "velocity_section_000002.png");
  EXPECT_NE(section.find(std::string("dsdem:section") + '\0' + "y = 3 m"), std::string::npos);
  EXPECT_NE(section.find("dsdem:time"), std::string::npos);
}

TEST_F(PostRun3D, RenderMovieWritesAnMp4OfEachView) {
  if (!have_ffmpeg()) GTEST_SKIP() << "ffmpeg is not installed";
  const auto c = run_dsdem("render " + out_.string() + " --field stress --movie --fps 5 --jobs 1 -q");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  for (const char* name : {"stress.mp4", "stress_section.mp4"}) {
    const fs::path mp4 = out_ / "render" / name;
    ASSERT_TRUE(fs::exists(mp4)) << name << "\n" << c.output;
    EXPECT_GT(fs::file_size(mp4), 1000u) << name;
    EXPECT_EQ(read_text(mp4).substr(4, 4), "ftyp") << name;  // an MP4 container
  }
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(is_png(out_ / "render" / ("stress_00000" + std::to_string(i) + ".png"))) << i;
    EXPECT_TRUE(is_png(out_ / "render" / ("stress_section_00000" + std::to_string(i) + ".png"))) << i;
  }
}

// The 2D errors, and the 3D ones: a plane outside the model; no display and no Xvfb to make one.
TEST_F(PostRun3D, BadInputExitsWith2AndNoDisplayWith1NamingWhy) {
  auto c = run_dsdem("render " + out_.string() + " --field no_such_array --frames last");
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("no_such_array"), std::string::npos) << c.output;
  c = run_dsdem("render " + out_.string() + " --frames 7");
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("frames 0..2"), std::string::npos) << c.output;
  c = run_dsdem("render " + out_.string() + " --frames last --section y=40");
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("misses the model"), std::string::npos) << c.output;
  c = run_command("env -u DISPLAY PATH=/nonexistent " + std::string(DSDEM_BINARY) + " render " + out_.string() +
                  " --frames last --field displacement");
  EXPECT_EQ(c.exit_code, 1) << c.output;
  EXPECT_NE(c.output.find("cannot render the 3D run"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("xvfb"), std::string::npos) << c.output;
  EXPECT_FALSE(fs::exists(out_ / "render" / "displacement_000002.png"));
}

// The report of a 3D run: its key numbers and both pictures of the last frame; no gauge, water or
// run-out section.
TEST_F(PostRun3D, ReportShowsThePerspectiveAndTheSectionOfTheLastFrame) {
  const auto c = run_dsdem("report " + out_.string());
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const std::string html = read_text(out_ / "report.html");
  ASSERT_FALSE(html.empty());
  EXPECT_NE(html.find("<code>render/velocity_000002.png</code>"), std::string::npos);
  EXPECT_NE(html.find("<code>render/velocity_section_000002.png</code>"), std::string::npos);
  EXPECT_NE(html.find("the section y = 3 m"), std::string::npos);
  EXPECT_GE(count(html, "src=\"data:image/png;base64,"), 3u);  // a history plot and the two pictures
  EXPECT_NE(html.find("3D, linear tetrahedra"), std::string::npos);
  EXPECT_NE(html.find("largest displacement (at x, y, z ="), std::string::npos);
  EXPECT_NE(html.find("largest speed of any node"), std::string::npos);
  const std::string summary = read_text(out_ / "summary.json");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(summary, m, std::regex("\"elements\": (\\d+)")));
  EXPECT_NE(html.find("<td>tetrahedra</td><td class=\"num\">" + m[1].str() + "</td>"), std::string::npos);
  for (const char* absent : {"id=\"gauges\"", "id=\"wave\"", "id=\"reservoir-wave\"", "per metre of thickness"})
    EXPECT_EQ(html.find(absent), std::string::npos) << absent;
}
