// Regression: the Dr2 shear-sliding scenario (examples/dr2/shear_sliding.yaml) on a very
// coarse mesh (element_size 16 m, ~830 triangles) and a short run: 1.5 s of gravity, then
// 3 s of the design earthquake with failure on. Runs in a few seconds.
//
// Two kinds of check (docs/dr2.md §6). Up to t = 2.4 s the motion is a smooth function of
// the input: 62 runs differing only in the order of their sums (triangle numberings)
// agree there to 5e-4 m and within 3 broken joints, so tight goldens catch a change of
// physics. After it the column breaks up, and rounding picks one of three ways it does:
// at 4.5 s the same 62 runs gave gauge 1 10.55-12.00 m, gauge 3 5.55-6.08 or 11.24-11.38 m
// and 187-195 or 250-265 broken joints. The late checks are that envelope with a margin,
// not one run's numbers: a compiler, flag or summation change can move a run to another
// of these outcomes.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli_util.hpp"

namespace {

// Golden numbers at t = 2.4 s (shear_sliding.yaml, 16 m): one run with the artificial
// wave matched with its free vibration (docs/artificial-wave-seeds.md). With the wave
// before it (dsdem 0.1.0, session 19: 2.2216 m, 2.2428 m, 150) the 62-run spread there was
// u1 2.2214-2.2219 m, u3 2.2426-2.2428 m, 149-152 broken joints; the late envelope below
// is of those runs (the run of the new wave at 4.5 s: 10.57 m, 5.96 m, 259, inside it).
constexpr double GOLDEN_ELEMENTS = 830;
constexpr double EARLY_TIME = 2.4;          // s
constexpr double GOLDEN_EARLY_U1 = 2.2226;  // |u| of gauge 1, m
constexpr double GOLDEN_EARLY_U3 = 2.2438;  // |u| of gauge 3, m
constexpr double GOLDEN_EARLY_BROKEN = 146; // broken joints (17 of them on L1 from the start)
constexpr double GOLDEN_GRAVITY_BROKEN = 128;  // at t = 2.0 s, identical in all 62 runs
// Envelope at t = 4.5 s: the 62 runs' range, widened by 10 % of its value.
constexpr double LATE_U1_MIN = 10.55 * 0.9, LATE_U1_MAX = 12.00 * 1.1;      // m
constexpr double LATE_U3_MIN = 5.55 * 0.9, LATE_U3_MAX = 11.38 * 1.1;       // m
constexpr double LATE_BROKEN_MIN = 187 * 0.9, LATE_BROKEN_MAX = 265 * 1.1;

const char* const kCoarseRun = " -q --no-fields --no-plots --set mesh.element_size=16"
                               " --set stages.0.duration=1.5 --set stages.1.duration=3.0"
                               " --set output.history_interval=0.05";

using dsdem::test::example;
using dsdem::test::fresh_dir;
using dsdem::test::read_text;
using dsdem::test::run_dsdem;

// The rows of a CSV history, each as name -> value.
std::vector<std::map<std::string, double>> history_rows(const std::string& csv) {
  std::istringstream in(csv);
  std::string header, line;
  std::getline(in, header);
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::map<std::string, double> row;
    std::istringstream hs(header), ls(line);
    std::string h, v;
    while (std::getline(hs, h, ',') && std::getline(ls, v, ',')) row[h] = std::stod(v);
    rows.push_back(std::move(row));
  }
  return rows;
}

// The row written nearest to time t, s.
const std::map<std::string, double>& row_at(const std::vector<std::map<std::string, double>>& rows, double t) {
  const auto* best = &rows.front();
  for (const auto& r : rows)
    if (std::abs(r.at("time_s") - t) < std::abs(best->at("time_s") - t)) best = &r;
  return *best;
}

double gauge_distance(const std::map<std::string, double>& row, int gauge) {
  const std::string g = "gauge" + std::to_string(gauge);
  return std::hypot(row.at(g + "_displacement_x_m"), row.at(g + "_displacement_y_m"));
}

double json_number(const std::string& json, const std::string& key) {
  const auto p = json.find("\"" + key + "\"");
  if (p == std::string::npos) return std::nan("");
  return std::stod(json.substr(json.find(':', p) + 1));
}

}  // namespace

TEST(Dr2Regression, CoarseShearSlidingStartsToSlide) {
  const auto out = fresh_dir("dr2");
  const auto r = run_dsdem("run " + example("dr2/shear_sliding.yaml") + " -o " + out.string() + " --threads 1" +
                           kCoarseRun);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string summary = read_text(out / "summary.json");
  const auto rows = history_rows(read_text(out / "history.csv"));
  ASSERT_FALSE(rows.empty());

  // Model: the reconstructed profile meshed at 16 m.
  EXPECT_EQ(json_number(summary, "elements"), GOLDEN_ELEMENTS);
  // The numbering the goldens are of (the default), recorded for a rerun.
  EXPECT_NE(summary.find("\"triangle_order\": \"spatial\""), std::string::npos) << summary;

  // Smooth phase: gravity and the first 0.9 s of shaking, before the column breaks up.
  const auto& gravity = row_at(rows, 2.0);
  EXPECT_NEAR(gravity.at("broken_joints"), GOLDEN_GRAVITY_BROKEN, 2);
  const auto& early = row_at(rows, EARLY_TIME);
  ASSERT_NEAR(early.at("time_s"), EARLY_TIME, 0.03);
  EXPECT_NEAR(gauge_distance(early, 1), GOLDEN_EARLY_U1, 0.01 * GOLDEN_EARLY_U1);
  EXPECT_NEAR(gauge_distance(early, 3), GOLDEN_EARLY_U3, 0.01 * GOLDEN_EARLY_U3);
  EXPECT_NEAR(early.at("broken_joints"), GOLDEN_EARLY_BROKEN, 5);

  // Break-up: within the envelope of the ways rounding lets the column break (4.5 s).
  const auto& last = rows.back();
  ASSERT_NEAR(last.at("time_s"), 4.5, 0.03);
  EXPECT_GE(gauge_distance(last, 1), LATE_U1_MIN);
  EXPECT_LE(gauge_distance(last, 1), LATE_U1_MAX);
  EXPECT_GE(gauge_distance(last, 3), LATE_U3_MIN);
  EXPECT_LE(gauge_distance(last, 3), LATE_U3_MAX);
  EXPECT_GE(last.at("broken_joints"), LATE_BROKEN_MIN);
  EXPECT_LE(last.at("broken_joints"), LATE_BROKEN_MAX);
  // The column moves out and down (toward the river, x > 0; down, y < 0), and the energy
  // books balance (the 62 runs: at most 1.0e-2 at any row).
  EXPECT_GT(last.at("gauge1_displacement_x_m"), 0.0);
  EXPECT_LT(last.at("gauge1_displacement_y_m"), 0.0);
  EXPECT_LT(std::abs(last.at("energy_balance_error")), 2e-2);
}

// The same run on two threads writes the same history and crack log, byte for byte
// (deterministic sums for any thread count), through the break-up.
TEST(Dr2Regression, CoarseShearSlidingIsTheSameOnOneAndTwoThreads) {
  std::string history[2], cracks[2];
  for (int threads = 1; threads <= 2; ++threads) {
    const auto out = fresh_dir("dr2_threads" + std::to_string(threads));
    const auto r = run_dsdem("run " + example("dr2/shear_sliding.yaml") + " -o " + out.string() + " --threads " +
                             std::to_string(threads) + kCoarseRun);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    history[threads - 1] = read_text(out / "history.csv");
    cracks[threads - 1] = read_text(out / "cracks.csv");
  }
  ASSERT_GT(history[0].size(), 1000u);
  EXPECT_TRUE(history[0] == history[1]) << "history.csv differs between 1 and 2 threads";
  EXPECT_TRUE(cracks[0] == cracks[1]) << "cracks.csv differs between 1 and 2 threads";
}
