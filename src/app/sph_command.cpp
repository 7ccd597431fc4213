#include "app/sph_command.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "io/pvd.hpp"
#include "io/vtu_writer.hpp"
#include "sph/dam_break.hpp"

namespace dsdem::app {

namespace {

struct DamBreakOptions {
  double resolution = 40.0;  // a / dp
  double alpha = 0.1;
  double h_over_dp = 1.5;
  double t_end = 0.0;  // s; 0: T = t sqrt(2 g / a) up to 3.2
  int frames = 0;      // VTU frames over the run (0: none)
  int threads = 1;
  std::string out = "dam_break_out";
};

// The water particles of one frame: positions, velocity_m_per_s, pressure_Pa, density.
void write_water_frame(io::PvdSeries& series, const sph::Fluid& fluid) {
  const auto& f = fluid.fluid();
  std::vector<Vec2> x(f.size()), v(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    x[i] = Vec2(f.x[i], f.y[i]);
    v[i] = Vec2(f.vx[i], f.vy[i]);
  }
  const auto path = series.frame_path(series.size());
  io::VtuOptions options;
  options.time_s = fluid.time();
  io::write_points_vtu(path, x,
                       {io::vector_field("velocity", "m/s", v), io::scalar_field("pressure", "Pa", f.p),
                        io::scalar_field("density", "kg/m3", f.rho), io::scalar_field("particle_id", "", f.id)},
                       options);
  series.add(fluid.time(), path);
}

void run_dam_break(const DamBreakOptions& o) {
  sph::DamBreakSetup s;
  s.dp = s.a / o.resolution;
  s.alpha = o.alpha;
  s.h_over_dp = o.h_over_dp;
  sph::Fluid fluid = sph::make_dam_break(s, o.threads > 1);
  const double T_of_t = std::sqrt(2.0 * s.g / s.a), tau_of_t = std::sqrt(s.g / s.a);
  const double t_end = o.t_end > 0.0 ? o.t_end : 3.2 / T_of_t;
  const double every = 0.02 / T_of_t;
  std::filesystem::create_directories(o.out);
  std::unique_ptr<io::PvdSeries> water;
  int frame_every = 0, sample = 0;
  if (o.frames > 0) {
    water = std::make_unique<io::PvdSeries>(std::filesystem::path(o.out) / "water.pvd");
    frame_every = std::max(1, static_cast<int>(std::lround(t_end / every)) / o.frames);
  }
  spdlog::info("dam break: a = {} m, a/dp = {}, {} water and {} wall particles, c0 = {:.1f} m/s", s.a, o.resolution,
               fluid.fluid().size(), fluid.boundary().size(), fluid.parameters().c0);
  const auto samples = sph::run_dam_break(fluid, s.dp, t_end, every, [&](const sph::Fluid& f) {
    if (water && sample % frame_every == 0) write_water_frame(*water, f);
    ++sample;
  });
  const auto csv = std::filesystem::path(o.out) / "dam_break.csv";
  std::ofstream out(csv);
  out << "# dsdem sph dam-break: a = " << s.a << " m, n^2 = " << s.n2 << ", a/dp = " << o.resolution
      << ", alpha = " << o.alpha << ", h/dp = " << o.h_over_dp << "\n";
  out << "t_s,T,front_m,Z,tau,height_m,H\n";
  for (const auto& x : samples)
    out << fmt::format("{:.6f},{:.4f},{:.6f},{:.4f},{:.4f},{:.6f},{:.4f}\n", x.t, x.t * T_of_t, x.front, x.front / s.a,
                       x.t * tau_of_t, x.height, x.height / (s.n2 * s.a));
  spdlog::info("dam break: {} steps, {} written", fluid.steps(), csv.string());
}

}  // namespace

void add_sph_commands(CLI::App& app) {
  auto* sph = app.add_subcommand("sph", "Weakly compressible SPH water on its own (verification cases)");
  sph->require_subcommand(1);
  auto o = std::make_shared<DamBreakOptions>();
  auto* db = sph->add_subcommand("dam-break", "Koshizuka & Oka / Martin & Moyce dam break: surge front and column height");
  db->add_option("--resolution", o->resolution, "Column width over particle spacing, a / dp")->capture_default_str();
  db->add_option("--alpha", o->alpha, "Artificial viscosity")->capture_default_str();
  db->add_option("--h-over-dp", o->h_over_dp, "Smoothing length over particle spacing")->capture_default_str();
  db->add_option("--t-end", o->t_end, "End time, s (default: T = t sqrt(2 g / a) = 3.2)");
  db->add_option("--frames", o->frames, "Water VTU frames over the run (0: none)")->capture_default_str();
  db->add_option("--threads", o->threads, "1 or 2 (the same results)")->capture_default_str();
  db->add_option("-o,--out", o->out, "Output directory")->capture_default_str();
  db->callback([o] {
    try {
      run_dam_break(*o);
    } catch (const std::exception& e) {
      spdlog::error("{}", e.what());
      throw CLI::RuntimeError(1);
    }
  });
}

}  // namespace dsdem::app
