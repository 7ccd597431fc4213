// The runner through the library: a short run's summary read back with run::read_summary,
// and the runner's checkpoint state written and read back.
#include "run/runner.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli_util.hpp"
#include "io/checkpoint.hpp"
#include "io/scenario.hpp"
#include "run/restart.hpp"
#include "run/summary.hpp"

namespace fs = std::filesystem;

namespace {

const std::string kSlope = std::string(DSDEM_SOURCE_DIR) + "/examples/elastic_slope/scenario.yaml";

dsdem::run::PreparedRun short_slope(const fs::path& work) {
  const auto sc = dsdem::io::load_scenario(kSlope, {"time.end=0.02"});
  return dsdem::run::prepare_run(sc, work.string());
}

TEST(Run, SummaryReadsBackWithItsKeysInOrder) {
  const fs::path dir = dsdem::test::fresh_dir("run_summary");
  auto prepared = short_slope(dir / "work");
  dsdem::run::RunOptions options;
  options.output_dir = (dir / "out").string();
  options.quiet = true;
  options.threads = 1;
  const auto result = dsdem::run::run(prepared, options);
  ASSERT_EQ(result.summary_path, (dir / "out" / "summary.json").string());

  const nlohmann::ordered_json s = dsdem::run::read_summary(dir / "out");
  std::vector<std::string> keys;
  for (const auto& [k, v] : s.items()) keys.push_back(k);
  const std::vector<std::string> expected{
      "title",        "scenario",      "overrides",     "dsdem_version", "elements",     "nodes",
      "joints",       "broken_joints", "fragments",     "steps",        "dt_s",
      "dt_controlled_by", "dt_adaptive", "triangle_order", "dt_last_s", "dt_last_controlled_by",
      "end_time_s",   "threads",       "wall_time_s",   "checkpoint",   "element_steps_per_s",
      "energy_balance_error", "completed", "final_energies", "gauges"};
  EXPECT_EQ(keys, expected);
  EXPECT_EQ(s["steps"].get<long>(), result.steps);
  EXPECT_EQ(s["energy_balance_error"].get<double>(), result.energy_balance_error);  // bit for bit
  EXPECT_EQ(s["dt_s"].get<double>(), prepared.dt);
  EXPECT_EQ(s["elements"].get<long>(), static_cast<long>(prepared.model.triangles.size()));
  EXPECT_TRUE(s["completed"].get<bool>());
  EXPECT_EQ(s["checkpoint"], result.checkpoint_path);
  EXPECT_EQ(s["final_energies"]["unit"], "J_per_m");  // plane strain: per metre of thickness
  ASSERT_EQ(s["gauges"].size(), 2u);
  EXPECT_EQ(s["gauges"][0]["name"], "crest");
  EXPECT_EQ(s["gauges"][1]["final_displacement_m"].size(), 2u);
  EXPECT_GT(s["gauges"][0]["max_displacement_m"].get<double>(), 0.0);
}

TEST(Run, RunnerStateRoundTripsAndRejectsAnotherTimeStep) {
  const fs::path dir = dsdem::test::fresh_dir("run_state");
  const auto prepared = short_slope(dir / "work");
  dsdem::run::RunnerState s;
  s.time = 0.0125;
  s.stage = 0;
  s.stage_starts = {0.0};
  s.stage_end = 0.02;
  s.peak_kinetic = 3.5;
  s.next_field = 0.05;
  s.next_history = 0.013;
  s.max_balance_error = 1e-3;
  s.history_rows = 13;
  s.fields_frames = 1;
  s.wall_time_before = 2.5;
  s.gauges = {{0.1, 0.2, 0.003}, {0.4, 0.5, 0.006}};
  {
    dsdem::io::CheckpointWriter w(dir / "state.h5");
    w.put("time", s.time);
    dsdem::run::write_runner_state(w, s, prepared);
    w.commit();
  }
  const auto back = dsdem::run::read_runner_state(dsdem::io::CheckpointReader(dir / "state.h5"), prepared);
  EXPECT_EQ(back.time, s.time);
  EXPECT_EQ(back.stage_starts, s.stage_starts);
  EXPECT_EQ(back.stage_end, s.stage_end);
  EXPECT_EQ(back.peak_kinetic, s.peak_kinetic);
  EXPECT_EQ(back.next_field, s.next_field);
  EXPECT_EQ(back.next_history, s.next_history);
  EXPECT_EQ(back.max_balance_error, s.max_balance_error);
  EXPECT_EQ(back.history_rows, s.history_rows);
  EXPECT_EQ(back.fields_frames, s.fields_frames);
  EXPECT_EQ(back.wall_time_before, s.wall_time_before);
  ASSERT_EQ(back.gauges.size(), 2u);
  EXPECT_EQ(back.gauges[1].time_of_max_speed, 0.006);

  auto other = prepared;
  other.dt *= 0.5;
  try {
    (void)dsdem::run::read_runner_state(dsdem::io::CheckpointReader(dir / "state.h5"), other);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("it was made with dt ="), std::string::npos) << e.what();
  }
}

}  // namespace
