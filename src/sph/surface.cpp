#include "sph/surface.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sph/kernels.hpp"

namespace dsdem::sph {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The fluid particles binned into columns `width` wide from x_min (a counting sort).
struct Columns {
  double x_min = 0.0, width = 1.0;
  std::vector<std::int32_t> start, order;

  Columns(const FluidParticles& f, double w) : width(w) {
    const std::size_t n = f.size();
    x_min = *std::min_element(f.x.begin(), f.x.end());
    const double x_max = *std::max_element(f.x.begin(), f.x.end());
    const auto nb = static_cast<std::size_t>((x_max - x_min) / width) + 1;
    start.assign(nb + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++start[column(f.x[i]) + 1];
    for (std::size_t b = 0; b < nb; ++b) start[b + 1] += start[b];
    order.resize(n);
    std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) order[static_cast<std::size_t>(fill[column(f.x[i])]++)] = static_cast<std::int32_t>(i);
  }
  std::size_t columns() const { return start.size() - 1; }
  std::size_t column(double x) const {
    const double c = std::floor((x - x_min) / width);
    return c <= 0.0 ? 0 : std::min(static_cast<std::size_t>(c), columns() - 1);
  }
  // The particles within `reach` of the vertical line at x, into near.
  void near_line(const FluidParticles& f, double x, double reach, std::vector<std::int32_t>& near) const {
    near.clear();
    if (x + reach < x_min || x - reach > x_min + width * static_cast<double>(columns())) return;
    for (std::size_t b = column(x - reach); b <= column(x + reach); ++b)
      for (std::int32_t k = start[b]; k < start[b + 1]; ++k) {
        const std::int32_t j = order[static_cast<std::size_t>(k)];
        if (std::abs(f.x[static_cast<std::size_t>(j)] - x) < reach) near.push_back(j);
      }
  }
};

// The highest y where c(x, y) = 1/2 over the particles `near` (within 2h of the line x), on
// water at least `thickness` deep below it (or reaching the column's bottom): spray, a few
// particles thrown above the surface, is stepped over.
double surface_at(const FluidParticles& f, std::span<const std::int32_t> near, double x, double h, double resolution,
                  double thickness) {
  if (near.empty()) return kNaN;
  double y_top = -std::numeric_limits<double>::infinity(), y_bottom = std::numeric_limits<double>::infinity();
  for (const std::int32_t j : near) {
    y_top = std::max(y_top, f.y[static_cast<std::size_t>(j)]);
    y_bottom = std::min(y_bottom, f.y[static_cast<std::size_t>(j)]);
  }
  // Down from where no particle reaches (c = 0) in steps of h/4, short enough not to step
  // over a sheet of water as thin as a particle, until c >= 1/2 over `thickness`; then
  // bisection between the last dry step and the first wet one.
  const double step = 0.25 * h, floor = y_bottom - 2.0 * h;
  double above = y_top + 2.0 * h;
  for (double y = above - step; y > floor; y -= step) {
    if (fluid_fraction(f, near, x, y, h) < 0.5) {
      above = y;
      continue;
    }
    const double enough = thickness - 1e-9 * h;
    double wet = y;
    bool bottom = false;
    while (y - wet < enough) {
      if (wet - step <= floor) {
        bottom = true;
        break;
      }
      if (fluid_fraction(f, near, x, wet - step, h) < 0.5) break;
      wet -= step;
    }
    const bool deep = bottom || y - wet >= enough;
    if (!deep) {  // spray: go on below it
      above = wet - step;
      y = above;
      continue;
    }
    double below = y;
    while (above - below > resolution) {
      const double mid = 0.5 * (above + below);
      (fluid_fraction(f, near, x, mid, h) >= 0.5 ? below : above) = mid;
    }
    return 0.5 * (above + below);
  }
  return kNaN;
}

}  // namespace

double fluid_fraction(const FluidParticles& f, std::span<const std::int32_t> near, double x, double y, double h) {
  // `near` spans the whole depth; the particles clearly beyond the support in height add
  // exactly zero, and are passed over without the kernel's square root.
  const double beyond2 = 4.0001 * h * h;
  double c = 0.0;
  for (const std::int32_t j : near) {
    const auto k = static_cast<std::size_t>(j);
    const double dx = x - f.x[k], dy = y - f.y[k];
    if (dy * dy > beyond2) continue;
    c += f.mass / f.rho[k] * wendland(dx * dx + dy * dy, h);
  }
  return c;
}

std::vector<double> free_surface_elevations(const FluidParticles& f, std::span<const double> xs, double h,
                                            double resolution, double thickness) {
  std::vector<double> out(xs.size(), kNaN);
  if (f.size() == 0) return out;
  const Columns columns(f, 2.0 * h);
  std::vector<std::int32_t> near;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    columns.near_line(f, xs[k], 2.0 * h, near);
    out[k] = surface_at(f, near, xs[k], h, resolution, thickness);
  }
  return out;
}

SurfacePeak highest_surface(const FluidParticles& f, double x0, double x1, double spacing, double h,
                            double resolution) {
  std::vector<double> xs;
  for (double x = x0; x <= x1 + 1e-9 * spacing; x += spacing) xs.push_back(x);
  const std::vector<double> ys = free_surface_elevations(f, xs, h, resolution);
  SurfacePeak peak{x0, kNaN};
  for (std::size_t k = 0; k < xs.size(); ++k)
    if (!std::isnan(ys[k]) && (std::isnan(peak.y) || ys[k] > peak.y)) peak = {xs[k], ys[k]};
  return peak;
}

double runup_on_polyline(const FluidParticles& f, std::span<const Vec2> polyline, double reach, double dp) {
  if (polyline.size() < 2) return kNaN;
  Vec2 lo = polyline[0], hi = polyline[0];
  for (const Vec2& p : polyline) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo.array() -= reach;
  hi.array() += reach;
  auto in_box = [&](const Vec2& p) { return p.x() >= lo.x() && p.y() >= lo.y() && p.x() <= hi.x() && p.y() <= hi.y(); };
  // The curve in bins dp/2 long by arc length; each particle near it wets the bins within dp
  // of its foot (one missing particle does not break the film) and sets its own bin's top.
  std::vector<double> arc(polyline.size(), 0.0);
  for (std::size_t s = 1; s < polyline.size(); ++s) arc[s] = arc[s - 1] + (polyline[s] - polyline[s - 1]).norm();
  const double bin = 0.5 * dp;
  const auto nb = static_cast<std::size_t>(arc.back() / bin) + 1;
  std::vector<char> wet(nb, 0);
  std::vector<double> top(nb, kNaN);
  auto bin_of = [&](double s) { return std::min(nb - 1, static_cast<std::size_t>(std::max(0.0, s) / bin)); };
  for (std::size_t j = 0; j < f.size(); ++j) {
    const Vec2 p(f.x[j], f.y[j]);
    if (!in_box(p)) continue;
    double best = reach, foot = -1.0;
    for (std::size_t s = 0; s + 1 < polyline.size(); ++s) {
      const Vec2 a = polyline[s], ab = polyline[s + 1] - a;
      const double l2 = ab.squaredNorm();
      const double u = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
      const double d = (p - (a + u * ab)).norm();
      if (d <= best) best = d, foot = arc[s] + u * std::sqrt(l2);
    }
    if (foot < 0.0) continue;
    for (std::size_t b = bin_of(foot - dp); b <= bin_of(foot + dp); ++b) wet[b] = 1;
    double& t = top[bin_of(foot)];
    if (!(p.y() <= t)) t = p.y();
  }
  // The water's edge joined to the body of water: the unbroken wet stretch through the wet bin
  // lowest on the curve. Spray landing higher up, apart from the tongue, is left out.
  auto elevation = [&](std::size_t b) {
    const double s = std::min((static_cast<double>(b) + 0.5) * bin, arc.back());
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin());
    const std::size_t i = std::clamp<std::size_t>(k, 1, polyline.size() - 1) - 1;
    const double len = arc[i + 1] - arc[i];
    return polyline[i].y() + (len > 0.0 ? (s - arc[i]) / len : 0.0) * (polyline[i + 1].y() - polyline[i].y());
  };
  std::size_t low = nb;
  for (std::size_t b = 0; b < nb; ++b)
    if (wet[b] && (low == nb || elevation(b) < elevation(low))) low = b;
  if (low == nb) return kNaN;
  std::size_t first = low, last = low;
  while (first > 0 && wet[first - 1]) --first;
  while (last + 1 < nb && wet[last + 1]) ++last;
  double z = kNaN;
  for (std::size_t b = first; b <= last; ++b)
    if (!std::isnan(top[b]) && !(top[b] <= z)) z = top[b];
  return std::isnan(z) ? z : z + 0.5 * dp;
}

double volume_beyond(const FluidParticles& f, double x_line, int direction, double y_min) {
  double area = 0.0;
  for (std::size_t j = 0; j < f.size(); ++j)
    if ((f.x[j] - x_line) * direction > 0.0 && f.y[j] > y_min) area += f.mass / f.rho[j];
  return area;
}

std::vector<TurningPoint> turning_points(std::span<const double> t, std::span<const double> eta, double band) {
  std::vector<TurningPoint> out;
  // Hysteresis: a crest is confirmed once the series falls `band` below it, a trough once it
  // rises `band` above it. Until the series first moves `band` away from its start, its
  // direction is unknown.
  enum class Trend { unknown, rising, falling } trend = Trend::unknown;
  double lo = INFINITY, hi = -INFINITY, extreme = 0.0, at = 0.0;
  for (std::size_t k = 0; k < std::min(t.size(), eta.size()); ++k) {
    const double e = eta[k];
    if (std::isnan(e)) continue;
    switch (trend) {
      case Trend::unknown:
        lo = std::min(lo, e), hi = std::max(hi, e);
        if (e > lo + band) trend = Trend::rising, extreme = e, at = t[k];
        else if (e < hi - band) trend = Trend::falling, extreme = e, at = t[k];
        break;
      case Trend::rising:
        if (e > extreme) {
          extreme = e, at = t[k];
        } else if (e < extreme - band) {
          out.push_back({at, extreme, true});
          trend = Trend::falling, extreme = e, at = t[k];
        }
        break;
      case Trend::falling:
        if (e < extreme) {
          extreme = e, at = t[k];
        } else if (e > extreme + band) {
          out.push_back({at, extreme, false});
          trend = Trend::rising, extreme = e, at = t[k];
        }
        break;
    }
  }
  return out;
}

std::vector<double> crest_times(std::span<const double> t, std::span<const double> eta, double band) {
  std::vector<double> out;
  for (const TurningPoint& p : turning_points(t, eta, band))
    if (p.crest) out.push_back(p.t);
  return out;
}

PrimaryWave primary_wave(std::span<const double> t, std::span<const double> eta, double t_from, double band) {
  PrimaryWave w;
  const std::vector<TurningPoint> points = turning_points(t, eta, band);
  auto crest = std::find_if(points.begin(), points.end(), [&](const TurningPoint& p) { return p.crest && p.t >= t_from; });
  if (crest == points.end()) return w;
  w.crest = crest->eta, w.crest_t = crest->t;
  // The trough: the lowest surface after the crest until the series turns up by `band` (the
  // next turning point), or until it crosses the still level upward, from below -band/4 to
  // above +band/4 (a zero up-crossing ends the wave, so a shallow trough is one too; the
  // quarter band keeps ripples from crossing).
  const std::size_t n = std::min(t.size(), eta.size());
  std::size_t k = 0;
  while (k < n && t[k] < w.crest_t) ++k;
  double low = INFINITY, low_t = kNaN;
  for (; k < n; ++k) {
    const double e = eta[k];
    if (std::isnan(e)) continue;
    if (e < low) {
      low = e, low_t = t[k];
    } else if (e > low + band || (low < -0.25 * band && e > 0.25 * band)) {
      w.trough = low, w.trough_t = low_t;
      break;
    }
  }
  return w;
}

double mean_crest_period(std::span<const double> t, std::span<const double> eta, double band) {
  const std::vector<double> crests = crest_times(t, eta, band);
  if (crests.size() < 2) return kNaN;
  return (crests.back() - crests.front()) / static_cast<double>(crests.size() - 1);
}

}  // namespace dsdem::sph
