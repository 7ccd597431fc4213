#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "model/types.hpp"
#include "seismic/response_spectrum.hpp"
#include "seismic/wave_tools.hpp"

using namespace dsdem;
using namespace dsdem::seismic;
namespace fs = std::filesystem;

namespace {
std::string first_line(const std::string& path) {
  std::ifstream in(path);
  std::string l;
  std::getline(in, l);
  return l;
}
fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::path(::testing::TempDir()) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
}  // namespace

TEST(WaveTools, CsvExtension) {
  EXPECT_EQ(replace_csv_extension("out/a.csv", ".png"), "out/a.png");
  EXPECT_EQ(replace_csv_extension("out/a.CSV", ".spectrum.csv"), "out/a.spectrum.csv");
  EXPECT_EQ(replace_csv_extension("out.d/a", ".png"), "out.d/a.png");
}

// `dsdem wave generate` with the paper's defaults: CSV with units in the header, the
// record reads back with the same PGA, the spectrum CSV carries the target, the PNG is
// made by scripts/plot_wave.py.
TEST(WaveTools, GenerateWritesCsvSpectrumAndPlot) {
  const fs::path d = temp_dir("dsdem_wave_generate");
  const std::string out = (d / "wave.csv").string();
  ArtificialWaveParams p;
  const GenerateResult r = run_wave_generate(p, out, log_spaced(0.04, 6.0, 40), default_plot_script());
  EXPECT_EQ(first_line(out), "t_s,a_mps2,v_mps,d_m");
  EXPECT_EQ(first_line(r.files.spectrum_csv), "period_s,Sa_mps2,Sv_mps,Sd_m,target_Sa_mps2");
  EXPECT_EQ(r.files.spectrum_csv, (d / "wave.spectrum.csv").string());
  const Accelerogram back = read_accelerogram_csv(out, AccelUnits::MetresPerSecondSquared, BaselineOptions{false, 3});
  ASSERT_EQ(back.size(), 501u);
  EXPECT_NEAR(back.pga(), 0.05 * kStandardGravity, 1e-9);
  EXPECT_EQ(r.files.png, (d / "wave.png").string());
  EXPECT_GT(fs::file_size(r.files.png), 10000u);
}

// `dsdem wave spectrum` on a PEER file: the CSV holds the Nigam-Jennings spectrum of
// the record as given; a failing plot script only costs the PNG.
TEST(WaveTools, SpectrumOfAt2AndPlotFailureKeepsCsv) {
  const fs::path d = temp_dir("dsdem_wave_spectrum");
  const std::string in = std::string(DSDEM_TEST_DATA_DIR) + "/seismic/sine_2hz.AT2";
  const std::string out = (d / "spec.csv").string();
  const std::vector<double> T = log_spaced(0.05, 2.0, 25);
  const SpectrumResult r = run_wave_spectrum(in, AccelUnits::MetresPerSecondSquared, 0.05, out, T,
                                             (d / "no_such_script.py").string());
  EXPECT_TRUE(r.files.png.empty());
  EXPECT_EQ(first_line(out), "period_s,Sa_mps2,Sv_mps,Sd_m");
  const Accelerogram rec = read_accelerogram_at2(in, BaselineOptions{false, 3});
  const ResponseSpectrum ref = response_spectrum(rec.a, rec.dt, T, 0.05);
  std::ifstream f(out);
  std::string line;
  std::getline(f, line);
  for (std::size_t j = 0; j < T.size(); ++j) {
    double t, sa, sv, sd;
    char c;
    ASSERT_TRUE(f >> t >> c >> sa >> c >> sv >> c >> sd);
    EXPECT_NEAR(sa, ref.Sa[j], 1e-8 * ref.Sa[j]);
    EXPECT_NEAR(sd, ref.Sd[j], 1e-8 * ref.Sd[j]);
  }
  EXPECT_THROW(run_wave_spectrum((d / "missing.csv").string(), AccelUnits::G, 0.05, out, T, ""),
               std::runtime_error);
}
