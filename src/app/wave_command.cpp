#include "app/wave_command.hpp"

#include <exception>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "model/types.hpp"
#include "seismic/response_spectrum.hpp"
#include "seismic/wave_tools.hpp"

namespace dsdem::app {

namespace {

struct GenerateOptions {
  seismic::ArtificialWaveParams p;
  std::string spectrum = "beta";
  double pga = 0.05;
  std::string pga_units = "g";
  std::string out;
  bool no_plot = false;
};

struct SpectrumOptions {
  std::string input;
  std::string units = "m/s2";
  double damping = 0.05;
  double tmin = 0.02, tmax = 10.0;
  int n = 200;
  std::string out;
  bool no_plot = false;
};

// Errors become one clear line and exit status 1 (CLI11_PARSE turns CLI::Error into it).
template <class F>
void guarded(F&& f) {
  try {
    f();
  } catch (const CLI::Error&) {
    throw;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    throw CLI::RuntimeError(1);
  }
}

}  // namespace

void add_wave_commands(CLI::App& app) {
  auto* wave = app.add_subcommand("wave", "Earthquake input: artificial accelerograms and response spectra");
  wave->require_subcommand(1);

  auto g = std::make_shared<GenerateOptions>();
  auto* gen = wave->add_subcommand(
      "generate", "Artificial accelerogram fitting a code spectrum (GB 17741 method); defaults = the paper's case");
  gen->add_option("--spectrum", g->spectrum, "Target spectrum: beta (hydraulic) or alpha (GB 50011)")
      ->capture_default_str();
  gen->add_option("--beta-max", g->p.spectrum.beta_max, "Peak amplification beta_max")->capture_default_str();
  gen->add_option("--pga", g->pga, "Peak ground acceleration, in --pga-units")->capture_default_str();
  gen->add_option("--pga-units", g->pga_units, "Units of --pga: g or m/s2")->capture_default_str();
  gen->add_option("--tg", g->p.spectrum.Tg, "Characteristic period Tg, s")->capture_default_str();
  gen->add_option("--damping", g->p.spectrum.damping, "Damping ratio of the spectrum")->capture_default_str();
  gen->add_option("--dt", g->p.dt, "Time step, s")->capture_default_str();
  gen->add_option("--duration", g->p.duration, "Duration, s")->capture_default_str();
  gen->add_option("--t1", g->p.t1, "Envelope: end of the (t/t1)^2 rise, s")->capture_default_str();
  gen->add_option("--t2", g->p.t2, "Envelope: start of the exp(-c(t-t2)) decay, s")->capture_default_str();
  gen->add_option("--c", g->p.c, "Envelope: decay rate c, 1/s")->capture_default_str();
  gen->add_option("--seed", g->p.seed, "Random seed of the phases")->capture_default_str();
  gen->add_option("--iterations", g->p.iterations, "Spectral corrections per attempt, at most")
      ->capture_default_str();
  gen->add_option("-o,--output", g->out, "Output CSV (t_s,a_mps2,v_mps,d_m); also OUT.spectrum.csv and OUT.png")
      ->required();
  gen->add_flag("--no-plot", g->no_plot, "Do not make the PNG");
  gen->callback([g] {
    guarded([&] {
      seismic::ArtificialWaveParams p = g->p;
      p.spectrum.kind = seismic::parse_design_spectrum_kind(g->spectrum);
      p.spectrum.pga = g->pga * seismic::to_si_factor(seismic::parse_accel_units(g->pga_units));
      // The spectrum is shown over the controlled range, 2 dt to period_max.
      const auto periods = seismic::log_spaced(2.0 * p.dt, p.period_max, 200);
      const auto r = seismic::run_wave_generate(p, g->out, periods, g->no_plot ? "" : seismic::default_plot_script());
      fmt::print("wrote {} ({} samples, dt {} s, PGA {:.6g} m/s2)\n", r.files.csv, r.wave.wave.size(),
                 r.wave.wave.dt, r.wave.wave.pga());
      fmt::print("spectral misfit: {:.1f}% for T >= 0.1 s, {:.1f}% below ({} corrections, {} phase set(s))\n",
                 100 * r.wave.max_misfit, 100 * r.wave.max_short_misfit, r.wave.iterations, r.wave.attempts);
      auto fit = [](const seismic::SpectralFit& f) {
        return fmt::format("{:+.1f}% at {:.3g} s / {:+.1f}% at {:.3g} s", 100 * f.low, f.T_low, 100 * f.high, f.T_high);
      };
      fmt::print("fit 0.1-{:g} s, record alone:        {}\n", p.period_max, fit(r.wave.fit_record));
      fmt::print("fit 0.1-{:g} s, with free vibration: {}\n", p.period_max, fit(r.wave.fit_free_vibration));
      fmt::print("wrote {}\n", r.files.spectrum_csv);
      if (!r.files.png.empty()) fmt::print("wrote {}\n", r.files.png);
    });
  });

  auto s = std::make_shared<SpectrumOptions>();
  auto* spec = wave->add_subcommand("spectrum", "Response spectrum (Nigam-Jennings) of a CSV (t,a) or PEER .AT2 record");
  spec->add_option("file", s->input, "Record: CSV with columns t,a or PEER .AT2 (values in g)")->required();
  spec->add_option("--units", s->units, "Units of a CSV record: g or m/s2")->capture_default_str();
  spec->add_option("--damping", s->damping, "Damping ratio")->capture_default_str();
  spec->add_option("--tmin", s->tmin, "Shortest period, s")->capture_default_str();
  spec->add_option("--tmax", s->tmax, "Longest period, s")->capture_default_str();
  spec->add_option("--n", s->n, "Number of log-spaced periods")->capture_default_str();
  spec->add_option("-o,--output", s->out, "Output CSV (period_s,Sa_mps2,Sv_mps,Sd_m); also OUT.png")->required();
  spec->add_flag("--no-plot", s->no_plot, "Do not make the PNG");
  spec->callback([s] {
    guarded([&] {
      const auto units = seismic::parse_accel_units(s->units);
      const auto periods = seismic::log_spaced(s->tmin, s->tmax, s->n);
      const auto r = seismic::run_wave_spectrum(s->input, units, s->damping, s->out, periods,
                                                s->no_plot ? "" : seismic::default_plot_script());
      fmt::print("read {} ({} samples, dt {} s, PGA {:.6g} m/s2)\n", s->input, r.record.size(), r.record.dt,
                 r.record.pga());
      fmt::print("wrote {}\n", r.files.csv);
      if (!r.files.png.empty()) fmt::print("wrote {}\n", r.files.png);
    });
  });
}

}  // namespace dsdem::app
