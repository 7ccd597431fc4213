#pragma once
// `dsdem ensemble ENSEMBLE.yaml -o OUT` (docs/theory.md §13): many runs of one scenario with
// sampled values, on one machine (a pool of processes) or many (mpirun), and their statistics.
#include <CLI/CLI.hpp>

#include <string>

namespace dsdem::app {

struct EnsembleArgs {
  CLI::App* cmd = nullptr;
  std::string file, out_dir = "ensemble_out";
  int jobs = 0;
  bool quiet = false, no_plots = false, check_only = false, aggregate_only = false;
};

void add_ensemble_command(CLI::App& app, EnsembleArgs& a);
// Exit codes: 0 done (failed members are recorded, not fatal), 2 bad input, 128 + signal when stopped.
int ensemble_command(const EnsembleArgs& a);

}  // namespace dsdem::app
