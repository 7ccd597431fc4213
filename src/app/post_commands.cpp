// dsdem plot / render / report: thin wrappers that check the output folder and run the
// post-processing scripts (see post_commands.hpp).
#include "app/post_commands.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>

extern char** environ;

namespace dsdem::app {

namespace fs = std::filesystem;

namespace {

constexpr int kExitFailure = 1;
constexpr int kExitInputError = 2;

std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return (v != nullptr && *v != '\0') ? std::string(v) : fallback;
}

std::string python_interpreter() {
  if (const char* v = std::getenv("DSDEM_PYTHON"); v != nullptr && *v != '\0') return v;
  // The system Python has numpy, matplotlib, meshio and VTK (scripts/install-deps.sh); a
  // pyenv or venv python3 earlier on PATH usually does not.
  std::error_code ec;
  if (fs::exists("/usr/bin/python3", ec)) return "/usr/bin/python3";
  return "python3";
}

// An output folder must exist and be a folder; prints the error and returns false if not.
bool check_out_dir(const std::string& out_dir) {
  std::error_code ec;
  if (out_dir.empty()) {
    fmt::print(stderr, "error: no output folder given\n");
    return false;
  }
  if (!fs::exists(out_dir, ec)) {
    fmt::print(stderr, "error: {}: no such output folder (give the -o folder of a dsdem run)\n", out_dir);
    return false;
  }
  if (!fs::is_directory(out_dir, ec)) {
    fmt::print(stderr, "error: {}: not a folder (give the -o folder of a dsdem run)\n", out_dir);
    return false;
  }
  return true;
}

bool check_file(const std::string& out_dir, const std::string& name, const std::string& hint) {
  std::error_code ec;
  const fs::path p = fs::path(out_dir) / name;
  if (!fs::is_regular_file(p, ec)) {
    fmt::print(stderr, "error: {}: not found{}\n", p.string(), hint.empty() ? "" : " (" + hint + ")");
    return false;
  }
  return true;
}

bool has_field_frames(const std::string& out_dir) {
  std::error_code ec;
  const fs::path out(out_dir);
  if (fs::is_regular_file(out / "fields.pvd", ec)) return true;
  if (!fs::is_directory(out / "fields", ec)) return false;
  for (const auto& e : fs::directory_iterator(out / "fields", ec))
    if (e.path().extension() == ".vtu") return true;
  return false;
}

[[noreturn]] void finish(int status) { throw CLI::RuntimeError(status); }

struct PlotOptions {
  std::string out;
  bool no_show_stages = false;
  bool quiet = false;
};

struct RenderOptions {
  std::string out;
  std::string field = "velocity";
  std::string frames = "all";
  bool movie = false;
  double fps = 10.0;
  std::string bbox;
  std::string clim;
  int width = 0;
  int jobs = 0;
  std::string water = "speed";
  std::string water_clim;
  std::string section;
  bool no_cracks = false;
  bool no_gauges = false;
  bool quiet = false;
};

struct ReportOptions {
  std::string out;
  bool no_render = false;
  bool quiet = false;
};

int run_plot_command(const PlotOptions& o) {
  if (!check_out_dir(o.out)) return kExitInputError;
  if (!check_file(o.out, "history.csv", "the run wrote no histories yet")) return kExitInputError;
  std::vector<std::string> args{o.out};
  if (o.no_show_stages) args.emplace_back("--no-show-stages");
  if (o.quiet) args.emplace_back("--quiet");
  return run_python_script("plot_history.py", args);
}

int run_render_command(const RenderOptions& o) {
  if (!check_out_dir(o.out)) return kExitInputError;
  if (!has_field_frames(o.out)) {
    fmt::print(stderr, "error: {}: not found (no field frames: was the run made with --no-fields?)\n",
               (fs::path(o.out) / "fields.pvd").string());
    return kExitInputError;
  }
  std::vector<std::string> args{o.out, "--field", o.field, "--frames", o.frames, "--fps", fmt::format("{}", o.fps)};
  if (o.movie) args.emplace_back("--movie");
  if (!o.bbox.empty()) args.insert(args.end(), {"--bbox", o.bbox});
  if (!o.clim.empty()) args.insert(args.end(), {"--clim", o.clim});
  if (o.width > 0) args.insert(args.end(), {"--width", std::to_string(o.width)});
  if (o.jobs > 0) args.insert(args.end(), {"--jobs", std::to_string(o.jobs)});
  args.insert(args.end(), {"--water", o.water});
  if (!o.water_clim.empty()) args.insert(args.end(), {"--water-clim", o.water_clim});
  if (!o.section.empty()) args.insert(args.end(), {"--section", o.section});
  if (o.no_cracks) args.emplace_back("--no-cracks");
  if (o.no_gauges) args.emplace_back("--no-gauges");
  if (o.quiet) args.emplace_back("--quiet");
  return run_python_script("render_fields.py", args);
}

int run_report_command(const ReportOptions& o) {
  if (!check_out_dir(o.out)) return kExitInputError;
  if (!check_file(o.out, "summary.json", "the run did not finish; dsdem writes it at the end")) return kExitInputError;
  std::vector<std::string> args{o.out};
  if (o.no_render) args.emplace_back("--no-render");
  if (o.quiet) args.emplace_back("--quiet");
  return run_python_script("report.py", args);
}

}  // namespace

std::string scripts_dir() {
#ifdef DSDEM_SOURCE_DIR
  const std::string fallback = std::string(DSDEM_SOURCE_DIR) + "/scripts";
#else
  const std::string fallback = "scripts";
#endif
  return env_or("DSDEM_SCRIPTS_DIR", fallback);
}

int run_python_script(const std::string& script_name, const std::vector<std::string>& args) {
  const fs::path script = fs::path(scripts_dir()) / script_name;
  std::error_code ec;
  if (!fs::is_regular_file(script, ec)) {
    fmt::print(stderr, "error: {}: script not found (set DSDEM_SCRIPTS_DIR to the scripts folder of dsdem)\n",
               script.string());
    return kExitFailure;
  }
  const std::string python = python_interpreter();
  std::vector<std::string> argv_s{python, script.string()};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  argv.reserve(argv_s.size() + 1);
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);

  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  pid_t pid = 0;
  const int err = ::posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ);
  if (err != 0) {
    fmt::print(stderr, "error: cannot start {}: {} (set DSDEM_PYTHON to a python3 with numpy, matplotlib, meshio)\n",
               python, std::strerror(err));
    return kExitFailure;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      fmt::print(stderr, "error: waiting for {}: {}\n", python, std::strerror(errno));
      return kExitFailure;
    }
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return kExitFailure;
}

int run_plot(const std::string& out_dir, bool quiet) {
  try {
    PlotOptions o;
    o.out = out_dir;
    o.quiet = quiet;
    return run_plot_command(o);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: plots of {}: {}\n", out_dir, e.what());
    return kExitFailure;
  }
}

void add_post_commands(CLI::App& app) {
  // plot
  {
    auto o = std::make_shared<PlotOptions>();
    auto* cmd = app.add_subcommand("plot", "Plot the histories of a run (gauges, energies, fracture, loads) into OUT/plots/");
    cmd->add_option("out", o->out, "Output folder of a dsdem run")->required();
    cmd->add_flag("--no-show-stages", o->no_show_stages, "Do not mark the stage changes");
    cmd->add_flag("-q,--quiet", o->quiet, "Do not list the files written");
    cmd->callback([o] { finish(run_plot_command(*o)); });
  }
  // render
  {
    auto o = std::make_shared<RenderOptions>();
    auto* cmd = app.add_subcommand("render",
                                   "Render field frames to PNG snapshots (and an mp4 movie) into OUT/render/; a 3D "
                                   "run gives two per frame: the model in perspective and a section through it");
    cmd->add_option("out", o->out, "Output folder of a dsdem run")->required();
    cmd->add_option("--field", o->field,
                    "velocity | displacement | material | stress (von Mises) | damage, or any array of the VTU "
                    "(e.g. max_principal_stress_Pa, zone, stress_Pa:xx)")
        ->capture_default_str();
    cmd->add_option("--frames", o->frames, "all | last | first | N | N,M | A-B (frame numbers)")->capture_default_str();
    cmd->add_flag("--movie", o->movie, "Also assemble OUT/render/<field>.mp4 with ffmpeg (H.264)");
    cmd->add_option("--fps", o->fps, "Movie frames per second")->check(CLI::PositiveNumber)->capture_default_str();
    cmd->add_option("--bbox", o->bbox,
                    "View box xmin,xmax,ymin,ymax in m; in 3D xmin,xmax,ymin,ymax,zmin,zmax (default: the model over "
                    "all frames)");
    cmd->add_option("--clim", o->clim, "Colour limits lo,hi in SI units (default: over all frames)");
    cmd->add_option("--width", o->width, "Image width in pixels (default 1280)")->check(CLI::Range(320, 8000));
    cmd->add_option("--jobs", o->jobs, "Parallel render processes (default: all cores, at most 8)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--water", o->water,
                    "The moving water's particles (OUT/water.pvd), drawn with the rock at the same time: coloured "
                    "by speed or pressure, or none")
        ->check(CLI::IsMember({"speed", "pressure", "none"}))
        ->capture_default_str();
    cmd->add_option("--water-clim", o->water_clim,
                    "The water's colour limits lo,hi in SI units (default: 0 to the 99th percentile of the particles "
                    "in the model over all frames)");
    cmd->add_option("--section", o->section,
                    "3D runs: the section's plane x|y|z[=COORDINATE in m], e.g. x=12.5 (default y through the "
                    "model's centre)");
    cmd->add_flag("--no-cracks", o->no_cracks, "Do not draw the joints (cracks)");
    cmd->add_flag("--no-gauges", o->no_gauges, "Do not mark the gauges");
    cmd->add_flag("-q,--quiet", o->quiet, "Print nothing but errors");
    cmd->callback([o] { finish(run_render_command(*o)); });
  }
  // report
  {
    auto o = std::make_shared<ReportOptions>();
    auto* cmd = app.add_subcommand("report", "Write OUT/report.html: a self-contained report of a run (tables, plots, snapshot)");
    cmd->add_option("out", o->out, "Output folder of a dsdem run")->required();
    cmd->add_flag("--no-render", o->no_render, "Do not render a field snapshot when OUT/render has none");
    cmd->add_flag("-q,--quiet", o->quiet, "Print nothing but errors");
    cmd->callback([o] { finish(run_report_command(*o)); });
  }
}

}  // namespace dsdem::app
