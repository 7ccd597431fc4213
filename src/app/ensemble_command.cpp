#include "app/ensemble_command.hpp"

#include <fmt/format.h>

#include <csignal>
#include <filesystem>
#include <thread>

#include "app/post_commands.hpp"
#include "ensemble/aggregate.hpp"
#include "ensemble/ensemble_file.hpp"
#include "ensemble/member_runner.hpp"
#include "ensemble/mpi_ranks.hpp"
#include "io/atomic_file.hpp"

namespace dsdem::app {

namespace fs = std::filesystem;

namespace {

volatile std::sig_atomic_t g_ensemble_stop = 0;
extern "C" void on_ensemble_stop(int sig) { g_ensemble_stop = sig; }

void install_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_ensemble_stop;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: waitpid returns, and the runner sees the flag
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

struct RanksGuard {
  ensemble::Ranks r;
  ~RanksGuard() { ensemble::finish_ranks(r); }
};

std::string rank_label(const ensemble::Ranks& r) {
  return r.size > 1 ? fmt::format("rank {}/{}: ", r.rank, r.size) : "";
}

// This rank's members run (a pool of processes), their files gathered on rank 0; the
// signal that stopped some rank, 0 if none did.
int run_this_ranks_members(const EnsembleArgs& a, const ensemble::EnsembleSpec& spec,
                           const std::vector<ensemble::MemberPlan>& plans, const ensemble::Ranks& r, const fs::path& out) {
  ensemble::RunnerOptions o;
  o.out_dir = out;
  o.dsdem_exe = fs::read_symlink("/proc/self/exe").string();
  o.scripts_dir = scripts_dir();
  const int cores = std::max(1u, std::thread::hardware_concurrency());
  o.jobs = a.jobs > 0 ? a.jobs : std::max(1, cores / std::max(1, r.local_size) / spec.member_threads);
  o.quiet = a.quiet;
  o.label = rank_label(r);
  o.stop_signal = &g_ensemble_stop;
  const auto mine = ensemble::members_of_rank(spec.members, r);
  const auto res = ensemble::run_members(spec, plans, mine, o);
  if (!a.quiet && res.skipped > 0)
    fmt::print(stderr, "{}ensemble: {} members already complete, skipped\n", o.label, res.skipped);
  std::vector<fs::path> dirs;
  for (std::size_t i : mine) dirs.push_back(ensemble::member_dir(out, i, spec.members));
  ensemble::gather_member_files(r, dirs, {"summary.json", "history.csv", "diagnosis.json", "member.log"}, "member.json");
  return ensemble::max_over_ranks(r, res.stopped ? static_cast<int>(g_ensemble_stop ? g_ensemble_stop : SIGTERM) : 0);
}

}  // namespace

void add_ensemble_command(CLI::App& app, EnsembleArgs& a) {
  a.cmd = app.add_subcommand("ensemble", "Many runs of a scenario with sampled values, on one machine or over MPI");
  // The long help under `dsdem ensemble --help`; the top-level list keeps one line per command.
  a.cmd->footer(
      "Many runs of a scenario with sampled values (docs/theory.md §13, docs/ensemble-reference.md): the members run as "
      "`dsdem run` processes, --jobs at a time (under `mpirun -n K` dealt to the K ranks, gathered on rank 0), in "
      "OUT/members/NNNN; a rerun skips members already complete and reruns those that were killed. Writes "
      "OUT/members.csv, OUT/ensemble.json (percentiles with bootstrap intervals, event probabilities with Wilson "
      "intervals, exceedance, sensitivity, convergence), OUT/envelopes.csv, OUT/plots/ and OUT/report.html.");
  a.cmd->add_option("ensemble", a.file, "Ensemble YAML file")->required();
  a.cmd->add_option("-o,--output", a.out_dir, "Output directory")->capture_default_str();
  a.cmd->add_option("--jobs", a.jobs, "Members at a time (per rank; default: the cores, shared by the ranks of a machine)")
      ->check(CLI::NonNegativeNumber);
  a.cmd->add_flag("-q,--quiet", a.quiet, "No progress lines");
  a.cmd->add_flag("--no-plots", a.no_plots, "No plots and no report.html");
  a.cmd->add_flag("--check", a.check_only, "Validate the file and every member's scenario, print the members, run nothing");
  a.cmd->add_flag("--aggregate-only", a.aggregate_only, "Run no member: aggregate what OUT/members holds");
}

int ensemble_command(const EnsembleArgs& a) {
  install_handlers();
  RanksGuard ranks{ensemble::start_ranks()};
  const ensemble::Ranks& r = ranks.r;
  const bool root = r.rank == 0;
  ensemble::EnsembleSpec spec;
  std::vector<ensemble::MemberPlan> plans;
  // Every rank reads the file; a rank that cannot (another machine without it, say) must
  // not leave the others waiting for its members: they agree before any member starts.
  std::vector<std::string> errors;
  try {
    spec = ensemble::load_ensemble(a.file);
    plans = ensemble::plan_members(spec);
    ensemble::validate_members(spec, plans);
  } catch (const io::ScenarioError& e) {
    errors = e.errors();
  } catch (const std::exception& e) {
    if (r.size == 1) throw;
    errors = {e.what()};
  }
  const int bad = errors.empty() ? 0 : 1;
  const bool any_bad = ensemble::max_over_ranks(r, bad) != 0;
  const bool root_bad = ensemble::max_over_ranks(r, root ? bad : 0) != 0;
  if (any_bad) {
    // Rank 0's errors, or those of the ranks that alone could not read it (once each).
    if (bad && (root || !root_bad)) {
      fmt::print(stderr, "{}error: the ensemble has {} error{}:\n", root ? "" : rank_label(r), errors.size(),
                 errors.size() == 1 ? "" : "s");
      for (const auto& l : errors) fmt::print(stderr, "  {}\n", l);
    }
    if (root && !bad) fmt::print(stderr, "error: another rank could not read the ensemble (its errors are above)\n");
    return 2;
  }
  if (a.check_only) {
    if (root) {
      fmt::print("{} members of {} ({}, seed {}):\n", spec.members, spec.base,
                 spec.method == ensemble::SamplingMethod::MonteCarlo ? "Monte Carlo" : "Latin hypercube", spec.seed);
      for (const auto& p : plans) {
        std::string line;
        for (std::size_t j = 0; j < spec.vary.size(); ++j)
          line += fmt::format("{}{}={}", j ? " " : "", spec.vary[j].name, p.values[j]);
        fmt::print("  {}: {}\n", ensemble::member_folder_name(p.index, spec.members), line);
      }
      fmt::print("ensemble OK\n");
    }
    return 0;
  }
  const fs::path out(a.out_dir.empty() ? "." : a.out_dir);
  int stopped = 0;
  try {
    io::ensure_writable_directory(out / "members");
    if (!a.aggregate_only) stopped = run_this_ranks_members(a, spec, plans, r, out);
  } catch (const std::exception& e) {
    if (r.size == 1) throw;
    // The other ranks wait for this one's files or its vote: end them all.
    fmt::print(stderr, "{}error: {}; ending every rank (members already complete are kept: run the same command again "
               "to go on)\n", rank_label(r), e.what());
    ensemble::abort_ranks(r, 1);
  }
  if (!root) return stopped ? 128 + stopped : 0;
  if (stopped) {
    fmt::print(stderr, "stopped by signal {}: the members that finished are kept; run the same command again to go on\n",
               stopped);
    return 128 + stopped;
  }
  const auto agg = ensemble::aggregate(spec, plans, out);
  fmt::print("ensemble: {} members, {} completed, {} failed{}; results in {} (members.csv, ensemble.json)\n", agg.members,
             agg.ok, agg.failed, agg.missing ? fmt::format(", {} not run", agg.missing) : "", out.string());
  if (!a.no_plots && run_python_script("plot_ensemble.py", {out.string()}) != 0)
    fmt::print(stderr, "warning: the ensemble plots and report were not made\n");
  return 0;
}

}  // namespace dsdem::app
