// The reservoir as moving water from the scenario (docs/theory.md §11): a block sliding down a
// 45-degree bank into a closed flume of SPH water. The run lays the water out, settles it,
// couples it with the solid and writes what engineers read off it (water.pvd, the gauges,
// the wave's amplitude, run-up, overtopping, the force on the end wall, the energy handed to
// the water); a restart gives the same record; bad sections are errors at their keys.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/cli_util.hpp"
#include "io/scenario.hpp"
#include "run/check.hpp"
#include "run/runner.hpp"
#include "run/summary.hpp"
#include "solver/solver.hpp"

namespace fs = std::filesystem;
using nlohmann::ordered_json;

namespace {

const std::string kFlume = std::string(DSDEM_TEST_DATA_DIR) + "/reservoir/flume.yaml";

ordered_json run_flume(const fs::path& dir, const std::vector<std::string>& overrides, long stop_at_step = 0,
                       const std::string& restart = "", bool fields = false) {
  auto sc = dsdem::io::load_scenario(kFlume, overrides);
  auto prepared = dsdem::run::prepare_run(sc, (dir / "work").string());
  dsdem::run::RunOptions options;
  options.output_dir = (dir / "out").string();
  options.quiet = true;
  options.threads = 1;
  options.write_fields = fields;
  options.stop_at_step = stop_at_step;
  options.restart_from = restart;
  dsdem::run::run(prepared, options);
  return dsdem::run::read_summary(dir / "out");
}

std::string file_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// history.csv by column name: its header and its rows of numbers (comment lines skipped).
struct History {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  // The column's index; names.size() when there is none.
  std::size_t column(const std::string& name) const {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
  }
};

History read_history(const fs::path& file) {
  History h;
  std::istringstream lines(file_text(file));
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
    h.rows.push_back(std::move(values));
  }
  return h;
}

std::string prepare_error(const std::vector<std::string>& overrides) {
  try {
    auto sc = dsdem::io::load_scenario(kFlume, overrides);
    dsdem::run::prepare_run(sc, dsdem::test::fresh_dir("moving_water_bad").string());
  } catch (const dsdem::io::ScenarioError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ReservoirWater, ABlockIntoAFlumeRaisesAWaveThatTheRunMeasures) {
  const fs::path dir = dsdem::test::fresh_dir("moving_water_flume");
  // The wave past the gauge and at the end wall: its run-up there jumps at 2.20-2.21 s.
  const ordered_json s = run_flume(dir, {"time.end=2.25"}, 0, "", true);
  const ordered_json& m = s["moving_water"];
  // 11 m x 2 m of water less the bank's wedge, 0.2 m apart: 395 particles, none lost.
  EXPECT_EQ(m["particles"].get<long>(), 395);
  EXPECT_DOUBLE_EQ(m["depth_m"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(m["sound_speed_mps"].get<double>(), 70.0);  // 10 x the expected 7 m/s
  EXPECT_EQ(m["escaped_particles"].get<long>(), 0);
  EXPECT_DOUBLE_EQ(m["coupled_top_m"].get<double>(), 4.0);  // the level plus the default freeboard, the depth
  EXPECT_EQ(m["above_freeboard_particles"].get<long>(), 0);
  EXPECT_EQ(m["faces_without_walls"].get<long>(), 0);  // the block's two triangles carry walls on every face
  // Water that got inside the rock at some history row: at most 6 of the 395 particles.
  EXPECT_LE(m["particles_inside_solid"].get<long>(), 6);
  // The water's steps, never longer than cfl h / c0 = 0.2 x 0.3 m / 70 m/s, cover the 2.25 s.
  EXPECT_GE(static_cast<double>(m["steps"].get<long>()) * 0.2 * 0.3 / 70.0, 2.25);
  // The block enters at about 1 s. The wave it raises passes the gauge 2.5 depths from the
  // shoreline (x = 9 m) at about 2.1 s with the amplitude of Heller & Hager's equation for this
  // slide, within their data's +/-30 % (a_M = 0.50 m).
  // The highest water beyond the block's front, the water heaped against it, stays below a
  // solitary wave's breaking limit 0.78 h.
  ASSERT_TRUE(s["heller_hager"]["slide_entered_water"].get<bool>());
  const double a_M = s["heller_hager"]["amplitude_m"].get<double>(), still = m["still_level_m"].get<double>();
  EXPECT_NEAR(still, 2.0, 0.05);
  const History h = read_history(dir / "out" / "history.csv");
  const std::size_t mid = h.column("mid_eta_m"), gain = h.column("water_energy_gain_J_per_m"),
                    work_col = h.column("moving_water_work_J_per_m");
  ASSERT_LT(std::max({mid, gain, work_col}), h.names.size());
  ASSERT_FALSE(h.rows.empty());
  double gauge = -1e9;
  for (const auto& r : h.rows) gauge = std::max(gauge, 2.0 + r[mid] - still);
  const double gain_end = h.rows.back()[gain], work_end = h.rows.back()[work_col];
  EXPECT_NEAR(gauge / a_M, 1.0, 0.3) << "the crest at the gauge " << gauge << " m against a_M " << a_M << " m";
  const double a = s["max_wave_amplitude_m"].get<double>();
  EXPECT_GT(a, 0.5 * a_M);
  EXPECT_LT(a, 0.78 * 2.0);
  EXPECT_GT(m["max_wave_amplitude"]["time_s"].get<double>(), s["heller_hager"]["impact_time_s"].get<double>());
  // Flagged as against a wall exactly when it stands in the last column before the end wall
  // (13 m; columns 0.2 m wide), never at the bank's shallows.
  EXPECT_EQ(m["max_wave_amplitude"]["at_wall"].get<bool>(), m["max_wave_amplitude"]["x_m"].get<double>() > 12.8);
  // The wave reaches the end wall (x = 13 m) just before the end and has begun to run up it;
  // at rest the wall holds 2 m of water, a force rho g H^2 / 2 = 19.6 kN/m.
  EXPECT_GT(m["runup"]["wall"]["elevation_m"].get<double>(), still + 0.5 * a_M);
  EXPECT_LT(m["runup"]["wall"]["elevation_m"].get<double>(), m["coupled_top_m"].get<double>());
  EXPECT_TRUE(s["max_runup_m"].contains("wall"));
  // Its rise above the wall's own reading at rest (the median of the rows before the block met
  // the water), and that the run ended while it was still rising there.
  const ordered_json& wall = m["runup"]["wall"];
  EXPECT_NEAR(wall["at_rest_elevation_m"].get<double>(), still, 0.2);  // within a spacing
  EXPECT_DOUBLE_EQ(wall["rise_m"].get<double>(),
                   wall["elevation_m"].get<double>() - wall["at_rest_elevation_m"].get<double>());
  EXPECT_GT(wall["rise_m"].get<double>(), 0.0);
  EXPECT_TRUE(wall["peak_at_end_of_run"].get<bool>());
  EXPECT_GT(m["force_on_curves"]["wall_face"]["max_force_N_per_m"].get<double>(), 0.9 * 1000 * 9.81 * 2.0);
  // The water at rest against it (the median before the block met the water): rho g H^2 / 2 to
  // a few per cent.
  EXPECT_NEAR(m["force_on_curves"]["wall_face"]["at_rest_force_N_per_m"].get<double>() / (1000 * 9.81 * 2.0), 1.0,
              0.05);
  EXPECT_GT(m["force_on_curves"]["wall_face"]["peak_pressure_Pa"].get<double>(), 0.9 * 1000 * 9.81 * 2.0);
  EXPECT_DOUBLE_EQ(m["overtopping"]["wall_top"]["volume_m2_per_m"].get<double>(), 0.0);
  // The slide hands energy to the water: more than its kinetic energy at the entry, as it
  // goes on sliding down the frictionless bank under water, but no more than the work the
  // solid did on the water (the two sides' work differ by the time discretisation); the
  // solid's ledger still closes.
  const double ratio = m["energy_handed_to_water_ratio"].get<double>();
  EXPECT_GT(ratio, 0.0);
  const double work = m["moving_water_work_J_per_m"].get<double>();
  EXPECT_LT(work, 0.0);  // the water took work from the solid
  EXPECT_DOUBLE_EQ(work, work_end);
  EXPECT_DOUBLE_EQ(s["final_energies"]["moving_water_work"].get<double>(), work);  // the ledger's own term
  EXPECT_GT(gain_end, 0.0);
  EXPECT_LT(gain_end, -1.01 * work);
  EXPECT_LT(s["energy_balance_error"].get<double>(), 0.01);
  // The files.
  EXPECT_TRUE(fs::exists(dir / "out" / "water.pvd"));
  const std::string pvd = file_text(dir / "out" / "water.pvd");
  const std::string fields = file_text(dir / "out" / "fields.pvd");
  auto frames = [](const std::string& t) {
    std::size_t n = 0;
    for (std::size_t p = t.find("<DataSet"); p != std::string::npos; p = t.find("<DataSet", p + 1)) ++n;
    return n;
  };
  EXPECT_EQ(frames(pvd), frames(fields));
  EXPECT_GE(frames(pvd), 6u);
  const std::string header = file_text(dir / "out" / "history.csv").substr(0, 2000);
  for (const char* c : {"moving_water_work_J_per_m", "mid_eta_m", "wave_amplitude_m", "wall_runup_m",
                        "wall_top_overtopped_m2_per_m", "wall_face_force_x_N_per_m", "wall_face_peak_pressure_Pa",
                        "water_energy_gain_J_per_m"})
    EXPECT_NE(header.find(c), std::string::npos) << c;
}

// The primary wave at the gauge beside Heller & Hager's decay laws (summary.json
// heller_hager.gauges): its first crest is the gauge's highest water after the entry, from
// the still level; the run ends before the trough after it is seen, so trough and height are
// null rather than a trough cut short.
TEST(ReservoirWater, TheWaveAtTheGaugeStandsBesideHellerHagersDecay) {
  const fs::path dir = dsdem::test::fresh_dir("moving_water_decay");
  const ordered_json s = run_flume(dir, {"time.end=2.6"});
  const ordered_json& hh = s["heller_hager"];
  ASSERT_TRUE(hh["slide_entered_water"].get<bool>());
  ASSERT_EQ(hh["gauges"].size(), 1u);
  const ordered_json& g = hh["gauges"][0];
  EXPECT_EQ(g["name"].get<std::string>(), "mid");
  EXPECT_DOUBLE_EQ(g["distance_m"].get<double>(), 5.0);  // the gauge at x = 9 m, the shoreline at x = 4 m
  EXPECT_DOUBLE_EQ(g["relative_distance"].get<double>(), 2.5);
  const double offset = s["moving_water"]["still_level_m"].get<double>() - 2.0, t0 = hh["impact_time_s"].get<double>();
  const History h = read_history(dir / "out" / "history.csv");
  const std::size_t mid = h.column("mid_eta_m"), time = h.column("time_s");
  ASSERT_LT(std::max(mid, time), h.names.size());
  double highest = -1e9, when = 0.0;
  for (const auto& r : h.rows)
    if (r[time] >= t0 && r[mid] - offset > highest) highest = r[mid] - offset, when = r[time];
  const double crest = g["crest_m"].get<double>();
  EXPECT_NEAR(crest, highest, 1e-9);
  EXPECT_NEAR(g["crest_time_s"].get<double>(), when, 1e-9);
  EXPECT_TRUE(g["trough_m"].is_null());
  EXPECT_TRUE(g["height_m"].is_null());
  EXPECT_TRUE(g["height_ratio"].is_null());
  // a(x) = 3/5 (P (x/h)^-1/3)^4/5 h and H(x) = 3/4 (...) h with the run's own P.
  const double P = hh["impulse_product"].get<double>();
  const double a = 0.6 * std::pow(P * std::pow(2.5, -1.0 / 3.0), 0.8) * 2.0;
  EXPECT_NEAR(g["heller_hager_crest_m"].get<double>(), a, 1e-12);
  EXPECT_NEAR(g["heller_hager_height_m"].get<double>(), 1.25 * a, 1e-12);
  EXPECT_NEAR(g["crest_ratio"].get<double>(), crest / a, 1e-12);
  // The crest, 0.46 m, within Heller & Hager's +/-30 % of their law at 2.5 depths.
  EXPECT_NEAR(crest / a, 1.0, 0.3);
  EXPECT_NEAR(hh["decay_onset_relative_distance"].get<double>(), 3.0814, 1e-4);
}

// The water's energy plus the solid's work on it can only fall (viscosity and density
// diffusion take energy out) once the work of the modified dynamic boundary's wall pressure
// is booked (history water_boundary_work, summary moving_water.boundary_work): at every
// history row the water's energy gain stays at or below the solid's work on it plus that
// work, to 1 % of the largest work of the run. Without it the gain exceeds the solid's work
// by up to 21 % while the block presses water against the toe.
// A gauge the sliding block comes up under (x = 5 m, a metre past the shoreline) reads the water
// the block pushes aside and then the block itself: its record stops being the wave when the
// block's rock rises to within two spacings of the surface there (moving_water.slide_at_gauges_s),
// and its primary wave is read before then. A gauge the block never reaches keeps its whole record.
TEST(ReservoirWater, AGaugeTheSlideComesOverIsReadOnlyUntilThen) {
  const fs::path dir = dsdem::test::fresh_dir("moving_water_overrun");
  const ordered_json s = run_flume(dir, {"time.end=2.0", "reservoir.sph.gauges=[{name: mid, x: 9}, {name: toe, x: 5}]"});
  const ordered_json& over = s["moving_water"]["slide_at_gauges_s"];
  EXPECT_TRUE(over["mid"].is_null());
  const double t_entry = s["heller_hager"]["impact_time_s"].get<double>(), t_over = over["toe"].get<double>();
  EXPECT_GT(t_over, t_entry);
  EXPECT_LT(t_over, 2.0);
  const ordered_json& toe = s["heller_hager"]["gauges"][1];
  ASSERT_EQ(toe["name"].get<std::string>(), "toe");
  EXPECT_DOUBLE_EQ(toe["slide_at_gauge_s"].get<double>(), t_over);
  // Its crest is the highest water between the entry and the front's arrival.
  const double offset = s["moving_water"]["still_level_m"].get<double>() - 2.0;
  const History h = read_history(dir / "out" / "history.csv");
  const std::size_t col = h.column("toe_eta_m"), time = h.column("time_s");
  ASSERT_LT(std::max(col, time), h.names.size());
  double highest = -1e9;
  for (const auto& r : h.rows)
    if (r[time] >= t_entry && r[time] < t_over) highest = std::max(highest, r[col] - offset);
  EXPECT_NEAR(toe["crest_m"].get<double>(), highest, 1e-9);
  EXPECT_LT(toe["crest_time_s"].get<double>(), t_over);
}

TEST(ReservoirWater, TheWatersEnergyGainNeverExceedsTheWorkDoneOnIt) {
  const fs::path dir = dsdem::test::fresh_dir("moving_water_energy_rows");
  const ordered_json s = run_flume(dir, {"time.end=2.2"});
  const History h = read_history(dir / "out" / "history.csv");
  const std::size_t gain_col = h.column("water_energy_gain_J_per_m"), work_col = h.column("moving_water_work_J_per_m"),
                    wall_col = h.column("water_boundary_work_J_per_m");
  ASSERT_LT(std::max({gain_col, work_col, wall_col}), h.names.size());
  ASSERT_GT(h.rows.size(), 200u);
  double largest = 0.0, excess_unbooked = -1e300;
  for (const auto& r : h.rows) largest = std::max(largest, std::abs(r[work_col]));
  for (const auto& r : h.rows) {
    EXPECT_LE(r[gain_col], -r[work_col] + r[wall_col] + 0.01 * largest) << "t = " << r[0] << " s";
    excess_unbooked = std::max(excess_unbooked, r[gain_col] + r[work_col]);
  }
  // Without the walls' work the same rows break the bound (by 1 698 J/m, 3.5 % of the largest
  // work): the squeeze's created energy is what is booked.
  EXPECT_GT(excess_unbooked, 0.01 * largest);
  EXPECT_GT(h.rows.back()[wall_col], 0.0);
  EXPECT_DOUBLE_EQ(s["moving_water"]["boundary_work_J_per_m"].get<double>(), h.rows.back()[wall_col]);
}

TEST(ReservoirWater, ARestartGivesTheSameRecord) {
  const std::vector<std::string> shorter{"time.end=1.1"};
  const fs::path whole = dsdem::test::fresh_dir("moving_water_whole");
  const ordered_json a = run_flume(whole, shorter);
  for (long stop : {2500L}) {  // t = 1.03 s, just after the block entered (about step 2370)
    const fs::path dir = dsdem::test::fresh_dir("moving_water_restart_" + std::to_string(stop));
    const ordered_json stopped = run_flume(dir, shorter, stop);
    // The overrides are part of the scenario as run: in the summary, and in the command the log
    // gives to continue.
    EXPECT_EQ(stopped["overrides"], ordered_json::array({"time.end=1.1"}));
    EXPECT_NE(file_text(dir / "out" / "dsdem.log").find("flume.yaml --set 'time.end=1.1' --restart "), std::string::npos);
    const fs::path elsewhere = dsdem::test::fresh_dir("moving_water_restart_elsewhere");
    fs::create_directories(elsewhere);
    fs::copy_file(dir / "out" / "checkpoint.h5", elsewhere / "checkpoint.h5");  // the run in place overwrites it
    const ordered_json b = run_flume(dir, shorter, 0, (dir / "out" / "checkpoint.h5").string());
    EXPECT_EQ(b["moving_water"].dump(), a["moving_water"].dump()) << "stopped at step " << stop;
    EXPECT_EQ(b["max_wave_amplitude_m"].dump(), a["max_wave_amplitude_m"].dump());
    EXPECT_EQ(file_text(dir / "out" / "history.csv"), file_text(whole / "out" / "history.csv"));
    // In another folder the files start at the checkpoint (a first row at its time), and the
    // measurements carry on: the wave is measured from the still level found before the slide
    // entered, the slide's entry and the banks' readings at rest are the whole run's, and every
    // later history row is the whole run's.
    const ordered_json c = run_flume(elsewhere, shorter, 0, (elsewhere / "checkpoint.h5").string());
    const auto &mc = c["moving_water"], &ma = a["moving_water"];
    EXPECT_EQ(mc["still_level_m"].dump(), ma["still_level_m"].dump());
    EXPECT_EQ(mc["max_wave_amplitude"].dump(), ma["max_wave_amplitude"].dump());
    EXPECT_EQ(mc["runup"].dump(), ma["runup"].dump());
    EXPECT_EQ(mc["force_on_curves"].dump(), ma["force_on_curves"].dump());
    EXPECT_EQ(mc["slide_kinetic_energy_at_impact_J_per_m"].dump(), ma["slide_kinetic_energy_at_impact_J_per_m"].dump());
    EXPECT_EQ(c["heller_hager"].dump(), a["heller_hager"].dump());
    const std::string tail = file_text(elsewhere / "out" / "history.csv");
    const std::size_t second_row = tail.find('\n', tail.find('\n') + 1) + 1;  // after the header and the first row
    const std::string rows = tail.substr(second_row);
    ASSERT_GT(rows.size(), 100u);
    EXPECT_NE(file_text(whole / "out" / "history.csv").find(rows), std::string::npos)
        << "rows of the restart elsewhere that the whole run does not have";
  }
}

// Water that leaves its weakly compressible range is taken out of the water, up to
// reservoir.sph.excluded_limit of it: here a sound speed of 8 m/s, below the flume's splash,
// where two particles leave it (3 of 395 allowed). Each is logged at the run's time, the summary
// counts them, a restart between the two gives the same record, and with the limit at 0 the
// first one stops the run, as a particle out of range did before particles could be taken out.
TEST(ReservoirWater, WaterOutOfItsRangeIsTakenOutUpToTheLimitThenTheRunStops) {
  const std::vector<std::string> o{"time.end=1.3", "reservoir.sph.sound_speed=8"};
  const fs::path whole = dsdem::test::fresh_dir("moving_water_excluded");
  const ordered_json a = run_flume(whole, o);
  const auto& x = a["moving_water"]["excluded"];
  std::printf("excluded: %s\n", x.dump().c_str());
  ASSERT_EQ(x["particles"].get<int>(), 2);
  EXPECT_DOUBLE_EQ(x["fraction"].get<double>(), 2.0 / a["moving_water"]["particles"].get<double>());
  EXPECT_DOUBLE_EQ(x["limit"].get<double>(), 0.01);
  EXPECT_GT(x["energy_J_per_m"].get<double>(), 0.0);
  const double t0 = x["first"]["time_s"].get<double>(), t1 = x["last"]["time_s"].get<double>();
  EXPECT_GT(t0, 0.9);  // after the block entered the water (t = 0.97 s), in the run's time
  EXPECT_LT(t0, t1);
  EXPECT_LT(t1, 1.3);
  const std::string log = file_text(whole / "out" / "dsdem.log");
  EXPECT_NE(log.find(fmt::format("water particle {} taken out of the water at t = ", x["first"]["id"].get<int>())),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("2 of the 3 reservoir.sph.excluded_limit = 0.01 allows"), std::string::npos) << log;

  const fs::path dir = dsdem::test::fresh_dir("moving_water_excluded_restart");
  const ordered_json stopped = run_flume(dir, o, 2560);  // t = 1.05 s, between the two
  ASSERT_EQ(stopped["moving_water"]["excluded"]["particles"].get<int>(), 1);
  // A limit below what the run has taken out is refused before anything is restored, naming
  // the least that fits.
  std::vector<std::string> lower = o;
  lower.push_back("reservoir.sph.excluded_limit=0");
  try {
    run_flume(dsdem::test::fresh_dir("moving_water_excluded_lower"), lower, 0,
              (dir / "out" / "checkpoint.h5").string());
    ADD_FAILURE() << "a limit below the particles taken out was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("1 water particles were taken out of the water, "
                                         "reservoir.sph.excluded_limit = 0 allows 0 of its 395: set it to at least"),
              std::string::npos)
        << e.what();
  }
  const ordered_json b = run_flume(dir, o, 0, (dir / "out" / "checkpoint.h5").string());
  EXPECT_EQ(b["moving_water"].dump(), a["moving_water"].dump());
  EXPECT_EQ(file_text(dir / "out" / "history.csv"), file_text(whole / "out" / "history.csv"));

  // Room for one: the second stops the run, which says how many went and what the limit allows.
  const fs::path one = dsdem::test::fresh_dir("moving_water_excluded_one");
  std::vector<std::string> tight = o;
  tight.push_back("reservoir.sph.excluded_limit=0.003");
  EXPECT_THROW(run_flume(one, tight), dsdem::solver::InstabilityError);
  const std::string why = ordered_json::parse(file_text(one / "out" / "diagnosis.json")).dump();
  EXPECT_NE(why.find("1 of the water's particles out of range at this step, 1 taken out before it, "
                     "reservoir.sph.excluded_limit = 0.003 allows 1 of its 395"),
            std::string::npos)
      << why;

  const fs::path none = dsdem::test::fresh_dir("moving_water_excluded_none");
  std::vector<std::string> strict = o;
  strict.push_back("reservoir.sph.excluded_limit=0");
  EXPECT_THROW(run_flume(none, strict), dsdem::solver::InstabilityError);
  const ordered_json d = ordered_json::parse(file_text(none / "out" / "diagnosis.json"));
  EXPECT_EQ(d["kind"], "water_unsound") << d.dump();
  EXPECT_EQ(file_text(none / "out" / "dsdem.log").find("taken out of the water"), std::string::npos);
}

// The bedrock faces the water may meet: the banks up to the level plus the freeboard, also
// beyond the filled span (the water runs up them), and not the model's base. Water that
// rises above the coupled faces is counted (the run warns), here with no freeboard at all.
TEST(ReservoirWater, TheBanksAreCoupledUpToTheFreeboardAndWaterAboveItIsCounted) {
  auto sc = dsdem::io::load_scenario(kFlume, {"reservoir.sph.freeboard=1"});
  const auto prepared = dsdem::run::prepare_run(sc, dsdem::test::fresh_dir("moving_water_faces").string());
  const auto& layout = *prepared.moving_water;
  EXPECT_DOUBLE_EQ(layout.coupled_top, 3.0);
  const double bottom = -3 * 0.2;  // the lowest water (the bed, y = 0) less the walls' reach
  bool bank_beyond_the_water = false;
  for (const auto& e : layout.edges) {
    if (e.c != dsdem::kNoIndex) continue;  // a discrete face: always coupled
    const auto a = prepared.model.nodes.X[e.a], b = prepared.model.nodes.X[e.b];
    EXPECT_LE(std::min(a.y(), b.y()), 3.0 + 1e-12);
    EXPECT_GE(std::max(a.y(), b.y()), bottom - 1e-12) << "the model's base is not coupled";
    // The water starts where the bank crosses the level, x = 4 m; the bank above it runs to
    // z = 3 m at x = 3 m.
    if (0.5 * (a.x() + b.x()) < 3.5 && std::max(a.y(), b.y()) > 2.5) bank_beyond_the_water = true;
  }
  EXPECT_TRUE(bank_beyond_the_water);
  EXPECT_EQ(layout.faces_without_walls, 0);
  // Triangles too small for a row dp/2 behind their faces still carry walls (about one
  // particle per dp^2, at least one): the block meshed at 0.5 m with particles 0.2 m apart
  // (inradii under 0.1 m) has no bare face and nothing is warned of.
  auto fine = dsdem::io::load_scenario(kFlume, {"mesh.element_size=0.5"});
  const auto small = dsdem::run::prepare_run(fine, dsdem::test::fresh_dir("moving_water_small").string());
  EXPECT_EQ(small.moving_water->faces_without_walls, 0);
  bool warned = false;
  for (const auto& line : small.build_log) warned = warned || line.text.find("carry no wall particles") != std::string::npos;
  EXPECT_FALSE(warned);
  const fs::path dir = dsdem::test::fresh_dir("moving_water_no_freeboard");
  const ordered_json s = run_flume(dir, {"reservoir.sph.freeboard=0"});
  EXPECT_DOUBLE_EQ(s["moving_water"]["coupled_top_m"].get<double>(), 2.0);
  EXPECT_GT(s["moving_water"]["above_freeboard_particles"].get<long>(), 0) << "the wave rises above the level";
  EXPECT_NE(file_text(dir / "out" / "dsdem.log").find("raise the freeboard"), std::string::npos);
}

TEST(ReservoirWater, BadSectionsAreErrorsAtTheirKeys) {
  auto parse_error = [](const std::vector<std::string>& o) {
    try {
      dsdem::io::load_scenario(kFlume, o);
    } catch (const dsdem::io::ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(parse_error({"reservoir.sph.spacing=-1"}).find("reservoir.sph.spacing"), std::string::npos);
  EXPECT_NE(parse_error({"reservoir.sph.smoothing=3"}).find("reservoir.sph.smoothing"), std::string::npos);
  EXPECT_NE(parse_error({"reservoir.sph.fill=[{rectangle: [[0, 0]]}]"}).find("reservoir.sph.fill[0].rectangle"),
            std::string::npos);
  EXPECT_NE(parse_error({"reservoir.sph.fill=[{rectangle: [[3, 0], [1, 1]]}]"}).find("x1 > x0"), std::string::npos);
  EXPECT_NE(parse_error({"reservoir.sph.fill=[{polygon: [[0, 0], [1, 1]]}]"}).find("at least 3"), std::string::npos);
  EXPECT_NE(parse_error({"reservoir.sph.fill=[{level: 2}]"}).find("either rectangle"), std::string::npos);
  EXPECT_NE(parse_error({"reservoir.sph.gauges=[{name: a, x: 5}, {name: a, x: 6}]"}).find("two entries are named 'a'"),
            std::string::npos);
  EXPECT_NE(parse_error({"reservoir.sph.crests=[{name: c, at: [1, 2], side: up}]"}).find("reservoir.sph.crests[0].side"),
            std::string::npos);
  EXPECT_NE(parse_error({"reservoir.sph.spacing_m=0.1"}).find("reservoir.sph.spacing_m"), std::string::npos);
  // Against the model: a gauge off the water, a region inside the rock.
  const std::string off = prepare_error({"reservoir.sph.gauges=[{name: far, x: 20}]"});
  EXPECT_NE(off.find("gauge 'far': x = 20 m lies outside the water"), std::string::npos) << off;
  // Set on the command line: no line to give (never a line -1).
  EXPECT_EQ(off.find(":-1"), std::string::npos) << off;
  EXPECT_NE(off.find("--set reservoir.sph.gauges"), std::string::npos) << off;
  const std::string rock = prepare_error({"reservoir.sph.fill=[{rectangle: [[13.2, -0.8], [13.8, 4.5]]}]"});
  EXPECT_NE(rock.find("no water fits"), std::string::npos) << rock;
  // A region holds no water above reservoir.level unless it gives its own level.
  const std::string above = prepare_error({"reservoir.sph.fill=[{rectangle: [[6, 2.5], [8, 3]]}]"});
  EXPECT_NE(above.find("no water fits: the fill regions lie inside the solid, above their level (reservoir.level, 2 m"),
            std::string::npos)
      << above;
  EXPECT_EQ(prepare_error({"reservoir.sph.fill=[{rectangle: [[6, 2.5], [10, 3]], level: 3}]"}), "");
  // Water beyond the model's box has nothing to hold it: refused at its region.
  const std::string beyond = prepare_error({"reservoir.sph.fill=[{rectangle: [[20, 0], [30, 1]]}]"});
  EXPECT_NE(beyond.find("reservoir.sph.fill[0]: the region reaches beyond the model"), std::string::npos) << beyond;
}

// A spacing a thousand times too fine (a value in the wrong unit), or a region far too large,
// asks for more memory than any machine has: refused at the spacing's key before the lattice is
// walked (walking it would take hours).
TEST(ReservoirWater, ASpacingTooFineForTheMachineIsRefusedBeforeTheWaterIsLaid) {
  if (dsdem::run::available_memory_bytes() == 0) GTEST_SKIP() << "no MemAvailable on this machine";
  const std::string fine = prepare_error({"reservoir.sph.spacing=2e-5"});
  EXPECT_NE(fine.find("reservoir.sph.spacing: 2e-05 m apart the fill regions take about"), std::string::npos) << fine;
  EXPECT_NE(fine.find("of memory"), std::string::npos) << fine;
  EXPECT_NE(fine.find("m or more fits in half of it"), std::string::npos) << fine;
  EXPECT_EQ(prepare_error({"reservoir.sph.spacing=0.1"}), "");
  // A long thin region (a strip 1000 km long and 0.5 m thick at 1 cm: 5e9 particles) is counted
  // too: the counting lattice keeps rows across its thickness.
  const std::string strip =
      prepare_error({"reservoir.sph.fill=[{rectangle: [[0, 1], [1000000, 1.5]]}]", "reservoir.sph.spacing=0.01"});
  EXPECT_NE(strip.find("m apart the fill regions take about 5e+09 particles"), std::string::npos) << strip;
  // A region whose span overflows a double is refused at the fill, not walked.
  const std::string vast = prepare_error({"reservoir.sph.fill=[{rectangle: [[-1e308, 0], [1e308, 1.5]]}]"});
  EXPECT_NE(vast.find("reservoir.sph.fill[0]: the region's extent overflows"), std::string::npos) << vast;
}

// A run-up or force curve, or a crest, that the water cannot reach is warned of at its key
// before the run; those within reach are not.
TEST(ReservoirWater, PlacesTheWaterCannotReachAreWarnedOf) {
  auto warnings = [](const std::vector<std::string>& overrides) {
    auto sc = dsdem::io::load_scenario(kFlume, overrides);
    const auto prepared = dsdem::run::prepare_run(sc, dsdem::test::fresh_dir("moving_water_reach").string());
    std::string out;
    for (const auto& l : prepared.build_log)
      if (l.level >= 3) out += l.text + "\n";
    return out;
  };
  EXPECT_EQ(warnings({}), "");
  const std::string far = warnings({"reservoir.sph.runup=[{name: far, polyline: [[100, 0], [101, 5]]}]",
                                    "reservoir.sph.pressure=[{name: high, polyline: [[13, 40], [13, 45]]}]",
                                    "reservoir.sph.crests=[{name: top, at: [13, 30]}]"});
  EXPECT_NE(far.find("reservoir.sph.runup[0]: 'far' lies outside the region the water can reach"), std::string::npos)
      << far;
  EXPECT_NE(far.find("reservoir.sph.pressure[0]: 'high' lies outside"), std::string::npos) << far;
  EXPECT_NE(far.find("reservoir.sph.crests[0]: crest 'top' at (13, 30) m lies outside"), std::string::npos) << far;
  // A crest beside the region (a dam 40 m away) is out of reach too.
  const std::string beside = warnings({"reservoir.sph.crests=[{name: dam, at: [80, 1]}]"});
  EXPECT_NE(beside.find("reservoir.sph.crests[0]: crest 'dam' at (80, 1) m lies outside"), std::string::npos) << beside;
  // A curve that crosses the region with both ends outside it is within reach.
  EXPECT_EQ(warnings({"reservoir.sph.runup=[{name: across, polyline: [[-50, 1], [60, 1]]}]"}), "");
  // Water a few spacings deep (the flume's 2 m at 0.5 m) is warned of at the spacing, with one
  // that gives ten rows; ten rows (0.2 m) are not.
  const std::string shallow = warnings({"reservoir.sph.spacing=0.5"});
  EXPECT_NE(shallow.find("reservoir.sph.spacing: the water is 4 spacings deep (2 m at 0.5 m)"), std::string::npos)
      << shallow;
  EXPECT_NE(shallow.find("a spacing of 0.2 m or less gives 10"), std::string::npos) << shallow;
  // A water-at-rest line that stands off the pool's level over the moving water is warned of at
  // its key; one at the level is not.
  const std::string off = warnings({"water={level: 2.6}"});
  EXPECT_NE(off.find("water.level: the piezometric line over the moving water (x 4.2 to 13 m) stands at 2.6 m, the pool "
                     "at reservoir.level 2 m"),
            std::string::npos)
      << off;
  EXPECT_EQ(warnings({"water={line: [[-20, 2], [40, 2]]}"}), "");
}

// The water's speeds at the history rows go to summary.json: the fastest particle, and the
// flow's speed (1 % of the water faster). Beyond a tenth of its sound speed the flow is no
// longer weakly compressible: the run says so, naming the setting that keeps it within. The
// flume's block enters at about 5 m/s and throws a few particles up at 13.5-14.5 m/s.
TEST(ReservoirWater, WaterFasterThanATenthOfItsSoundSpeedIsWarnedOf) {
  const fs::path stiff = dsdem::test::fresh_dir("moving_water_c150"), soft = dsdem::test::fresh_dir("moving_water_c30");
  const ordered_json s = run_flume(stiff, {"time.end=1.3", "reservoir.sph.sound_speed=150"});
  const auto &top = s["moving_water"]["max_speed"], &flow = s["moving_water"]["flow_speed"];
  ASSERT_TRUE(top["speed_mps"].is_number()) << top.dump();
  ASSERT_TRUE(flow["speed_mps"].is_number()) << flow.dump();
  const double fastest = top["speed_mps"].get<double>(), speed = flow["speed_mps"].get<double>();
  std::printf("the water's flow speed %.3g m/s (t = %.3g s); the fastest particle %.3g m/s at x = %.3g m, t = %.3g s\n",
              speed, flow["time_s"].get<double>(), fastest, top["x_m"].get<double>(), top["time_s"].get<double>());
  EXPECT_GT(fastest, 5.0);
  EXPECT_LT(fastest, 15.0);
  EXPECT_GT(speed, 2.0);
  EXPECT_LE(speed, fastest);
  EXPECT_EQ(file_text(stiff / "out" / "dsdem.log").find("more than c0 / 10"), std::string::npos);
  run_flume(soft, {"time.end=1.3", "reservoir.sph.sound_speed=" + std::to_string(5.0 * speed)});
  const std::string log = file_text(soft / "out" / "dsdem.log");
  EXPECT_NE(log.find("1 % of the water moved faster than"), std::string::npos) << log;
  EXPECT_NE(log.find("reservoir.sph.expected_speed:"), std::string::npos) << log;
}

// The water's steps that `check` counts before the run (the settle's at the step at rest, the
// run's at the step of water moving at c0 / 10) against the steps the run takes: the block's
// entry moves the water slower than that, so the count is a little high (3 % here).
TEST(ReservoirWater, CheckCountsTheWaterStepsOfTheRun) {
  const std::vector<std::string> o = {"time.end=0.6", "reservoir.sph.settle=0.3"};
  auto sc = dsdem::io::load_scenario(kFlume, o);
  auto prepared = dsdem::run::prepare_run(sc, dsdem::test::fresh_dir("moving_water_check").string());
  const dsdem::run::WaterEstimate e = dsdem::run::estimate_water_steps(prepared);
  EXPECT_GT(e.per_step_s, 0.0);
  EXPECT_GE(e.steps_timed, 20);
  const ordered_json s = run_flume(dsdem::test::fresh_dir("moving_water_check_run"), o);
  const double actual = s["moving_water"]["steps"].get<double>();
  std::printf("water steps: %.0f counted before the run, %.0f taken\n", e.steps, actual);
  EXPECT_GE(e.steps, actual);
  EXPECT_LT(e.steps, 1.06 * actual);
  EXPECT_NE(dsdem::run::check_report(prepared).find("estimate   the water:"), std::string::npos);
}

// The particles hang from the level dp/2 apart; where the depth (2 m here) is no whole number
// of spacings the bottom row is missing and the water settles below the level: the run says
// so at the spacing's key and names a spacing that fills the depth; with one that divides it
// (0.2 m) it says nothing.
TEST(ReservoirWater, ASpacingThatLeavesTheBottomRowOutIsWarnedOf) {
  auto warnings = [](const std::string& spacing) {
    auto sc = dsdem::io::load_scenario(kFlume, {"reservoir.sph.spacing=" + spacing});
    const auto prepared = dsdem::run::prepare_run(sc, dsdem::test::fresh_dir("moving_water_depth").string());
    std::string out;
    for (const auto& l : prepared.build_log)
      if (l.level >= 3) out += l.text + "\n";
    return out;
  };
  const std::string off = warnings("0.15");  // 13 rows: 1.95 m of 2 m
  // At the section in the file, 1-based (flume.yaml's `sph:` body starts on line 22, column 5).
  EXPECT_NE(off.find("flume.yaml:22:5: "), std::string::npos) << off;
  EXPECT_NE(off.find("reservoir.sph.spacing: the particles fill 1.95 m of the 2 m"), std::string::npos) << off;
  EXPECT_NE(off.find("e.g. 0.153846 m"), std::string::npos) << off;
  EXPECT_EQ(warnings("0.2"), "");
  EXPECT_EQ(warnings("0.153846"), "");  // the spacing it names, as printed
}
