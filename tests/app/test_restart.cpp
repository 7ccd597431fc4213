// Checkpoints and `dsdem run --restart` through the CLI (issues 8 and 9): a run stopped
// at any step, by a signal or killed outright, continues from its checkpoint to files
// bit-identical to those of a run that was never interrupted.
#include <H5Cpp.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "app/cli_util.hpp"

namespace fs = std::filesystem;
using namespace dsdem::test;

namespace {

// The Dr2 shear-sliding scenario made small and short: a gravity stage, then a strong
// earthquake through the viscous-spring boundary, joints breaking and blocks in contact.
// About 3000 steps, under a second of wall time.
std::string small_dr2(double quake_duration = 1.5) {
  return example("dr2/shear_sliding.yaml") +
         " --set mesh.element_size=20 --set stages.0.duration=0.3 --set stages.1.duration=" +
         std::to_string(quake_duration) +
         " --set earthquake.horizontal.generate.pga=0.6 --set output.field_interval=0.25"
         " --set output.history_interval=0.01 -q --no-plots --threads 1";
}

// The summary's gauge block and counts: equal for the interrupted and the uninterrupted run.
std::string summary_results(const fs::path& out) {
  const std::string s = read_text(out / "summary.json");
  std::string picked;
  for (const char* key : {"broken_joints", "fragments", "steps", "end_time_s"}) {
    std::smatch m;
    if (std::regex_search(s, m, std::regex("\"" + std::string(key) + "\": [^,\n]+"))) picked += m.str() + "\n";
  }
  const auto g = s.find("\"gauges\"");
  if (g != std::string::npos) picked += s.substr(g, s.find(']', s.find("final_displacement_m", g)) - g);
  return picked;
}

// Everything a user reads after a run, except the log and the wall-clock numbers.
void expect_same_results(const fs::path& a, const fs::path& b) {
  for (const char* f : {"history.csv", "cracks.csv", "fields.pvd", "cracks.pvd", "summary.json"}) {
    ASSERT_TRUE(fs::exists(a / f)) << (a / f);
    ASSERT_TRUE(fs::exists(b / f)) << (b / f);
  }
  ASSERT_GE(std::distance(fs::directory_iterator(a / "fields"), fs::directory_iterator{}), 3);
  EXPECT_EQ(read_text(a / "history.csv"), read_text(b / "history.csv")) << "history.csv differs";
  EXPECT_EQ(read_text(a / "cracks.csv"), read_text(b / "cracks.csv")) << "cracks.csv differs";
  EXPECT_EQ(read_text(a / "fields.pvd"), read_text(b / "fields.pvd")) << "fields.pvd differs";
  EXPECT_EQ(read_text(a / "cracks.pvd"), read_text(b / "cracks.pvd")) << "cracks.pvd differs";
  for (const auto& e : fs::directory_iterator(a / "fields"))
    EXPECT_EQ(read_text(e.path()), read_text(b / "fields" / e.path().filename())) << e.path().filename();
  EXPECT_EQ(summary_results(a), summary_results(b));
}

class Restart : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    reference_ = fresh_dir("restart_reference");
    const auto c = run_dsdem("run " + small_dr2() + " -o " + reference_.string());
    ASSERT_EQ(c.exit_code, 0) << c.output;
    const std::string s = read_text(reference_ / "summary.json");
    ASSERT_NE(s.find("\"completed\": true"), std::string::npos) << s;
    // The case must exercise what a restart has to carry: broken joints and contacts.
    ASSERT_EQ(s.find("\"broken_joints\": 0,"), std::string::npos) << s;
  }
  static void TearDownTestSuite() {
    fs::remove_all(reference_);
    fresh_dir("restart_long_reference");  // removes it, if a test made it
  }
  static fs::path reference_;
};
fs::path Restart::reference_;

// Stopped in the gravity stage (the stage switch to viscous springs and the earthquake
// happen after the restart) and in the earthquake stage (joints breaking, contacts).
class RestartAtStep : public Restart, public ::testing::WithParamInterface<long> {};

TEST_P(RestartAtStep, ContinuesBitIdenticallyInItsOwnFolder) {
  const long stop = GetParam();
  const fs::path out = fresh_dir("restart_at_" + std::to_string(stop));
  const auto first = run_dsdem("run " + small_dr2() + " -o " + out.string() + " --stop-at-step " + std::to_string(stop));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_NE(first.output.find("--restart"), std::string::npos) << first.output;
  ASSERT_TRUE(fs::exists(out / "checkpoint.h5"));
  const std::string partial = read_text(out / "summary.json");
  EXPECT_NE(partial.find("\"completed\": false"), std::string::npos) << partial;
  EXPECT_NE(partial.find("\"stopped_at_step\": " + std::to_string(stop)), std::string::npos) << partial;

  // No -o: the run goes on in the checkpoint's folder.
  const auto second = run_dsdem("run " + small_dr2() + " --restart " + (out / "checkpoint.h5").string());
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_NE(read_text(out / "dsdem.log").find("restarted from"), std::string::npos);
  expect_same_results(reference_, out);
  const std::string s = read_text(out / "summary.json");
  EXPECT_NE(s.find("\"restart_step\": " + std::to_string(stop)), std::string::npos) << s;
  fs::remove_all(out);
}
INSTANTIATE_TEST_SUITE_P(Restart, RestartAtStep, ::testing::Values(200L, 1700L));

TEST_F(Restart, InAnotherFolderStartsNewFilesAtTheCheckpoint) {
  const fs::path first = fresh_dir("restart_first"), second = fresh_dir("restart_second");
  ASSERT_EQ(run_dsdem("run " + small_dr2() + " -o " + first.string() + " --stop-at-step 1500").exit_code, 0);
  const auto c = run_dsdem("run " + small_dr2() + " -o " + second.string() + " --restart " +
                           (first / "checkpoint.h5").string());
  ASSERT_EQ(c.exit_code, 0) << c.output;
  // The new history starts at the checkpoint and ends exactly as the reference does.
  const std::string ref = read_text(reference_ / "history.csv"), got = read_text(second / "history.csv");
  const auto lines = [](const std::string& t) {
    std::vector<std::string> v;
    std::istringstream in(t);
    for (std::string l; std::getline(in, l);) v.push_back(l);
    return v;
  };
  const auto r = lines(ref), g = lines(got);
  ASSERT_GE(g.size(), 3u);
  EXPECT_EQ(g.front(), r.front());  // header
  EXPECT_EQ(g.back(), r.back());
  EXPECT_LT(g.size(), r.size());
  EXPECT_EQ(read_text(reference_ / "cracks.csv"), read_text(second / "cracks.csv"));
  EXPECT_EQ(summary_results(reference_), summary_results(second));
  fs::remove_all(first);
  fs::remove_all(second);
}

// A longer run (8 s of earthquake, a few seconds of wall time), so that a signal lands
// mid-run; its uninterrupted reference is made once for the tests that need it.
const std::string kLongArgs = small_dr2(8.0) + " --set output.checkpoint_steps=500";

const fs::path& long_reference() {
  static const fs::path ref = [] {
    const fs::path d = fresh_dir("restart_long_reference");
    const auto c = run_dsdem("run " + kLongArgs + " -o " + d.string());
    EXPECT_EQ(c.exit_code, 0) << c.output;
    return d;
  }();
  return ref;
}

// Starts the long run in `out` and sends `sig` once a few field frames (and so at least
// one periodic checkpoint) are written. Returns the exit status.
int run_long_and_signal(const fs::path& out, int sig) {
  const std::string cmd = std::string(DSDEM_BINARY) + " run " + kLongArgs + " -o " + out.string();
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", ("exec " + cmd + " > /dev/null 2>&1").c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  for (int i = 0; i < 1200 && !fs::exists(out / "fields" / "fields_000003.vtu"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  kill(pid, sig);
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

TEST_F(Restart, SigtermWritesACheckpointToContinueFrom) {
  const fs::path& ref = long_reference();
  const fs::path out = fresh_dir("restart_sigterm");
  const int status = run_long_and_signal(out, SIGTERM);
  ASSERT_TRUE(WIFEXITED(status));
  if (WEXITSTATUS(status) == 0) GTEST_SKIP() << "the run ended before the signal arrived (machine too fast)";
  ASSERT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  ASSERT_TRUE(fs::exists(out / "checkpoint.h5"));
  const auto c = run_dsdem("run " + kLongArgs + " --restart " + (out / "checkpoint.h5").string());
  ASSERT_EQ(c.exit_code, 0) << c.output;
  expect_same_results(ref, out);
  fs::remove_all(out);
}

TEST_F(Restart, SigkilledRunResumesFromItsLastCheckpoint) {
  const fs::path& ref = long_reference();
  const fs::path out = fresh_dir("restart_sigkill");
  const int status = run_long_and_signal(out, SIGKILL);
  if (WIFEXITED(status)) GTEST_SKIP() << "the run ended before the signal arrived (machine too fast)";
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  ASSERT_TRUE(fs::exists(out / "checkpoint.h5"));
  const auto c = run_dsdem("run " + kLongArgs + " --restart " + (out / "checkpoint.h5").string());
  ASSERT_EQ(c.exit_code, 0) << c.output;
  expect_same_results(ref, out);
  fs::remove_all(out);
}

TEST_F(Restart, KilledRunResumesFromItsLastPeriodicCheckpoint) {
  const fs::path out = fresh_dir("restart_kill");
  const std::string args = small_dr2() + " --set output.checkpoint_steps=1000";
  const fs::path ref = fresh_dir("restart_kill_ref");
  ASSERT_EQ(run_dsdem("run " + args + " -o " + ref.string()).exit_code, 0);
  // Stand in for a SIGKILL at step 2345: a stop there, then the files as a kill after the
  // periodic checkpoint at step 2000 leaves them (rows and frames beyond the checkpoint).
  const auto stopped = run_dsdem("run " + args + " -o " + out.string() + " --stop-at-step 2000");
  ASSERT_EQ(stopped.exit_code, 0);
  // It says how to continue: the scenario with its --set overrides, then --restart.
  EXPECT_NE(stopped.output.find("continue with dsdem run " + example("dr2/shear_sliding.yaml") +
                                 " --set 'mesh.element_size=20' --set 'stages.0.duration=0.3'"),
            std::string::npos)
      << stopped.output;
  EXPECT_NE(stopped.output.find("--set 'output.checkpoint_steps=1000' --restart " + (out / "checkpoint.h5").string()),
            std::string::npos)
      << stopped.output;
  const fs::path saved = out.string() + ".ckpt";
  fs::copy_file(out / "checkpoint.h5", saved, fs::copy_options::overwrite_existing);
  ASSERT_EQ(run_dsdem("run " + args + " --restart " + (out / "checkpoint.h5").string() + " --stop-at-step 2345")
                .exit_code,
            0);
  fs::copy_file(saved, out / "checkpoint.h5", fs::copy_options::overwrite_existing);
  const auto c = run_dsdem("run " + args + " --restart " + (out / "checkpoint.h5").string());
  ASSERT_EQ(c.exit_code, 0) << c.output;
  expect_same_results(ref, out);
  fs::remove_all(out);
  fs::remove_all(ref);
  fs::remove(saved);
}

TEST_F(Restart, RefusesAnotherModelOrACompleteRunWithExitCode2) {
  const fs::path out = fresh_dir("restart_refuse");
  ASSERT_EQ(run_dsdem("run " + small_dr2() + " -o " + out.string() + " --stop-at-step 100").exit_code, 0);
  const auto other = run_dsdem("run " + small_dr2() + " --set mesh.element_size=25 --restart " +
                               (out / "checkpoint.h5").string());
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find("another model"), std::string::npos) << other.output;
  EXPECT_NE(other.output.find("checkpoint.h5"), std::string::npos) << other.output;

  const auto faster = run_dsdem("run " + small_dr2() + " --set time.safety=0.2 --restart " +
                                (out / "checkpoint.h5").string());
  EXPECT_EQ(faster.exit_code, 2) << faster.output;
  EXPECT_NE(faster.output.find("dt ="), std::string::npos) << faster.output;
  // The step rule is a time setting too: a run with a fixed step cannot go on as adaptive.
  const auto fixed = run_dsdem("run " + small_dr2() + " --set time.adaptive=false --restart " +
                               (out / "checkpoint.h5").string());
  EXPECT_EQ(fixed.exit_code, 2) << fixed.output;
  EXPECT_NE(fixed.output.find("time.adaptive = true"), std::string::npos) << fixed.output;
  // The water switched on (a --set the first run did not have): the history it goes on with has
  // another column; refused the same way, naming the first column that differs.
  const auto wet = run_dsdem("run " + small_dr2() + " --set water.dry=false --restart " +
                             (out / "checkpoint.h5").string());
  EXPECT_EQ(wet.exit_code, 2) << wet.output;
  EXPECT_NE(wet.output.find("cannot resume history"), std::string::npos) << wet.output;
  EXPECT_NE(wet.output.find("'water_work_J_per_m' here"), std::string::npos) << wet.output;

  const auto done = run_dsdem("run " + small_dr2() + " --restart " + (reference_ / "checkpoint.h5").string() +
                              " -o " + out.string());
  EXPECT_EQ(done.exit_code, 2) << done.output;
  EXPECT_NE(done.output.find("complete"), std::string::npos) << done.output;

  // A checkpoint of a dsdem that numbered nodes as the mesh does (no node-order record):
  // its node arrays would land on the wrong nodes, so it is refused, not continued.
  const fs::path old = out / "old_numbering.h5";
  fs::copy_file(out / "checkpoint.h5", old, fs::copy_options::overwrite_existing);
  {
    H5::H5File f(old.string(), H5F_ACC_RDWR);
    f.unlink("runner/node_order");
  }
  const auto renumbered = run_dsdem("run " + small_dr2() + " --restart " + old.string() + " -o " + (out / "o").string());
  EXPECT_EQ(renumbered.exit_code, 2) << renumbered.output;
  EXPECT_NE(renumbered.output.find("numbered the nodes as the mesh does"), std::string::npos) << renumbered.output;

  // A checkpoint of the file's triangle numbering (or of a dsdem before it had another,
  // with no record) continues only with that numbering, and the refusal says how.
  ASSERT_EQ(run_dsdem("run " + small_dr2() + " --set mesh.triangle_order=file -o " + (out / "f").string() +
                      " --stop-at-step 100")
                .exit_code,
            0);
  const auto spatial = run_dsdem("run " + small_dr2() + " --restart " + (out / "f" / "checkpoint.h5").string() +
                                 " -o " + (out / "s").string());
  EXPECT_EQ(spatial.exit_code, 2) << spatial.output;
  EXPECT_NE(spatial.output.find("mesh.triangle_order = file, this scenario gives spatial"), std::string::npos)
      << spatial.output;
  EXPECT_NE(spatial.output.find("--set mesh.triangle_order=file"), std::string::npos) << spatial.output;
  const fs::path unrecorded = out / "no_order_record.h5";
  fs::copy_file(out / "f" / "checkpoint.h5", unrecorded, fs::copy_options::overwrite_existing);
  {
    H5::H5File f(unrecorded.string(), H5F_ACC_RDWR);
    f.unlink("runner/spatial_triangle_order");
  }
  const auto older = run_dsdem("run " + small_dr2() + " --restart " + unrecorded.string() + " -o " +
                               (out / "u").string());
  EXPECT_EQ(older.exit_code, 2) << older.output;
  EXPECT_NE(older.output.find("(dsdem before 2026-11-24)"), std::string::npos) << older.output;
  const auto as_file = run_dsdem("run " + small_dr2() + " --set mesh.triangle_order=file --restart " +
                                 unrecorded.string() + " -o " + (out / "u").string() + " --stop-at-step 150");
  EXPECT_EQ(as_file.exit_code, 0) << as_file.output;

  std::ofstream(out / "bad.h5") << "not a checkpoint";
  const auto bad = run_dsdem("run " + small_dr2() + " --restart " + (out / "bad.h5").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("bad.h5"), std::string::npos) << bad.output;
  fs::remove_all(out);
}

// "add a stage to the scenario to continue it", as the refusal above says: the complete
// run's end state, continued with the scenario plus one stage, gives what the longer
// scenario gives run straight through. (The restart used to stop with "its stage record is
// inconsistent (damaged file?)".)
TEST_F(Restart, CompleteRunContinuesWithAnAddedStage) {
  const fs::path dir = fresh_dir("restart_added_stage");
  fs::create_directories(dir);
  // The example with a third stage, 0.2 s more of free run on the viscous boundary.
  std::string yaml = read_text(example("dr2/shear_sliding.yaml"));
  const std::string mesh = "file: dr2.geo";
  ASSERT_NE(yaml.find(mesh), std::string::npos);
  yaml.replace(yaml.find(mesh), mesh.size(), "file: " + example("dr2/dr2.geo"));
  const auto time_key = yaml.find("\ntime:");
  ASSERT_NE(time_key, std::string::npos);
  yaml.insert(time_key + 1,
              "  - name: more\n"
              "    duration: 0.2\n"
              "    failure: true\n"
              "    boundaries:\n"
              "      - {group: base, type: viscous_spring, scattering_centre: [450, 960]}\n"
              "      - {group: left, type: viscous_spring, scattering_centre: [450, 960]}\n"
              "      - {group: right, type: viscous_spring, scattering_centre: [450, 960]}\n");
  std::ofstream(dir / "three_stages.yaml") << yaml;
  auto three_stages = [&] {
    std::string args = small_dr2();
    args.replace(0, example("dr2/shear_sliding.yaml").size(), (dir / "three_stages.yaml").string());
    return args;
  };
  const fs::path straight = dir / "straight", continued = dir / "continued";
  const auto a = run_dsdem("run " + three_stages() + " -o " + straight.string());
  ASSERT_EQ(a.exit_code, 0) << a.output;

  // The complete two-stage run (the suite's reference), copied, then continued in place.
  fs::create_directories(continued);
  for (const auto& e : fs::recursive_directory_iterator(reference_)) {
    const fs::path to = continued / fs::relative(e.path(), reference_);
    if (e.is_directory()) fs::create_directories(to);
    else fs::copy_file(e.path(), to);
  }
  const auto b = run_dsdem("run " + three_stages() + " --restart " + (continued / "checkpoint.h5").string());
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_NE(read_text(continued / "dsdem.log").find("at the start of stage 3 'more'"), std::string::npos)
      << read_text(continued / "dsdem.log");
  const std::string s = read_text(continued / "summary.json");
  EXPECT_NE(s.find("\"completed\": true"), std::string::npos) << s;
  // The same history, cracks and end state. (The continued folder also keeps the frame
  // the complete run wrote of its last state, at the end of stage 2.)
  EXPECT_EQ(read_text(straight / "history.csv"), read_text(continued / "history.csv")) << "history.csv differs";
  EXPECT_EQ(read_text(straight / "cracks.csv"), read_text(continued / "cracks.csv")) << "cracks.csv differs";
  EXPECT_EQ(summary_results(straight), summary_results(continued));
  auto last_frame = [](const fs::path& out, const char* index) {
    const std::string pvd = read_text(out / index);
    const auto f = pvd.rfind("file=\"");
    EXPECT_NE(f, std::string::npos) << pvd;
    return read_text(out / pvd.substr(f + 6, pvd.find('"', f + 6) - (f + 6)));
  };
  for (const char* index : {"fields.pvd", "cracks.pvd"})
    EXPECT_EQ(last_frame(straight, index), last_frame(continued, index)) << "last frame of " << index << " differs";
  fs::remove_all(dir);
}

}  // namespace

// A 3D run (examples/box3d made coarse and short: a gravity stage on rollers, then a
// three-component earthquake through viscous springs) stopped in either stage continues
// from its checkpoint to the files of the run that was never stopped.
std::string small_box3d() {
  return example("box3d/scenario.yaml") +
         " --set mesh.element_size=8 --set stages.0.duration=0.2 --set stages.1.duration=0.25"
         " --set output.field_interval=0.1 --set output.history_interval=0.01 -q --threads 1";
}

class Restart3D : public ::testing::TestWithParam<long> {};

TEST_P(Restart3D, AStoppedRunContinuesBitIdenticallyInItsOwnFolder) {
  static const fs::path reference = [] {
    const fs::path d = fresh_dir("restart3d_reference");
    const auto c = run_dsdem("run " + small_box3d() + " -o " + d.string());
    EXPECT_EQ(c.exit_code, 0) << c.output;
    return d;
  }();
  const long stop = GetParam();
  const fs::path out = fresh_dir("restart3d_at_" + std::to_string(stop));
  const auto first = run_dsdem("run " + small_box3d() + " -o " + out.string() + " --stop-at-step " + std::to_string(stop));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_NE(first.output.find("--restart"), std::string::npos) << first.output;
  const std::string partial = read_text(out / "summary.json");
  EXPECT_NE(partial.find("\"completed\": false"), std::string::npos) << partial;
  const auto second = run_dsdem("run " + small_box3d() + " --restart " + (out / "checkpoint.h5").string());
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_NE(read_text(out / "dsdem.log").find("restarted from"), std::string::npos);
  EXPECT_EQ(read_text(reference / "history.csv"), read_text(out / "history.csv")) << "history.csv differs";
  EXPECT_EQ(read_text(reference / "fields.pvd"), read_text(out / "fields.pvd")) << "fields.pvd differs";
  ASSERT_GE(std::distance(fs::directory_iterator(reference / "fields"), fs::directory_iterator{}), 5);
  for (const auto& e : fs::directory_iterator(reference / "fields"))
    EXPECT_EQ(read_text(e.path()), read_text(out / "fields" / e.path().filename())) << e.path().filename();
  const std::string a = read_text(reference / "summary.json"), b = read_text(out / "summary.json");
  for (const char* key : {"steps", "end_time_s", "energy_balance_error", "value_m"}) {
    std::smatch ma, mb;
    ASSERT_TRUE(std::regex_search(a, ma, std::regex("\"" + std::string(key) + "\": [^,\n]+"))) << key;
    ASSERT_TRUE(std::regex_search(b, mb, std::regex("\"" + std::string(key) + "\": [^,\n]+"))) << key;
    EXPECT_EQ(ma.str(), mb.str());
  }
  EXPECT_NE(b.find("\"restart_step\": " + std::to_string(stop)), std::string::npos) << b;
  fs::remove_all(out);
}
// In the gravity stage (1673 steps; the earthquake stage's springs and record start after the restart)
// and in the earthquake stage.
INSTANTIATE_TEST_SUITE_P(Restart, Restart3D, ::testing::Values(300L, 2000L));
