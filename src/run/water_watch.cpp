#include "run/water_watch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "run/bounds.hpp"
#include "run/slide_impact.hpp"
#include "sph/kernels.hpp"
#include "sph/surface.hpp"

namespace dsdem::run {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void raise(WaterWatch::Peak& p, double value, double x, double t) {
  if (std::isnan(value) || (p.seen && value <= p.value)) return;
  p = {value, x, t, true};
}

// The water's pressure at a point, a Shepard mean of the particles' pressures within the
// kernel's support (a wall truncates the support; the mean renormalises it), and the fluid
// fraction there. O(N) scan over the particles listed in `near`.
std::pair<double, double> pressure_at(const sph::FluidParticles& f, std::span<const std::int32_t> near, const Vec2& p,
                                      double h) {
  double c = 0.0, pc = 0.0;
  for (const std::int32_t j : near) {
    const auto k = static_cast<std::size_t>(j);
    const double dx = p.x() - f.x[k], dy = p.y() - f.y[k];
    const double w = f.mass / f.rho[k] * sph::wendland(dx * dx + dy * dy, h);
    c += w;
    pc += w * f.p[k];
  }
  return {c > 0.0 ? pc / c : 0.0, c};
}

// Particles within `reach` of a polyline's bounding box (one scan).
void particles_near(const sph::FluidParticles& f, std::span<const Vec2> poly, double reach, std::vector<std::int32_t>& out) {
  const auto [x0, y0, x1, y1] = bounds_of(poly);
  out.clear();
  for (std::size_t i = 0; i < f.size(); ++i)
    if (f.x[i] >= x0 - reach && f.x[i] <= x1 + reach && f.y[i] >= y0 - reach && f.y[i] <= y1 + reach)
      out.push_back(static_cast<std::int32_t>(i));
}

}  // namespace

WaveColumns wave_columns(std::span<const double> bottom, double x_min, double dx, double level, double min_depth) {
  WaveColumns c;
  const std::size_t n = bottom.size();
  const auto dry = [&](std::size_t b) { return !std::isfinite(bottom[b]); };
  for (std::size_t b = 0; b < n; ++b) {
    if (!(level - bottom[b] >= min_depth)) continue;
    c.x.push_back(x_min + (static_cast<double>(b) + 0.5) * dx);
    c.at_wall.push_back(b == 0 || b + 1 == n || dry(b - 1) || dry(b + 1));
  }
  return c;
}

Crest crest_beyond(std::span<const double> xs, std::span<const double> surface, double level, double front,
                   int direction) {
  Crest c{kNaN, kNaN};
  for (std::size_t i = 0; i < std::min(xs.size(), surface.size()); ++i) {
    if (std::isnan(surface[i]) || (direction != 0 && !std::isnan(front) && (xs[i] - front) * direction <= 0.0)) continue;
    if (std::isnan(c.amplitude) || surface[i] - level > c.amplitude) c = {surface[i] - level, xs[i]};
  }
  return c;
}

// The particles binned in cells, each triangle testing those under its bounding box: O(N + T).
long particles_in_solid(const sph::FluidParticles& f, const Model& m, double cell) {
  const std::size_t n = f.size();
  if (n == 0) return 0;
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  for (std::size_t i = 0; i < n; ++i)
    x0 = std::min(x0, f.x[i]), y0 = std::min(y0, f.y[i]), x1 = std::max(x1, f.x[i]), y1 = std::max(y1, f.y[i]);
  // No more cells than about four per particle, however far stray particles fly.
  cell = std::max(cell, std::sqrt((x1 - x0) * (y1 - y0) / (4.0 * static_cast<double>(n))));
  cell = std::max({cell, (x1 - x0) / 65536.0, (y1 - y0) / 65536.0});
  const int nx = static_cast<int>((x1 - x0) / cell) + 1, ny = static_cast<int>((y1 - y0) / cell) + 1;
  auto column = [&](double x) { return std::clamp(static_cast<int>(std::floor((x - x0) / cell)), 0, nx - 1); };
  auto row = [&](double y) { return std::clamp(static_cast<int>(std::floor((y - y0) / cell)), 0, ny - 1); };
  auto bin = [&](std::size_t i) { return static_cast<std::size_t>(row(f.y[i])) * nx + column(f.x[i]); };
  std::vector<std::int32_t> start(static_cast<std::size_t>(nx) * ny + 1, 0), order(n);
  for (std::size_t i = 0; i < n; ++i) ++start[bin(i) + 1];
  for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) order[static_cast<std::size_t>(fill[bin(i)]++)] = static_cast<std::int32_t>(i);
  std::vector<char> inside(n, 0);
  auto cross = [](const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
  for (const auto& t : m.triangles.conn) {
    const Vec2 a = m.nodes.x(t[0]), b = m.nodes.x(t[1]), c = m.nodes.x(t[2]);
    const double lo_x = std::min({a.x(), b.x(), c.x()}), hi_x = std::max({a.x(), b.x(), c.x()});
    const double lo_y = std::min({a.y(), b.y(), c.y()}), hi_y = std::max({a.y(), b.y(), c.y()});
    if (hi_x < x0 || lo_x > x1 || hi_y < y0 || lo_y > y1) continue;
    for (int r = row(lo_y); r <= row(hi_y); ++r)
      for (int q = column(lo_x); q <= column(hi_x); ++q) {
        const auto cell_index = static_cast<std::size_t>(r) * nx + q;
        for (std::int32_t k = start[cell_index]; k < start[cell_index + 1]; ++k) {
          const auto j = static_cast<std::size_t>(order[static_cast<std::size_t>(k)]);
          const Vec2 p(f.x[j], f.y[j]);
          const double s1 = cross(b - a, p - a), s2 = cross(c - b, p - b), s3 = cross(a - c, p - c);
          if ((s1 > 0.0 && s2 > 0.0 && s3 > 0.0) || (s1 < 0.0 && s2 < 0.0 && s3 < 0.0)) inside[j] = 1;
        }
      }
  }
  return static_cast<long>(std::count(inside.begin(), inside.end(), 1));
}

double mean_surface(std::span<const double> surface) {
  double sum = 0.0;
  int n = 0;
  for (const double y : surface)
    if (!std::isnan(y)) sum += y, ++n;
  return n > 0 ? sum / n : kNaN;
}

WaterWatch::WaterWatch(const io::Scenario& sc, const MovingWaterLayout& layout, const Model& model, int direction)
    : spec_(sc.reservoir.sph),
      level_(sc.reservoir.level),
      dp_(layout.parameters.dp),
      h_(layout.parameters.h()),
      direction_(direction),
      top_(layout.coupled_top) {
  box_min_ = Vec2::Constant(std::numeric_limits<double>::infinity());
  box_max_ = -box_min_;
  for (const Vec2& X : model.nodes.X) box_min_ = box_min_.cwiseMin(X), box_max_ = box_max_.cwiseMax(X);
  box_min_ -= Vec2::Constant(2.0 * h_);
  box_max_ += Vec2::Constant(2.0 * h_);
  for (const auto& g : spec_.gauges) gauge_x_.push_back(g.x);
  gauge_t_.resize(gauge_x_.size());
  gauge_eta_.resize(gauge_x_.size());
  gauge_overrun_t_.assign(gauge_x_.size(), kNaN);
  // The wave is sought where the still water is at least a quarter of the deepest (the
  // run-up on the banks is measured apart), and beyond the slide (crest_beyond).
  const double dx = dp_;
  const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil((layout.x_max - layout.x_min) / dx)));
  std::vector<double> bottom(n, std::numeric_limits<double>::infinity());
  const auto& f = layout.fluid;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const auto b = std::min(n - 1, static_cast<std::size_t>(std::max(0.0, (f.x[i] - layout.x_min) / dx)));
    bottom[b] = std::min(bottom[b], f.y[i] - 0.5 * dp_);
  }
  WaveColumns columns = wave_columns(bottom, layout.x_min, dx, level_, 0.25 * layout.depth);
  wave_x_ = std::move(columns.x);
  wave_wall_ = std::move(columns.at_wall);
  for (const auto& r : spec_.runup) runup_.push_back({r.name, {}, 0.0, {}});
  for (const auto& c : spec_.crests) crests_.push_back({c.name, {}, 0.0, {}});
  for (const auto& c : spec_.pressure) forces_.push_back({c.name, {}, 0.0, {}});
  crest_start_.assign(crests_.size(), kNaN);
}

bool WaterWatch::against_wall(double x) const {
  for (std::size_t k = 0; k < wave_x_.size(); ++k)
    if (std::abs(wave_x_[k] - x) <= 0.5 * dp_) return wave_wall_[k];
  return false;
}

std::vector<io::HistoryColumn> WaterWatch::columns(const io::SphSpec& spec, const std::string& energy_unit,
                                                   const std::string& force_unit) {
  std::vector<io::HistoryColumn> c;
  for (const auto& g : spec.gauges) c.push_back({g.name + "_eta", "m"});
  c.push_back({"wave_amplitude", "m"});
  for (const auto& r : spec.runup) c.push_back({r.name + "_runup", "m"});
  for (const auto& r : spec.crests) c.push_back({r.name + "_overtopped", "m2_per_m"});
  for (const auto& r : spec.pressure) {
    c.push_back({r.name + "_force_x", force_unit});
    c.push_back({r.name + "_force_y", force_unit});
    c.push_back({r.name + "_peak_pressure", "Pa"});
  }
  c.push_back({"water_energy_gain", energy_unit});
  c.push_back({"water_boundary_work", energy_unit});
  return c;
}

void WaterWatch::observe(const sph::Fluid& fluid, double t, std::span<double> row, double slide_front,
                         bool slide_entered, const Model& model) {
  const sph::FluidParticles& f = fluid.fluid();
  const double resolution = dp_ / 20.0;
  std::size_t k = 0;
  last_t_ = t;
  // A gauge reads the water body's surface, not spray thrown above it.
  const auto eta = sph::free_surface_elevations(f, gauge_x_, h_, resolution, 2.0 * dp_);
  const auto rock = moved_rock_tops(model, gauge_x_, dp_);
  for (std::size_t g = 0; g < eta.size(); ++g) {
    row[k++] = eta[g] - level_;
    gauge_t_[g].push_back(t);
    gauge_eta_[g].push_back(eta[g] - level_);
    const bool debris = std::isfinite(rock[g]) && (std::isnan(eta[g]) || rock[g] >= eta[g] - 2.0 * dp_);
    if (std::isnan(gauge_overrun_t_[g]) && debris) gauge_overrun_t_[g] = t;
  }
  const auto surface = sph::free_surface_elevations(f, wave_x_, h_, resolution, 2.0 * dp_);
  if (!slide_entered && !std::isnan(mean_surface(surface))) still_ = mean_surface(surface);
  const Crest crest = crest_beyond(wave_x_, surface, still_level(), slide_front, direction_);
  row[k++] = crest.amplitude;
  raise(amplitude_, crest.amplitude, crest.x, t);
  observe_curves(fluid, t, row, k, slide_entered);
  long out = 0, above = 0;
  std::size_t fastest = 0;
  speeds_.resize(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    out += f.x[i] < box_min_.x() || f.x[i] > box_max_.x() || f.y[i] < box_min_.y() || f.y[i] > box_max_.y();
    above += f.y[i] > top_;
    speeds_[i] = std::hypot(f.vx[i], f.vy[i]);
    if (speeds_[i] > speeds_[fastest]) fastest = i;
  }
  if (!speeds_.empty()) {
    raise(speed_, speeds_[fastest], f.x[fastest], t);
    const auto p99 = speeds_.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(speeds_.size() - 1));
    std::nth_element(speeds_.begin(), p99, speeds_.end());
    raise(flow_speed_, *p99, 0.0, t);
  }
  escaped_ = std::max(escaped_, out);
  above_top_ = std::max(above_top_, above);
  inside_ = std::max(inside_, particles_in_solid(f, model, 2.0 * dp_));
  // The particles taken out of the water keep their energy in its books.
  const double total = fluid.energy().total() + fluid.excluded_energy();
  if (!energy_start_) energy_start_ = total;
  row[k++] = total - *energy_start_;
  raise(energy_gain_, total - *energy_start_, 0.0, t);
  row[k++] = fluid.boundary_work();
}

double WaterWatch::Named::at_rest() const {
  std::vector<double> v;
  for (const double x : before_entry) {
    if (std::isinf(x)) return kNaN;  // restored from a checkpoint that did not keep them
    if (!std::isnan(x)) v.push_back(x);
  }
  if (v.empty()) return kNaN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

void WaterWatch::observe_curves(const sph::Fluid& fluid, double t, std::span<double> row, std::size_t& k,
                                bool slide_entered) {
  const sph::FluidParticles& f = fluid.fluid();
  for (std::size_t r = 0; r < runup_.size(); ++r) {
    const double z = sph::runup_on_polyline(f, spec_.runup[r].polyline, dp_, dp_);
    if (!slide_entered) runup_[r].before_entry.push_back(z);
    row[k++] = z;
    raise(runup_[r].peak, z, 0.0, t);
  }
  for (std::size_t c = 0; c < crests_.size(); ++c) {
    const auto& s = spec_.crests[c];
    const double v = sph::volume_beyond(f, s.at.x(), s.direction, s.at.y());
    if (std::isnan(crest_start_[c])) crest_start_[c] = v;
    row[k++] = v - crest_start_[c];
    raise(crests_[c].peak, v - crest_start_[c], s.at.x(), t);
  }
  std::vector<std::int32_t> near;
  for (std::size_t c = 0; c < forces_.size(); ++c) {
    // The water on the curve's right (walked a -> b): the force on it p (-n) ds, n = (t_y,
    // -t_x) into the water, sampled every dp / 2 (docs/theory.md §12).
    const auto& poly = spec_.pressure[c].polyline;
    particles_near(f, poly, 2.0 * h_, near);
    Vec2 force = Vec2::Zero();
    double peak = 0.0;
    for (std::size_t i = 0; i + 1 < poly.size(); ++i) {
      const Vec2 a = poly[i], b = poly[i + 1];
      const double len = (b - a).norm();
      if (!(len > 0.0)) continue;
      const Vec2 tan = (b - a) / len, n(tan.y(), -tan.x());
      const int samples = std::max(1, static_cast<int>(std::ceil(len / (0.5 * dp_))));
      for (int s = 0; s < samples; ++s) {
        const auto [p, frac] = pressure_at(f, near, a + (s + 0.5) / samples * (b - a), h_);
        if (frac < 0.1) continue;  // dry
        force -= p * (len / samples) * n;
        peak = std::max(peak, p);
      }
    }
    row[k++] = force.x();
    row[k++] = force.y();
    row[k++] = peak;
    if (!slide_entered) forces_[c].before_entry.push_back(force.norm());
    raise(forces_[c].peak, force.norm(), 0.0, t);
    forces_[c].pressure = std::max(forces_[c].pressure, peak);
  }
}

std::vector<double> WaterWatch::state() const {
  std::vector<double> s;
  auto peak = [&](const Peak& p) {
    for (const double v : {p.value, p.x, p.t, p.seen ? 1.0 : 0.0}) s.push_back(v);
  };
  peak(amplitude_);
  peak(energy_gain_);
  peak(speed_);
  peak(flow_speed_);
  s.push_back(still_);
  s.push_back(energy_start_ ? *energy_start_ : kNaN);
  s.push_back(static_cast<double>(escaped_));
  s.push_back(static_cast<double>(above_top_));
  s.push_back(static_cast<double>(inside_));
  for (const auto* list : {&runup_, &crests_, &forces_})
    for (const auto& n : *list) {
      peak(n.peak);
      s.push_back(n.pressure);
    }
  s.insert(s.end(), crest_start_.begin(), crest_start_.end());
  for (std::size_t g = 0; g < gauge_t_.size(); ++g) {
    s.push_back(static_cast<double>(gauge_t_[g].size()));
    s.insert(s.end(), gauge_t_[g].begin(), gauge_t_[g].end());
    s.insert(s.end(), gauge_eta_[g].begin(), gauge_eta_[g].end());
  }
  s.push_back(last_t_);
  s.insert(s.end(), gauge_overrun_t_.begin(), gauge_overrun_t_.end());
  for (const auto* list : {&runup_, &forces_})
    for (const auto& n : *list) {
      s.push_back(static_cast<double>(n.before_entry.size()));
      s.insert(s.end(), n.before_entry.begin(), n.before_entry.end());
    }
  return s;
}

void WaterWatch::restore(std::span<const double> s) {
  std::size_t k = 0;
  auto take = [&]() {
    if (k >= s.size()) throw std::runtime_error("its water measurements do not fit this scenario's water");
    return s[k++];
  };
  auto peak = [&](Peak& p) {
    p.value = take(), p.x = take(), p.t = take();
    p.seen = take() != 0.0;
  };
  peak(amplitude_);
  peak(energy_gain_);
  peak(speed_);
  peak(flow_speed_);
  still_ = take();
  const double e0 = take();
  energy_start_ = std::isnan(e0) ? std::nullopt : std::optional<double>(e0);
  escaped_ = static_cast<long>(take());
  above_top_ = static_cast<long>(take());
  inside_ = static_cast<long>(take());
  for (auto* list : {&runup_, &crests_, &forces_})
    for (auto& n : *list) {
      peak(n.peak);
      n.pressure = take();
    }
  for (double& c : crest_start_) c = take();
  for (std::size_t g = 0; g < gauge_t_.size(); ++g) {
    const auto n = static_cast<std::size_t>(take());
    gauge_t_[g].resize(n);
    gauge_eta_[g].resize(n);
    for (double& v : gauge_t_[g]) v = take();
    for (double& v : gauge_eta_[g]) v = take();
  }
  // A checkpoint written before these were kept leaves them unknown: no rest (null in the
  // summary; later rows before the entry would not be the same median), no overrun.
  if (k < s.size()) {
    last_t_ = take();
    for (double& v : gauge_overrun_t_) v = take();
    for (auto* list : {&runup_, &forces_})
      for (auto& n : *list) {
        n.before_entry.resize(static_cast<std::size_t>(take()));
        for (double& v : n.before_entry) v = take();
      }
  } else {
    for (auto* list : {&runup_, &forces_})
      for (auto& n : *list) n.before_entry.assign(1, std::numeric_limits<double>::infinity());
  }
  if (k != s.size()) throw std::runtime_error("its water measurements do not fit this scenario's water");
}

std::span<const double> WaterWatch::before_overrun(std::size_t g, const std::vector<double>& series) const {
  const auto& t = gauge_t_[g];
  const auto n = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), gauge_overrun_t_[g]) - t.begin());
  return {series.data(), std::isnan(gauge_overrun_t_[g]) ? series.size() : std::min(n, series.size())};
}

std::vector<std::pair<std::string, double>> WaterWatch::gauge_periods() const {
  std::vector<std::pair<std::string, double>> out;
  for (std::size_t g = 0; g < gauge_x_.size(); ++g)
    out.emplace_back(spec_.gauges[g].name, sph::mean_crest_period(before_overrun(g, gauge_t_[g]),
                                                                  before_overrun(g, gauge_eta_[g]), dp_));
  return out;
}

std::vector<WaterWatch::GaugeWave> WaterWatch::primary_waves(double t_from) const {
  std::vector<GaugeWave> out;
  const double offset = still_level() - level_;  // the gauges read above reservoir.level
  std::vector<double> eta;
  for (std::size_t g = 0; g < gauge_x_.size(); ++g) {
    eta.assign(gauge_eta_[g].begin(), gauge_eta_[g].end());
    for (double& e : eta) e -= offset;
    out.push_back({spec_.gauges[g].name, gauge_x_[g],
                   sph::primary_wave(before_overrun(g, gauge_t_[g]), before_overrun(g, eta), t_from, dp_),
                   gauge_overrun_t_[g]});
  }
  return out;
}

}  // namespace dsdem::run
