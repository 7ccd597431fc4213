#include "seismic/wave_tools.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "seismic/response_spectrum.hpp"

extern char** environ;

namespace dsdem::seismic {

std::string default_plot_script() {
#ifdef DSDEM_SOURCE_DIR
  return std::string(DSDEM_SOURCE_DIR) + "/scripts/plot_wave.py";
#else
  return "scripts/plot_wave.py";
#endif
}

std::string replace_csv_extension(const std::string& path, const std::string& suffix) {
  const auto slash = path.find_last_of('/');
  const auto dot = path.rfind('.');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) {
    std::string ext = path.substr(dot);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".csv") return path.substr(0, dot) + suffix;
  }
  return path + suffix;
}

bool run_python_script(const std::string& script, const std::vector<std::string>& args) {
  const std::string python = "/usr/bin/python3";
  std::vector<std::string> all{python, script};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ);
  if (rc != 0) {
    spdlog::warn("could not start {} {}: {}; the CSV output is kept, the plot is not made", python, script,
                 std::strerror(rc));
    return false;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      spdlog::warn("waiting for {} failed: {}", script, std::strerror(errno));
      return false;
    }
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    spdlog::warn("{} {} failed (exit status {}); the CSV output is kept, the plot is not made", python, script,
                 WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    return false;
  }
  return true;
}

GenerateResult run_wave_generate(const ArtificialWaveParams& params, const std::string& out_csv,
                                 const std::vector<double>& periods, const std::string& plot_script) {
  GenerateResult r;
  r.wave = generate_artificial_wave(params);
  r.files.csv = out_csv;
  write_accelerogram_csv(out_csv, r.wave.wave);
  const ResponseSpectrum s = response_spectrum(r.wave.wave.a, r.wave.wave.dt, periods, params.spectrum.damping);
  std::vector<double> target(periods.size());
  for (std::size_t j = 0; j < periods.size(); ++j) target[j] = params.spectrum.sa(periods[j]);
  r.files.spectrum_csv = replace_csv_extension(out_csv, ".spectrum.csv");
  write_spectrum_csv(r.files.spectrum_csv, s, target);
  if (!plot_script.empty()) {
    const std::string png = replace_csv_extension(out_csv, ".png");
    const std::string title =
        fmt::format("artificial wave: {} spectrum, PGA {:.3g} m/s2, Tg {} s, damping {}, seed {}",
                    to_string(params.spectrum.kind), params.spectrum.pga, params.spectrum.Tg,
                    params.spectrum.damping, params.seed);
    if (run_python_script(plot_script, {"--wave", out_csv, "--spectrum", r.files.spectrum_csv, "--png", png,
                                        "--title", title}))
      r.files.png = png;
  }
  return r;
}

SpectrumResult run_wave_spectrum(const std::string& input, AccelUnits units, double damping,
                                 const std::string& out_csv, const std::vector<double>& periods,
                                 const std::string& plot_script) {
  SpectrumResult r;
  // The spectrum of the record as given: no baseline correction.
  r.record = read_accelerogram(input, units, BaselineOptions{false, 3});
  r.spectrum = response_spectrum(r.record.a, r.record.dt, periods, damping);
  r.files.csv = r.files.spectrum_csv = out_csv;
  write_spectrum_csv(out_csv, r.spectrum);
  if (!plot_script.empty()) {
    const std::string png = replace_csv_extension(out_csv, ".png");
    const std::string title = fmt::format("response spectrum of {}, damping {}", input, damping);
    if (run_python_script(plot_script, {"--spectrum", out_csv, "--png", png, "--title", title})) r.files.png = png;
  }
  return r;
}

}  // namespace dsdem::seismic
