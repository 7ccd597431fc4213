// The command line: version, check, run, and bad input that exits cleanly.
#include <gtest/gtest.h>

#include <fstream>

#include "cli_util.hpp"

using namespace dsdem::test;
namespace fs = std::filesystem;

TEST(Cli, VersionPrintsVersionAndCommit) {
  const auto c = run_dsdem("--version");
  EXPECT_EQ(c.exit_code, 0);
  EXPECT_NE(c.output.find("dsdem 0."), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("git "), std::string::npos) << c.output;
}

// The wave commands run in CLI11 callbacks: main must not print the help after them
// (it did, after every successful `wave generate` and `wave spectrum`); a bare `dsdem` shows it.
TEST(Cli, WaveCommandsPrintTheirResultsWithoutTheHelp) {
  const fs::path d = fresh_dir("cli_wave");
  fs::create_directories(d);
  const std::string wave = (d / "w.csv").string();
  const auto g = run_dsdem("wave generate --duration 4 --t1 1 --t2 2.5 --iterations 2 --no-plot -o " + wave);
  EXPECT_EQ(g.exit_code, 0) << g.output;
  EXPECT_NE(g.output.find("wrote " + wave), std::string::npos) << g.output;
  EXPECT_EQ(g.output.find("Usage:"), std::string::npos) << g.output;
  const auto s = run_dsdem("wave spectrum " + wave + " --units m/s2 --n 10 --no-plot -o " + (d / "s.csv").string());
  EXPECT_EQ(s.exit_code, 0) << s.output;
  EXPECT_NE(s.output.find("read " + wave), std::string::npos) << s.output;
  EXPECT_EQ(s.output.find("Usage:"), std::string::npos) << s.output;
  const auto bare = run_dsdem("");
  EXPECT_EQ(bare.exit_code, 0);
  EXPECT_NE(bare.output.find("Usage:"), std::string::npos) << bare.output;
  fs::remove_all(d);
}

TEST(Cli, CheckPrintsModelTimeStepAndEstimate) {
  const auto c = run_dsdem("check " + example("elastic_slope/scenario.yaml"));
  EXPECT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("triangles"), std::string::npos);
  EXPECT_NE(c.output.find("stable dt"), std::string::npos);
  EXPECT_NE(c.output.find("controlled by triangle"), std::string::npos);
  EXPECT_NE(c.output.find("of wall time"), std::string::npos);
  EXPECT_NE(c.output.find("scenario OK"), std::string::npos);
}

TEST(Cli, RunWritesFieldsHistoriesLogAndSummary) {
  const fs::path out = fresh_dir("cli_run");
  const auto c = run_dsdem("run " + example("elastic_slope/scenario.yaml") + " -o " + out.string() +
                           " --set time.end=0.02 --set output.field_interval=0.01 --threads 1 -q");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  for (const char* f : {"summary.json", "history.csv", "fields.pvd", "dsdem.log", "slope.msh"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const std::string summary = read_text(out / "summary.json");
  for (const char* key : {"\"elements\"", "\"nodes\"", "\"joints\"", "\"steps\"", "\"dt_s\"", "\"end_time_s\"",
                          "\"threads\"", "\"wall_time_s\"", "\"energy_balance_error\""})
    EXPECT_NE(summary.find(key), std::string::npos) << key;
  const std::string history = read_text(out / "history.csv");
  EXPECT_EQ(history.rfind("time_s,step,stage,kinetic_J_per_m,strain_J_per_m", 0), 0u) << history.substr(0, 200);
  EXPECT_NE(history.find("crest_displacement_x_m"), std::string::npos);
  const std::string pvd = read_text(out / "fields.pvd");
  EXPECT_NE(pvd.find("fields/fields_000002.vtu"), std::string::npos) << pvd;
  fs::remove_all(out);
}

// Regression: reading the mesh through the Gmsh API set the OpenMP thread count to 1,
// so a run without --threads used one core whatever the machine had.
TEST(Cli, RunWithoutThreadsOptionUsesTheOpenMPDefault) {
  const fs::path out = fresh_dir("cli_threads");
  setenv("OMP_NUM_THREADS", "3", 1);  // not the machine's count, so that a reset to 1 or nproc shows
  const auto c = run_dsdem("run " + example("elastic_slope/scenario.yaml") + " -o " + out.string() +
                           " --set time.end=0.002 -q --no-plots --no-fields");
  setenv("OMP_NUM_THREADS", "1", 1);
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(read_text(out / "summary.json").find("\"threads\": 3"), std::string::npos)
      << read_text(out / "summary.json");
  fs::remove_all(out);
}

TEST(Cli, BadScenarioExitsWithCode2AndWritesNothing) {
  const fs::path dir = fresh_dir("cli_bad");
  fs::create_directories(dir);
  fs::copy_file(example("elastic_slope/slope.geo"), dir / "slope.geo");
  std::string text = read_text(example("elastic_slope/scenario.yaml"));
  text.replace(text.find("nu: 0.25"), 8, "nu: 0.55");
  std::ofstream(dir / "bad.yaml") << text;
  const fs::path out = dir / "out";
  const auto c = run_dsdem("run " + (dir / "bad.yaml").string() + " -o " + out.string());
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("bad.yaml:11:9:"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("materials.limestone.nu: 0.55 is out of range"), std::string::npos) << c.output;
  EXPECT_FALSE(fs::exists(out));
  // A group the mesh lacks is found after meshing, still before anything is written.
  text = read_text(example("elastic_slope/scenario.yaml"));
  text.replace(text.find("group: base"), 11, "group: bse");
  std::ofstream(dir / "bad2.yaml") << text;
  const auto c2 = run_dsdem("run " + (dir / "bad2.yaml").string() + " -o " + out.string());
  EXPECT_EQ(c2.exit_code, 2) << c2.output;
  EXPECT_NE(c2.output.find("no curve or point group 'bse' (did you mean 'base'?)"), std::string::npos) << c2.output;
  EXPECT_FALSE(fs::exists(out));
  const auto c3 = run_dsdem("run " + (dir / "missing.yaml").string());
  EXPECT_EQ(c3.exit_code, 2);
  EXPECT_NE(c3.output.find("cannot open the scenario file"), std::string::npos) << c3.output;
  fs::remove_all(dir);
}

TEST(Cli, TooLargeFixedTimeStepIsRejectedNamingTheElement) {
  const auto c = run_dsdem("check " + example("elastic_slope/scenario.yaml") + " --set time.dt=0.01");
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("exceeds the stable time step"), std::string::npos) << c.output;
}

// Regression: what model building logs (the penalty joint stiffness, which docs/theory.md §3
// says is logged) went to the terminal before dsdem.log was opened: missing from the
// log, and printed even with -q. Now it is in the log, in `check`, and quiet stays quiet.
TEST(Cli, ModelBuildingMessagesReachTheLogAndCheckButNotAQuietTerminal) {
  const fs::path dir = fresh_dir("cli_build_log");
  fs::create_directories(dir);
  fs::copy_file(std::string(DSDEM_TEST_DATA_DIR) + "/mesh/square.geo", dir / "square.geo");
  std::ofstream(dir / "s.yaml") << R"(mesh: {file: square.geo, element_size: 0.25}
materials:
  rock: {E: 10.0e9, nu: 0.25, rho: 2500}
regions:
  - {group: block, material: rock, zone: discrete}
joints:
  default: {ft: 1.0e6, c: 4.0e6, phi: 30, GI: 100, GII: 1000, penalty: 10}
boundaries:
  - {group: bottom, type: fixed}
time: {end: 0.001}
)";
  const auto chk = run_dsdem("check " + (dir / "s.yaml").string());
  ASSERT_EQ(chk.exit_code, 0) << chk.output;
  EXPECT_NE(chk.output.find("model      joints 'block': kn = p*E/h from the penalty rule with h the local element size"),
            std::string::npos) << chk.output;
  const fs::path out = dir / "out";
  const auto c = run_dsdem("run " + (dir / "s.yaml").string() + " -o " + out.string() + " -q --no-plots --threads 1");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_EQ(c.output.find("penalty rule"), std::string::npos) << c.output;
  const std::string log = read_text(out / "dsdem.log");
  EXPECT_NE(log.find("joints 'block': kn = p*E/h from the penalty rule"), std::string::npos) << log;
  fs::remove_all(dir);
}
