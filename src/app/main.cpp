// dsdem command line: a thin layer over libdsdem (docs/user-guide.md).
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>

#include <csignal>
#include <filesystem>
#include <iostream>
#include <optional>
#include <unistd.h>

#include "app/ensemble_command.hpp"
#include "app/post_commands.hpp"
#include "app/sph_command.hpp"
#include "app/wave_command.hpp"
#include "dsdem_version.hpp"
#include "ensemble/ensemble_file.hpp"
#include "io/scenario.hpp"
#include "io/schema.hpp"
#include "mesh/model_builder3d.hpp"
#include "run/run3d.hpp"
#include "run/runner.hpp"
#include "run/stability.hpp"
#include "solver/solver.hpp"

namespace {

// Exit codes: 0 success, 1 unexpected failure, 2 bad input, 3 the run went unstable.
constexpr int kExitInputError = 2;
constexpr int kExitUnstable = 3;

// SIGINT / SIGTERM during a run: the first one asks the run to stop cleanly at the end of
// the current step (last fields, history and summary written; exit code 128 + signal);
// the handler then resets, so a second one ends the process at once.
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }

void install_stop_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int guarded(const std::function<int()>& body) {
  try {
    return body();
  } catch (const dsdem::io::ScenarioError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitInputError;
  } catch (const dsdem::solver::InstabilityError& e) {
    fmt::print(stderr, "error: the run went unstable: {}\n", e.what());
    return kExitUnstable;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
}

// Removes a scratch folder when it goes out of scope.
struct ScratchDir {
  std::filesystem::path p;
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(p, ec);
  }
};

struct RunArgs {
  CLI::App* cmd = nullptr;
  std::string scenario_path, out_dir = "out";
  std::vector<std::string> sets;
  int threads = 0;
  bool quiet = false, no_fields = false, no_plots = false;
  std::string restart_path;
  long stop_at_step = 0;
};

void add_run_command(CLI::App& app, RunArgs& a) {
  auto* run_cmd = app.add_subcommand("run", "Run a scenario");
  a.cmd = run_cmd;
  run_cmd->add_option("scenario", a.scenario_path, "Scenario YAML file")->required();
  run_cmd->add_option("-o,--output", a.out_dir, "Output directory")->capture_default_str();
  run_cmd->add_option("--threads", a.threads, "OpenMP threads (default: all cores)")->check(CLI::NonNegativeNumber);
  run_cmd->add_option("--set", a.sets, "Override a scenario value: key.path=value (repeatable)");
  run_cmd->add_flag("-q,--quiet", a.quiet, "No progress on the terminal (the log still gets everything)");
  run_cmd->add_flag("--no-fields", a.no_fields, "Do not write VTU field frames");
  run_cmd->add_flag("--no-plots", a.no_plots, "Do not make the history plots at the end");
  run_cmd->add_option("--restart", a.restart_path,
                      "Continue from a checkpoint (OUT/checkpoint.h5) of an earlier run of the same scenario; the "
                      "output goes on in the checkpoint's folder unless -o names another")
      ->check(CLI::ExistingFile);
  run_cmd->add_option("--stop-at-step", a.stop_at_step,
                      "Stop cleanly after this step, writing a checkpoint (e.g. to split a run into batch jobs)")
      ->check(CLI::PositiveNumber);
}

// Runs a prepared scenario of either dimension (run_fn: run::run or run::run_3d) and says
// where its results are and how to continue a stopped run.
template <class Prepared, class RunFn>
int run_prepared(RunArgs& a, Prepared& prepared, RunFn run_fn, bool plots) {
  dsdem::run::RunOptions options;
  options.output_dir = a.out_dir;
  options.threads = a.threads;
  options.quiet = a.quiet;
  options.write_fields = !a.no_fields;
  options.stop_signal = &g_stop_signal;
  options.restart_from = a.restart_path;
  options.stop_at_step = a.stop_at_step;
  if (!a.restart_path.empty() && a.cmd->count("--output") == 0)
    options.output_dir = a.out_dir = std::filesystem::path(a.restart_path).parent_path().string();
  if (options.output_dir.empty()) options.output_dir = a.out_dir = ".";
  if (g_stop_signal) return 128 + static_cast<int>(g_stop_signal);  // stopped while meshing: nothing written
  const auto result = run_fn(prepared, options);
  if (result.stopped_by_signal) {
    fmt::print(stderr, "stopped by signal {}: last fields, history and summary in {}; continue with {}\n",
               result.stopped_by_signal, a.out_dir, result.continue_command);
    return 128 + result.stopped_by_signal;
  }
  if (result.stopped_at_step) {
    fmt::print("stopped at step {} as asked: results so far in {}; continue with {}\n", result.steps, a.out_dir,
               result.continue_command);
    return 0;
  }
  fmt::print("results in {} ({} steps, {:.1f} s wall, energy balance error {:.2e})\n", a.out_dir, result.steps,
             result.wall_time_s, result.energy_balance_error);
  if (plots && !a.no_plots && dsdem::app::run_plot(a.out_dir, true) != 0)
    fmt::print(stderr, "warning: history plots were not made\n");
  return 0;
}

int run_command(RunArgs& a) {
  install_stop_handlers();
  const auto sc = dsdem::io::load_scenario(a.scenario_path, a.sets);
  if (a.threads > 0) omp_set_num_threads(a.threads);
  // Mesh and validate in a scratch folder: a scenario that fails leaves no output behind.
  const auto work = std::filesystem::temp_directory_path() / fmt::format("dsdem-run-{}", ::getpid());
  ScratchDir cleanup{work};
  // A volume mesh makes a 3D model (docs/theory.md §14): the same runner, no history plots yet.
  if (auto mesh3 = dsdem::mesh::load_volume_mesh(sc, work.string())) {
    auto prepared = dsdem::run::prepare_run_3d(sc, *mesh3);
    std::error_code ec;
    std::filesystem::remove_all(work, ec);
    return run_prepared(a, prepared, dsdem::run::run_3d, false);
  }
  auto prepared = dsdem::run::prepare_run(sc, work.string());
  // The mesh is in memory now (prepared.mesh_text): no scratch folder left behind by a
  // run killed outright later on.
  std::error_code ec;
  std::filesystem::remove_all(work, ec);
  return run_prepared(a, prepared, dsdem::run::run, true);
}

struct CheckArgs {
  CLI::App* cmd = nullptr;
  std::string scenario_path;
  std::vector<std::string> sets;
};

void add_check_command(CLI::App& app, CheckArgs& a) {
  a.cmd = app.add_subcommand("check", "Validate a scenario and print the model, dt and a run-time estimate");
  a.cmd->add_option("scenario", a.scenario_path, "Scenario YAML file")->required();
  a.cmd->add_option("--set", a.sets, "Override a scenario value: key.path=value (repeatable)");
}

int check_command(const CheckArgs& a) {
  const auto sc = dsdem::io::load_scenario(a.scenario_path, a.sets);
  const auto work = std::filesystem::temp_directory_path() / fmt::format("dsdem-check-{}", ::getpid());
  ScratchDir cleanup{work};
  if (auto mesh3 = dsdem::mesh::load_volume_mesh(sc, work.string())) {
    fmt::print("{}", dsdem::run::check_report_3d(dsdem::run::prepare_run_3d(sc, *mesh3)));
    fmt::print("scenario OK\n");
    return 0;
  }
  auto prepared = dsdem::run::prepare_run(sc, work.string());
  fmt::print("{}", dsdem::run::check_report(prepared));
  fmt::print("scenario OK\n");
  return 0;
}

struct StabilityArgs {
  CLI::App* cmd = nullptr;
  std::string scenario_path, out_dir = "out";
  std::vector<std::string> sets;
  int threads = 0;
  bool quiet = false, no_plots = false, dynamic = false, check_budget = false;
  std::optional<double> kh, kv, tolerance;
  std::vector<double> bounds;
};

void add_stability_command(CLI::App& app, StabilityArgs& a) {
  a.cmd = app.add_subcommand("stability", "Factor of safety by strength reduction (static, pseudo-static, dynamic)");
  // The long help under `dsdem stability --help`; the top-level list keeps one line per command.
  a.cmd->footer(
      "Factor of safety by strength reduction (docs/theory.md §9): c/F, tan(phi)/F and ft/F for every joint, "
      "Mohr-Coulomb material and contact friction; bisection on F.\n"
      "The scenario's static stages (before its first earthquake stage) settle the slope at full strength with "
      "elastic joints; each trial F starts from that state with reduced strengths and failure allowed, solved "
      "quasi-statically (local non-viscous damping 0.8 and adaptive mass damping; stability.damping fixes the "
      "mass damping instead), never with the scenario's damping. A trial STANDS when the largest unbalanced "
      "nodal force falls below stability.equilibrium_ratio (1e-5) times the mean nodal weight; it FAILS when a "
      "monitored point (stability.monitor, else any node) moves stability.failure_displacement (default: the "
      "mean element size of the discrete zone) from the settled state, when the monitored mass keeps moving over "
      "a doubling of the trial (accelerating, or creeping with its unbalanced force undiminished), or when the run "
      "goes unstable; it is UNDECIDED when neither comes within stability.max_steps. FS is the largest F that "
      "stood, to "
      "stability.tolerance (0.005). With kh/kv also the pseudo-static FS: body force |g| (kh, kv) m, kh > 0 "
      "toward +x (give the sign of the free face), kv > 0 upward.\n"
      "With --dynamic also the dynamic FS: the scenario's earthquake stages at strengths 1/F from the settled "
      "state; a trial fails when a monitored point moves failure_displacement during them.\n"
      "Writes OUT/summary.json (factor_of_safety[, factor_of_safety_pseudo_static, factor_of_safety_dynamic], the "
      "brackets, the trials), OUT/trials.csv and stability_trials.png (each trial's unbalanced force ratio and "
      "displacement), OUT/fs_displacement.png, OUT/mechanism*.vtu (the lowest F that failed) and mechanism*.png, OUT/stability.log.");
  a.cmd->add_option("scenario", a.scenario_path, "Scenario YAML file")->required();
  a.cmd->add_option("-o,--output", a.out_dir, "Output directory")->capture_default_str();
  a.cmd->add_option("--threads", a.threads, "OpenMP threads (default: all cores)")->check(CLI::NonNegativeNumber);
  a.cmd->add_option("--set", a.sets, "Override a scenario value: key.path=value (repeatable)");
  a.cmd->add_option("--kh", a.kh, "Pseudo-static horizontal coefficient (stability.kh), > 0 toward +x");
  a.cmd->add_option("--kv", a.kv, "Pseudo-static vertical coefficient (stability.kv), > 0 upward");
  a.cmd->add_flag("--check-budget", a.check_budget,
                  "Rerun the two trials that bracket the FS watched twice as long (stability.check_budget) and say "
                  "whether their verdicts held");
  a.cmd->add_flag("--dynamic", a.dynamic,
                  "Also the dynamic FS (stability.dynamic): the earthquake stages at strengths 1/F from the settled "
                  "state; a trial fails when a monitored point moves failure_displacement");
  a.cmd->add_option("--bounds", a.bounds, "F_low F_high (stability.bounds)")->expected(2);
  a.cmd->add_option("--tolerance", a.tolerance, "Bisection tolerance on F (stability.tolerance)");
  a.cmd->add_flag("-q,--quiet", a.quiet, "No progress on the terminal (OUT/stability.log still gets it)");
  a.cmd->add_flag("--no-plots", a.no_plots,
                  "Do not make fs_displacement.png, stability_trials.png and the mechanism picture");
}

int stability_command(StabilityArgs& a) {
  install_stop_handlers();
  // The flags are overrides of the stability section: errors then name the flag.
  std::vector<std::string> sets = a.sets;
  auto num = [](double v) { return fmt::format("{:.17g}", v); };
  if (a.kh) sets.push_back("stability.kh=" + num(*a.kh));
  if (a.kv) sets.push_back("stability.kv=" + num(*a.kv));
  if (a.tolerance) sets.push_back("stability.tolerance=" + num(*a.tolerance));
  if (a.dynamic) sets.push_back("stability.dynamic=true");
  if (a.check_budget) sets.push_back("stability.check_budget=true");
  if (a.bounds.size() == 2) sets.push_back(fmt::format("stability.bounds=[{}, {}]", num(a.bounds[0]), num(a.bounds[1])));
  const auto sc = dsdem::io::load_scenario(a.scenario_path, sets);
  if (a.threads > 0) omp_set_num_threads(a.threads);
  const auto work = std::filesystem::temp_directory_path() / fmt::format("dsdem-stability-mesh-{}", ::getpid());
  ScratchDir cleanup{work};
  dsdem::run::StabilityOptions options;
  options.output_dir = a.out_dir.empty() ? "." : a.out_dir;
  options.threads = a.threads;
  options.quiet = a.quiet;
  options.stop_signal = &g_stop_signal;
  // A volume mesh makes a 3D model (docs/theory.md §14); the procedure is the same.
  const auto result = [&] {
    std::error_code ec;
    if (auto mesh3 = dsdem::mesh::load_volume_mesh(sc, work.string())) {
      auto prepared = dsdem::run::prepare_run_3d(sc, *mesh3);
      std::filesystem::remove_all(work, ec);
      return dsdem::run::find_factor_of_safety(prepared, options);
    }
    auto prepared = dsdem::run::prepare_run(sc, work.string());
    std::filesystem::remove_all(work, ec);
    return dsdem::run::find_factor_of_safety(prepared, options);
  }();
  if (result.stopped_by_signal) return 128 + result.stopped_by_signal;
  fmt::print("factor of safety {:.3f}", result.factor_of_safety);
  if (result.factor_of_safety_pseudo_static)
    fmt::print(", pseudo-static {:.3f}", *result.factor_of_safety_pseudo_static);
  if (result.factor_of_safety_dynamic) fmt::print(", dynamic {:.3f}", *result.factor_of_safety_dynamic);
  fmt::print(" ({} trials, {:.1f} s wall); results in {}\n", result.trials.size(), result.wall_time_s,
             options.output_dir);
  if (!a.no_plots && dsdem::app::run_python_script("plot_stability.py", {options.output_dir}) != 0)
    fmt::print(stderr, "warning: the stability plots were not made\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dsdem: continuous-discontinuous simulation of rock-slope failure and landslide run-out (FEM-DSDEM, 2D)"};
  app.require_subcommand(0, 1);
  bool show_version = false;
  app.add_flag("--version", show_version, "Print version and git commit");
  RunArgs run_args;
  add_run_command(app, run_args);
  CheckArgs check_args;
  add_check_command(app, check_args);
  StabilityArgs stability_args;
  add_stability_command(app, stability_args);
  auto* schema_cmd = app.add_subcommand("schema", "Print the scenario reference (every key, unit, default, range) as Markdown");
  bool ensemble_schema = false;
  schema_cmd->add_flag("--ensemble", ensemble_schema, "The keys of an ensemble file instead (docs/ensemble-reference.md)");
  dsdem::app::EnsembleArgs ensemble_args;
  dsdem::app::add_ensemble_command(app, ensemble_args);
  dsdem::app::add_wave_commands(app);
  dsdem::app::add_sph_commands(app);
  dsdem::app::add_post_commands(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  if (show_version) {
    fmt::print("dsdem {} (git {})\n", DSDEM_VERSION, DSDEM_GIT_COMMIT);
    return 0;
  }
  if (*run_args.cmd) return guarded([&] { return run_command(run_args); });
  if (*check_args.cmd) return guarded([&] { return check_command(check_args); });
  if (*stability_args.cmd) return guarded([&] { return stability_command(stability_args); });
  if (*ensemble_args.cmd) return guarded([&] { return dsdem::app::ensemble_command(ensemble_args); });
  if (*schema_cmd) {
    fmt::print("{}", ensemble_schema ? dsdem::ensemble::ensemble_schema_markdown() : dsdem::io::schema_markdown());
    return 0;
  }
  // `wave` and the post commands ran in their callbacks; help only for a bare `dsdem`.
  if (app.get_subcommands().empty()) fmt::print("{}", app.help());
  return 0;
}
