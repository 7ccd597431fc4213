// dsdem ensemble end to end (docs/theory.md §13) on a block sliding down a 30-degree incline,
// a member taking a fraction of a second: the analytic ensemble, the same members.csv
// however the members ran (--jobs 1, --jobs 2, mpirun -n 2, killed and rerun), failures.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "app/cli_util.hpp"
#include "ensemble/aggregate.hpp"
#include "ensemble/statistics.hpp"

using namespace dsdem;
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

const std::string kBase = std::string(DSDEM_TEST_DATA_DIR) + "/ensemble/incline.yaml";
// Sanitizer builds run the members some 20 times slower: the analytic ensemble (125 members,
// the same bits as the plain build) is left to the plain build; the other EnsembleRun tests
// take the ensemble's own code (pool, kill, MPI, aggregates) through the sanitizers.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

// incline.yaml's gravity: g sin 30 deg and g cos 30 deg.
constexpr double kGs = 4.905, kGc = 8.495709211;

void write(const fs::path& p, const std::string& text) {
  std::ofstream out(p);
  out << text;
}

Json read_json(const fs::path& p) {
  std::ifstream in(p);
  return Json::parse(in);
}

std::string friction_file(int members, const std::string& method, int seed, const std::string& extra = "") {
  return "base: " + kBase + "\nmembers: " + std::to_string(members) + "\nsampling: {method: " + method +
         ", seed: " + std::to_string(seed) + "}\nvary:\n  - {key: contact.friction, name: friction, distribution: uniform, "
         "lower: 0.1, upper: 0.5}\n" + extra;
}

}  // namespace

TEST(EnsembleAggregate, FlattensSummariesByName) {
  const Json s = Json::parse(R"({"title": "t", "steps": 10, "completed": true, "wall_time_s": 3.0, "threads": 2,
    "final_energies": {"unit": "J_per_m", "kinetic": 1.5},
    "gauges": [{"name": "G1", "max_displacement_m": 2.0, "final_displacement_m": [1.0, -1.0]}],
    "river_blocked_time_s": null, "profile": [1, 2, 3, 4, 5]})");
  std::vector<std::string> names;
  for (const auto& [k, v] : ensemble::flatten_scalars(s)) names.push_back(k);
  EXPECT_EQ(names, (std::vector<std::string>{"steps", "completed", "final_energies.kinetic", "gauges.G1.max_displacement_m",
                                             "gauges.G1.final_displacement_m.0", "gauges.G1.final_displacement_m.1",
                                             "river_blocked_time_s"}));
}

// Friction uniform in [0.1, 0.5]: the displacement after t is x = (g sin - mu g cos) t^2 / 2,
// decreasing in mu, so its median is x(0.3) and P(x > d) = P(mu < mu_d) = (mu_d - 0.1) / 0.4.
// Both must lie in their 95 % intervals, which narrow like 1/sqrt(N) from 25 to 100 members.
// Monte Carlo: the first 25 members of the 100 are the 25-member ensemble (the rerun skips them).
TEST(EnsembleRun, AnalyticBlockOnAnInclineWithinItsIntervals) {
  const fs::path dir = test::fresh_dir("ens_analytic");
  fs::create_directories(dir);
  const double t = 0.3;  // nominal end; the summary's end_time_s is used below
  const double d = 0.5 * (kGs - 0.2 * kGc) * t * t;
  const std::string event = "events: [\"gauges.block.final_displacement_m.0 > " + std::to_string(d) + "\"]\n";
  const std::string key = "gauges.block.final_displacement_m.0";
  struct Widths {
    double mean, p50, event;
  };
  std::vector<Widths> widths;
  if (kSanitized) GTEST_SKIP() << "125 member runs: plain build only";
  for (int n : {25, 100}) {
    write(dir / "ens.yaml", friction_file(n, "monte_carlo", 4, event));
    const auto c = test::run_dsdem("ensemble " + (dir / "ens.yaml").string() + " -o " + (dir / "out").string() +
                                   " --jobs 2 -q --no-plots");
    ASSERT_EQ(c.exit_code, 0) << c.output;
    const Json e = read_json(dir / "out" / "ensemble.json");
    ASSERT_EQ(e["completed_members"].get<int>(), n);
    const double tend = e["scalars"]["end_time_s"]["p50"].get<double>();
    const double exact_p50 = 0.5 * (kGs - 0.3 * kGc) * tend * tend;
    const double mu_d = (kGs - 2.0 * d / (tend * tend)) / kGc;
    const double exact_p = (mu_d - 0.1) / 0.4;
    const Json& s = e["scalars"][key];
    const Json& ev = e["events"][key + " > " + std::to_string(d)];
    const double p50_lo = s["ci95"]["p50"][0], p50_hi = s["ci95"]["p50"][1];
    const double p_lo = ev["wilson95"][0], p_hi = ev["wilson95"][1];
    EXPECT_LE(p50_lo, exact_p50) << n;
    EXPECT_GE(p50_hi, exact_p50) << n;
    EXPECT_LE(p_lo, exact_p) << n;
    EXPECT_GE(p_hi, exact_p) << n;
    // P10 and P90 of the displacement: the friction's P90 (0.46) and P10 (0.14).
    for (const auto& [q, mu] : {std::pair<const char*, double>{"p10", 0.46}, {"p90", 0.14}}) {
      const double exact = 0.5 * (kGs - mu * kGc) * tend * tend;
      EXPECT_LE(s["ci95"][q][0].get<double>(), exact) << q << " " << n;
      EXPECT_GE(s["ci95"][q][1].get<double>(), exact) << q << " " << n;
      EXPECT_LE(s["ci95"][q][0].get<double>(), s[q].get<double>()) << q << " " << n;
      EXPECT_GE(s["ci95"][q][1].get<double>(), s[q].get<double>()) << q << " " << n;
    }
    const double m_lo = s["ci95"]["mean"][0], m_hi = s["ci95"]["mean"][1];
    widths.push_back({m_hi - m_lo, p50_hi - p50_lo, p_hi - p_lo});
    std::cout << "N = " << n << ": P50 " << s["p50"].get<double>() << " m in [" << p50_lo << ", " << p50_hi
              << "], exact " << exact_p50 << "; P(x > " << d << ") " << ev["probability"].get<double>() << " in ["
              << p_lo << ", " << p_hi << "], exact " << exact_p << "; widths mean " << m_hi - m_lo << ", P50 "
              << p50_hi - p50_lo << ", P " << p_hi - p_lo << "\n";
  }
  // Four times the members: intervals half as wide (sqrt 4), within the scatter of one sample.
  EXPECT_NEAR(widths[0].mean / widths[1].mean, 2.0, 0.5);
  EXPECT_NEAR(widths[0].p50 / widths[1].p50, 2.0, 1.0);
  EXPECT_NEAR(widths[0].event / widths[1].event, 2.0, 0.6);
}

// The members' results do not depend on how they ran: one at a time, two at a time, on two
// MPI ranks, or killed half-way and run again.
TEST(EnsembleRun, SameMembersCsvForJobsMpiAndAKilledRun) {
  const fs::path dir = test::fresh_dir("ens_same");
  fs::create_directories(dir);
  write(dir / "ens.yaml", friction_file(6, "latin_hypercube", 3,
                                        "  - {key: contact.restitution, distribution: uniform, lower: 0.1, upper: 0.35}\n"));
  const std::string ens = (dir / "ens.yaml").string();
  auto csv = [&](const std::string& out) { return test::read_text(dir / out / "members.csv"); };
  auto c = test::run_dsdem("ensemble " + ens + " -o " + (dir / "j1").string() + " --jobs 1 -q --no-plots");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const std::string reference = csv("j1");
  ASSERT_NE(reference.find("\n5,ok,0,"), std::string::npos) << reference;
  c = test::run_dsdem("ensemble " + ens + " -o " + (dir / "j2").string() + " --jobs 2 -q --no-plots");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_EQ(csv("j2"), reference);

  // Killed (SIGKILL, no chance to clean up) once two members are complete, then run again.
  const fs::path killed = dir / "killed";
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execl(DSDEM_BINARY, DSDEM_BINARY, "ensemble", ens.c_str(), "-o", killed.c_str(), "--jobs", "2", "--no-plots",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  auto complete = [&] {
    int n = 0;
    for (int i = 0; i < 6; ++i) n += fs::exists(killed / "members" / ("000" + std::to_string(i)) / "member.json");
    return n;
  };
  const auto t0 = std::chrono::steady_clock::now();
  while (complete() < 2 && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  const int done_before = complete();
  EXPECT_LT(done_before, 6) << "the ensemble finished before it was killed";
  EXPECT_FALSE(fs::exists(killed / "members.csv"));
  c = test::run_dsdem("ensemble " + ens + " -o " + killed.string() + " --jobs 2 --no-plots");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find(std::to_string(done_before) + " members already complete, skipped"), std::string::npos) << c.output;
  EXPECT_EQ(csv("killed"), reference);

  const std::string mpirun = DSDEM_MPIRUN;
  if (mpirun.empty()) GTEST_SKIP() << "built without MPI";
  const std::string root = ::geteuid() == 0 ? " --allow-run-as-root" : "";
  // Open MPI keeps memory to the end: no leak check of the ranks (sanitizer builds).
  c = test::run_command("ASAN_OPTIONS=detect_leaks=0 " + mpirun + root + " --oversubscribe -n 2 " + DSDEM_BINARY + " ensemble " + ens + " -o " +
                        (dir / "mpi").string() + " --jobs 1 -q --no-plots");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_EQ(csv("mpi"), reference);
}

// Under mpirun, a rank that cannot go on must not leave the others waiting for it: a rank
// without the ensemble file (it is read on every machine) stops them all before any member,
// and a rank that fails later (here its output folder is a file) ends the job. `timeout`
// turns a hang into exit code 124.
TEST(EnsembleRun, MpiRankThatCannotGoOnStopsTheOthers) {
  const std::string mpirun = DSDEM_MPIRUN;
  if (mpirun.empty()) GTEST_SKIP() << "built without MPI";
  const fs::path dir = test::fresh_dir("ens_mpi_fail");
  for (const char* d : {"a", "b", "c"}) fs::create_directories(dir / d);
  const std::string text = friction_file(4, "monte_carlo", 1);
  write(dir / "a" / "ens.yaml", text);  // b has none
  write(dir / "c" / "ens.yaml", text);
  write(dir / "c" / "out", "a file where rank 1 wants its output folder");
  const std::string root = ::geteuid() == 0 ? " --allow-run-as-root" : "";
  auto two_ranks = [&](const char* rank1_dir) {
    const std::string one = std::string(DSDEM_BINARY) + " ensemble ens.yaml -o out --jobs 1 -q --no-plots";
    return test::run_command("ASAN_OPTIONS=detect_leaks=0 timeout -k 10 120 " + mpirun + root + " --oversubscribe -n 1 -wdir " +
                             (dir / "a").string() + " " + one + " : -n 1 -wdir " + (dir / rank1_dir).string() + " " + one);
  };
  auto c = two_ranks("b");
  EXPECT_NE(c.exit_code, 0) << c.output;
  EXPECT_NE(c.exit_code, 124) << "the ranks hung\n" << c.output;
  EXPECT_NE(c.output.find("rank 1/2: error: the ensemble has 1 error"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("another rank could not read the ensemble"), std::string::npos) << c.output;
  EXPECT_FALSE(fs::exists(dir / "a" / "out" / "members")) << "a member started";

  fs::remove_all(dir / "a" / "out");
  c = two_ranks("c");
  EXPECT_NE(c.exit_code, 0) << c.output;
  EXPECT_NE(c.exit_code, 124) << "the ranks hung\n" << c.output;
  EXPECT_NE(c.output.find("rank 1/2: error:"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("ending every rank"), std::string::npos) << c.output;
}

// A member that fails is recorded with its exit status and diagnosis; the others run.
TEST(EnsembleRun, AFailedMemberIsRecordedAndTheOthersRun) {
  const fs::path dir = test::fresh_dir("ens_fail");
  fs::create_directories(dir);
  write(dir / "ens.yaml", "base: " + kBase + R"(
members: 4
vary:
  - {key: time.dt, distribution: list, values: [0.0001, 0.002]}
)");
  const auto c = test::run_dsdem("ensemble " + (dir / "ens.yaml").string() + " -o " + (dir / "out").string() + " -q --no-plots");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("4 members, 2 completed, 2 failed"), std::string::npos) << c.output;
  const Json e = read_json(dir / "out" / "ensemble.json");
  ASSERT_EQ(e["failures"].size(), 2u);
  EXPECT_EQ(e["failures"][0]["status"], "input_error");
  EXPECT_EQ(e["failures"][0]["exit_code"], 2);
  EXPECT_NE(e["failures"][0]["diagnosis"].get<std::string>().find("exceeds the stable time step"), std::string::npos);
  EXPECT_EQ(e["events"]["member_failed"]["count"], 2);
  const std::string csv = test::read_text(dir / "out" / "members.csv");
  EXPECT_NE(csv.find(",input_error,2,0.002"), std::string::npos) << csv;
}

TEST(EnsembleRun, BadInputStopsBeforeAnyMemberWithFileLineAndKey) {
  const fs::path dir = test::fresh_dir("ens_bad");
  fs::create_directories(dir);
  write(dir / "ens.yaml", "base: " + kBase + "\nmembers: 0\nvary:\n  - {key: contact.friction, distribution: triangular, "
                                             "lower: 0.1, mode: 0.7, upper: 0.5}\n");
  const auto c = test::run_dsdem("ensemble " + (dir / "ens.yaml").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(c.exit_code, 2);
  EXPECT_NE(c.output.find("ens.yaml:2:10: members: 0 is out of range"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("ens.yaml:4:73: vary[0].mode: impossible triangular distribution"), std::string::npos) << c.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// member.postprocess runs in each finished member; the keys it merges into summary.json are
// aggregated: a null threshold key is the event not happening, and a deposit_profile gives
// the hazard profile P(thickness > d) along x.
TEST(EnsembleRun, PostprocessKeysAndTheDepositHazardProfile) {
  const fs::path dir = test::fresh_dir("ens_post");
  fs::create_directories(dir);
  write(dir / "ens.yaml", "base: " + kBase + R"Y(
members: 4
vary:
  - {key: contact.friction, name: friction, distribution: list, values: [0.1, 0.2, 0.3, 0.4]}
events:
  - {name: blocked, when: "river_blocked_time_s >= 0"}
member:
  postprocess:
    - /usr/bin/python3
    - -c
    - "import json, sys; p = sys.argv[1] + '/summary.json'; d = json.load(open(p)); u = d['gauges'][0]['max_displacement_m']; d['deposit_profile'] = {'x_m': [0.0, 1.0, 2.0], 'thickness_m': [0.0, u, 2 * u]}; d['river_blocked_time_s'] = 1.0 if u > 0.1 else None; json.dump(d, open(p, 'w'))"
    - "{out}"
deposit_thresholds_m: [0.1]
)Y");
  const auto c = test::run_dsdem("ensemble " + (dir / "ens.yaml").string() + " -o " + (dir / "out").string() + " -q --no-plots");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const Json e = read_json(dir / "out" / "ensemble.json");
  ASSERT_EQ(e["completed_members"], 4) << e["failures"].dump();
  // x after 0.3 s for mu = 0.1 ... 0.4: 0.18, 0.14, 0.11, 0.07 m.
  EXPECT_EQ(e["events"]["blocked"]["n"], 4);
  EXPECT_EQ(e["events"]["blocked"]["count"], 3);
  EXPECT_EQ(test::read_text(dir / "out" / "deposit_hazard.csv"), "x_m,p_thicker_than_0.1_m\n0,0\n1,0.75\n2,1\n");
  // The envelopes' last row: P5, P50, P95 of the four members' final gauge displacements
  // (each member's last history row; they all end at the same time).
  auto last_row = [](const fs::path& file) {
    std::ifstream in(file);
    std::string header, line, last;
    std::getline(in, header);
    while (std::getline(in, line))
      if (!line.empty()) last = line;
    std::vector<std::pair<std::string, double>> row;
    std::stringstream hs(header), ls(last);
    for (std::string h, v; std::getline(hs, h, ',') && std::getline(ls, v, ',');) row.push_back({h, std::stod(v)});
    return row;
  };
  auto value = [](const std::vector<std::pair<std::string, double>>& row, const std::string& name) {
    for (const auto& [h, v] : row)
      if (h == name) return v;
    ADD_FAILURE() << "no column " << name;
    return 0.0;
  };
  const auto env = last_row(dir / "out" / "envelopes.csv");
  std::string gauge;
  for (const auto& [h, v] : env)
    if (h.size() > 18 && h.compare(h.size() - 18, 18, "_displacement_m_p5") == 0) gauge = h.substr(0, h.size() - 18);
  ASSERT_FALSE(gauge.empty());
  std::vector<double> final_u;
  for (int i = 0; i < 4; ++i) {
    const auto h = last_row(dir / "out" / "members" / ("000" + std::to_string(i)) / "history.csv");
    final_u.push_back(std::hypot(value(h, gauge + "_displacement_x_m"), value(h, gauge + "_displacement_y_m")));
  }
  std::sort(final_u.begin(), final_u.end());
  for (const auto& [q, p] : {std::pair<const char*, double>{"p5", 0.05}, {"p50", 0.5}, {"p95", 0.95}})
    EXPECT_NEAR(value(env, gauge + "_displacement_m_" + q), ensemble::quantile_sorted(final_u, p), 1e-12) << q;
  // Aggregated again from the folder, now with the plots and the report.
  const auto p = test::run_dsdem("ensemble " + (dir / "ens.yaml").string() + " -o " + (dir / "out").string() + " --aggregate-only");
  ASSERT_EQ(p.exit_code, 0) << p.output;
  for (const char* f : {"report.html", "plots/distributions.png", "plots/events.png", "plots/envelopes.png",
                        "plots/tornado.png", "plots/convergence.png", "plots/deposit_hazard.png"})
    EXPECT_TRUE(fs::exists(dir / "out" / f)) << f << "\n" << p.output;
}
