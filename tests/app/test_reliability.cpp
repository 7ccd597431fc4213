// Issue 9 through the CLI: instability diagnosis, signals, SIGKILL, unwritable or full
// output directory, `check` resource warnings.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "app/cli_util.hpp"

namespace fs = std::filesystem;
using namespace dsdem::test;

namespace {

const std::string kSlope = example("elastic_slope/scenario.yaml");

// Starts dsdem with the given arguments, stdout+stderr to `log`; returns the pid.
pid_t spawn_dsdem(const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    std::string bin = DSDEM_BINARY;
    argv.push_back(bin.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    FILE* f = std::fopen(log.c_str(), "w");
    if (f) {
      dup2(fileno(f), 1);
      dup2(fileno(f), 2);
    }
    execv(bin.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

int wait_exit(pid_t pid, int* signal_out = nullptr) {
  int status = 0;
  waitpid(pid, &status, 0);
  if (signal_out) *signal_out = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Number of data rows in history.csv (0 if absent).
int history_rows(const fs::path& out) {
  std::ifstream in(out / "history.csv");
  std::string line;
  int n = -1;
  while (std::getline(in, line)) ++n;
  return std::max(n, 0);
}

// Waits until the run has written at least `frames` field frames (or 120 s).
bool wait_for_frames(const fs::path& out, int frames) {
  for (int i = 0; i < 1200; ++i) {
    int n = 0;
    std::error_code ec;
    if (fs::exists(out / "fields", ec))
      for (const auto& e : fs::directory_iterator(out / "fields", ec))
        if (e.path().extension() == ".vtu") ++n;
    if (n >= frames) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return false;
}

Command check_outputs(const fs::path& out) {
  return run_command("python3 " + std::string(DSDEM_SOURCE_DIR) + "/tests/app/check_outputs.py " + out.string());
}

void expect_diagnosis(const fs::path& out, const Command& c, const std::string& kind, const std::string& entity) {
  EXPECT_EQ(c.exit_code, 3) << c.output;
  EXPECT_NE(c.output.find("the run went unstable"), std::string::npos) << c.output;
  ASSERT_TRUE(fs::exists(out / "diagnosis.json")) << c.output;
  const std::string d = read_text(out / "diagnosis.json");
  EXPECT_NE(d.find("\"kind\": \"" + kind + "\""), std::string::npos) << d;
  EXPECT_NE(d.find("\"entity\": \"" + entity + "\""), std::string::npos) << d;
  for (const char* key : {"\"id\"", "\"position_m\"", "\"step\"", "\"time_s\"", "\"message\""})
    EXPECT_NE(d.find(key), std::string::npos) << key << " in " << d;
  // The log says it too, and the last fields and history row are there and complete.
  const std::string log = read_text(out / "dsdem.log");
  EXPECT_NE(log.find("run stopped:"), std::string::npos) << log;
  EXPECT_NE(log.find("diagnosis.json"), std::string::npos) << log;
  EXPECT_TRUE(fs::exists(out / "fields.pvd"));
  EXPECT_GE(history_rows(out), 2);
  const auto ok = check_outputs(out);
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
}

}  // namespace

TEST(Reliability, CrushedElementStopsWithInvertedElementDiagnosis) {
  // The base driven down at 100 km/s: the elements on it turn inside out in one step.
  const fs::path out = fresh_dir("rel_inverted");
  const auto c = run_dsdem("run " + kSlope + " -o " + out.string() +
                           " --set boundaries.0.type=velocity --set boundaries.0.y=-1e5 --set time.end=0.01 -q --no-plots");
  expect_diagnosis(out, c, "inverted_element", "element");
  EXPECT_NE(c.output.find("inverted element"), std::string::npos) << c.output;
  fs::remove_all(out);
}

TEST(Reliability, NonFiniteStateStopsNamingTheNode) {
  // A prescribed velocity of 1e200 m/s: kinetic energy overflows to infinity.
  const fs::path out = fresh_dir("rel_nan");
  const auto c = run_dsdem("run " + kSlope + " -o " + out.string() +
                           " --set boundaries.0.type=velocity --set boundaries.0.y=1e200 --set time.end=0.01 -q --no-plots");
  expect_diagnosis(out, c, "non_finite", "node");
  EXPECT_NE(c.output.find("non-finite velocity at node"), std::string::npos) << c.output;
  fs::remove_all(out);
}

TEST(Reliability, EnergyGrowthStopsTheRunNamingTheNode) {
  // Stiff joints at time.safety = 1 (allowed by the schema): the joint stable
  // step counts each joint end alone, but the nodes also carry the triangles and the other
  // joints, so the step is above the real limit and the high modes grow exponentially.
  const fs::path dir = fresh_dir("rel_growth");
  fs::create_directories(dir);
  fs::copy_file(std::string(DSDEM_TEST_DATA_DIR) + "/mesh/square.geo", dir / "square.geo");
  std::ofstream(dir / "s.yaml") << R"(mesh:
  file: square.geo
  element_size: 0.25
materials:
  rock: {E: 10.0e9, nu: 0.25, rho: 2500}
regions:
  - group: block
    material: rock
    zone: discrete
joints:
  default: {ft: 1.0e9, c: 4.0e9, phi: 30, GI: 1.0e6, GII: 1.0e7, penalty: 10}
boundaries:
  - group: bottom
    type: fixed
gravity: [0, -9.81]
time:
  end: 0.01
  safety: 1.0
)";
  const fs::path out = dir / "out";
  // `check` times 50 steps on a copy: it sees the growth already and says so.
  const auto chk = run_dsdem("check " + (dir / "s.yaml").string());
  EXPECT_EQ(chk.exit_code, 3) << chk.output;
  EXPECT_NE(chk.output.find("energy growing beyond the work put in"), std::string::npos) << chk.output;
  const auto c = run_dsdem("run " + (dir / "s.yaml").string() + " -o " + out.string() + " -q --no-plots --threads 1");
  expect_diagnosis(out, c, "energy_growth", "node");
  EXPECT_NE(c.output.find("energy growing beyond the work put in"), std::string::npos) << c.output;
  fs::remove_all(dir);
}

TEST(Reliability, SigkillLeavesOnlyCompleteFiles) {
  const fs::path out = fresh_dir("rel_kill");
  const pid_t pid = spawn_dsdem({"run", kSlope, "-o", out.string(), "--set", "time.end=100", "--set",
                                 "output.field_interval=0.0005", "--set", "output.history_interval=0.0001",
                                 "--threads", "1", "-q", "--no-plots"},
                                fs::path(out.string() + ".log"));
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for_frames(out, 4));
  std::this_thread::sleep_for(std::chrono::milliseconds(2300));  // past a history flush (every 2 s)
  kill(pid, SIGKILL);
  int sig = 0;
  wait_exit(pid, &sig);
  EXPECT_EQ(sig, SIGKILL);
  const auto ok = check_outputs(out);
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_GE(history_rows(out), 2) << "histories are flushed every 2 s";
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  // The mesh went from memory to the results, and no scratch folder was left behind:
  // it is removed as soon as the model is built, not when the run ends.
  EXPECT_GT(fs::file_size(out / "slope.msh"), 1000u);
  EXPECT_FALSE(fs::exists(fs::temp_directory_path() / ("dsdem-run-" + std::to_string(pid))));
  fs::remove_all(out);
  fs::remove(out.string() + ".log");
}

class StopSignal : public ::testing::TestWithParam<int> {};

TEST_P(StopSignal, StopsCleanlyWithLastFieldsHistoryAndSummary) {
  const int sig = GetParam();
  const fs::path out = fresh_dir("rel_sig" + std::to_string(sig));
  const pid_t pid = spawn_dsdem({"run", kSlope, "-o", out.string(), "--set", "time.end=100", "--set",
                                 "output.field_interval=0.001", "--threads", "1", "-q", "--no-plots"},
                                fs::path(out.string() + ".log"));
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for_frames(out, 2));
  kill(pid, sig);
  const int code = wait_exit(pid);
  EXPECT_EQ(code, 128 + sig) << read_text(out.string() + ".log");
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  const std::string summary = read_text(out / "summary.json");
  EXPECT_NE(summary.find("\"completed\": false"), std::string::npos) << summary;
  EXPECT_NE(summary.find(sig == SIGINT ? "\"SIGINT\"" : "\"SIGTERM\""), std::string::npos) << summary;
  EXPECT_NE(read_text(out / "dsdem.log").find("stopped by"), std::string::npos);
  const auto ok = check_outputs(out);
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_GE(history_rows(out), 2);
  fs::remove_all(out);
  fs::remove(out.string() + ".log");
}
INSTANTIATE_TEST_SUITE_P(Reliability, StopSignal, ::testing::Values(SIGINT, SIGTERM));

TEST(Reliability, OutputUnderAFileIsRejectedBeforeStepZero) {
  const fs::path dir = fresh_dir("rel_unwritable");
  fs::create_directories(dir);
  std::ofstream(dir / "plain_file") << "x";
  const auto c = run_dsdem("run " + kSlope + " -o " + (dir / "plain_file" / "out").string() + " -q --no-plots");
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("--output"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("cannot create output directory"), std::string::npos) << c.output;
  fs::remove_all(dir);
}

// Read-only and full file systems need a tmpfs mount: root only (CI runs as root).
TEST(Reliability, ReadOnlyOrFullOutputDirectoryIsRejectedAndLeftEmpty) {
  const fs::path ro = fresh_dir("rel_ro"), full = fresh_dir("rel_full");
  fs::create_directories(ro);
  fs::create_directories(full);
  if (geteuid() != 0 || mount("tmpfs", ro.c_str(), "tmpfs", MS_RDONLY, "size=1m") != 0) {
    fs::remove_all(ro);
    fs::remove_all(full);
    GTEST_SKIP() << "needs root to mount a tmpfs";
  }
  const auto c = run_dsdem("run " + kSlope + " -o " + ro.string() + " -q --no-plots");
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("cannot write into output directory"), std::string::npos) << c.output;
  umount(ro.c_str());

  ASSERT_EQ(mount("tmpfs", full.c_str(), "tmpfs", 0, "size=64k"), 0);
  const auto c2 = run_dsdem("run " + kSlope + " -o " + full.string() + " -q --no-plots");
  EXPECT_EQ(c2.exit_code, 2) << c2.output;
  EXPECT_NE(c2.output.find("free but this run will write about"), std::string::npos) << c2.output;
  EXPECT_TRUE(fs::is_empty(full)) << "nothing written";
  umount(full.c_str());
  fs::remove_all(ro);
  fs::remove_all(full);
}

TEST(Reliability, CheckPrintsMemoryAndWarnsAboutAVeryLongRun) {
  const auto c = run_dsdem("check " + kSlope);
  EXPECT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("memory     about"), std::string::npos) << c.output;
  EXPECT_EQ(c.output.find("warning:"), std::string::npos) << c.output;
  // 10^7 s of simulated time: billions of steps.
  const auto w = run_dsdem("check " + kSlope + " --set time.end=1e7");
  EXPECT_EQ(w.exit_code, 0) << w.output;
  EXPECT_NE(w.output.find("warning: this run would take about"), std::string::npos) << w.output;
  EXPECT_NE(w.output.find("more than 24 h"), std::string::npos) << w.output;
}
