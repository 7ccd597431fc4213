#pragma once
// Runs a scenario end to end: stages, output, checkpoints, summary (docs/user-guide.md).
// prepare_run (run/prepare.hpp) builds what it runs; check_report (run/check.hpp) is
// `dsdem check`.
#include <csignal>
#include <string>

#include "run/check.hpp"
#include "run/prepare.hpp"

namespace dsdem::run {

struct RunOptions {
  std::string output_dir = "out";
  int threads = 0;          // 0 = all cores
  bool quiet = false;       // no progress lines on the terminal
  bool write_fields = true;
  // Set (to the signal number) by a SIGINT/SIGTERM handler: the run stops at the end of
  // the current step and writes its last fields, history and summary.
  const volatile std::sig_atomic_t* stop_signal = nullptr;
  // Continue from this checkpoint (OUT/checkpoint.h5 of an earlier run of the same
  // scenario). In the checkpoint's own directory the run continues its files; elsewhere
  // new files start at the checkpoint's time.
  std::string restart_from;
  // Stop cleanly after this step with a checkpoint (0: run to the end), e.g. to split a
  // long run into batch jobs.
  long stop_at_step = 0;
};

struct RunResult {
  long steps = 0;
  double wall_time_s = 0.0;
  double energy_balance_error = 0.0;
  std::string summary_path;
  int stopped_by_signal = 0;  // the signal that stopped the run early, 0 if it ran to the end
  bool stopped_at_step = false;  // RunOptions::stop_at_step reached
  std::string checkpoint_path;   // the last checkpoint written
  // The command that continues the run from it: the scenario, its --set overrides (shell-quoted)
  // and --restart.
  std::string continue_command;
};

// Runs every stage and writes OUT/{fields.pvd, fields/, history.csv, summary.json, dsdem.log}.
RunResult run(PreparedRun& prepared, const RunOptions& options);

}  // namespace dsdem::run
