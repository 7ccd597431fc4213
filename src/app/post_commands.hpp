#pragma once
// Post-processing subcommands of the dsdem command line (docs/user-guide.md):
//
//   dsdem plot OUT [--no-show-stages]      PNG history plots into OUT/plots/
//   dsdem render OUT [--field F] [--frames all|last|N,M|A-B] [--movie] [--fps 10]
//                [--bbox xmin,xmax,ymin,ymax] [--water speed|pressure|none] [--water-clim lo,hi]
//                                          PNG snapshots (and an mp4) into OUT/render/,
//                                          the moving water's particles with the rock
//   dsdem report OUT                        self-contained OUT/report.html
//
// The work is done by the Python scripts scripts/plot_history.py, render_fields.py and
// report.py (matplotlib, meshio, ffmpeg), run with /usr/bin/python3 (override: env
// DSDEM_PYTHON). The scripts are found in $DSDEM_SCRIPTS_DIR if set, else in
// DSDEM_SOURCE_DIR/scripts. Exit codes: 0 success, 1 unexpected failure, 2 bad input (a
// missing output folder or file, an unknown field, ...), else the script's own status.
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace dsdem::app {

// Registers the plot, render and report subcommands on `app`. Each runs from its CLI11
// callback and ends the parse by throwing CLI::RuntimeError(exit status) (also for
// status 0), which the usual `catch (const CLI::ParseError& e) { return app.exit(e); }`
// turns into the process exit status without printing anything more.
void add_post_commands(CLI::App& app);

// `dsdem plot OUT` as a function, for the end of `dsdem run`: writes OUT/plots/*.png.
// quiet: do not list the files written (errors are still printed on stderr).
// Returns the exit status (0 ok, 2 OUT or OUT/history.csv missing, else the script's).
// Never throws.
int run_plot(const std::string& out_dir, bool quiet);

// Lower level, exposed for tests and other commands.
// The folder holding the scripts: $DSDEM_SCRIPTS_DIR, else DSDEM_SOURCE_DIR/scripts.
std::string scripts_dir();
// Runs `python script args...` (no shell), stdout/stderr inherited, and returns its exit
// status (128 + signal if it was killed; 1 with a message if it could not be started).
int run_python_script(const std::string& script_name, const std::vector<std::string>& args);

}  // namespace dsdem::app

// The names main.cpp calls.
using dsdem::app::add_post_commands;
using dsdem::app::run_plot;
