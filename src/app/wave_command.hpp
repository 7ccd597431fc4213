#pragma once
// `dsdem wave generate` and `dsdem wave spectrum` (docs/theory.md §5, docs/user-guide.md). The work is done
// by seismic/wave_tools; this only declares the options.
#include <CLI/CLI.hpp>

namespace dsdem::app {

void add_wave_commands(CLI::App& app);

}  // namespace dsdem::app
