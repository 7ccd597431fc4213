#pragma once
// The work behind `dsdem wave generate` and `dsdem wave spectrum` (docs/theory.md §5, docs/user-guide.md),
// kept in the library so that it is testable; src/app/wave_command.cpp only parses
// options and calls these.
#include <string>
#include <vector>

#include "seismic/accelerogram.hpp"
#include "seismic/artificial_wave.hpp"
#include "seismic/response_spectrum.hpp"

namespace dsdem::seismic {

// scripts/plot_wave.py in the source tree (DSDEM_SOURCE_DIR).
std::string default_plot_script();

// What was written. png is empty when no plot was asked for or python failed (a
// warning is logged; the CSV files are kept).
struct WaveOutputs {
  std::string csv;           // the main CSV
  std::string spectrum_csv;  // generate: OUT.spectrum.csv; spectrum: same as csv
  std::string png;
};

// Generate an artificial accelerogram and write OUT.csv (t_s,a_mps2,v_mps,d_m),
// OUT.spectrum.csv (period_s,Sa_mps2,Sv_mps,Sd_m,target_Sa_mps2 at `periods`) and,
// when plot_script is not empty, OUT.png (time histories + spectrum vs target).
// OUT.png / OUT.spectrum.csv replace the .csv extension of out_csv (or are appended).
struct GenerateResult {
  ArtificialWave wave;
  WaveOutputs files;
};
GenerateResult run_wave_generate(const ArtificialWaveParams& params, const std::string& out_csv,
                                 const std::vector<double>& periods, const std::string& plot_script);

// Response spectrum of a record (CSV t,a in `units`, or PEER .AT2 in g) at `periods`
// and damping: writes out_csv (period_s,Sa_mps2,Sv_mps,Sd_m) and OUT.png.
struct SpectrumResult {
  Accelerogram record;
  ResponseSpectrum spectrum;
  WaveOutputs files;
};
SpectrumResult run_wave_spectrum(const std::string& input, AccelUnits units, double damping,
                                 const std::string& out_csv, const std::vector<double>& periods,
                                 const std::string& plot_script);

// Runs /usr/bin/python3 script args... (no shell). Returns false, with a warning
// logged, if it cannot start or exits non-zero.
bool run_python_script(const std::string& script, const std::vector<std::string>& args);

// "dir/name.csv" -> "dir/name" + suffix.
std::string replace_csv_extension(const std::string& path, const std::string& suffix);

}  // namespace dsdem::seismic
