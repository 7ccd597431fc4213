#include "water/hydrostatic.hpp"

#include <algorithm>
#include <stdexcept>

namespace dsdem::water {

PiezometricLine::PiezometricLine(std::vector<Vec2> points) : points_(std::move(points)) {
  if (points_.empty()) throw std::invalid_argument("a piezometric line needs at least one point");
  for (std::size_t k = 1; k < points_.size(); ++k)
    if (!(points_[k].x() > points_[k - 1].x()))
      throw std::invalid_argument("the piezometric line's x must increase from point to point");
  highest_ = points_.front().y();
  for (const Vec2& p : points_) highest_ = std::max(highest_, p.y());
}

double PiezometricLine::elevation(double x) const {
  if (x <= points_.front().x()) return points_.front().y();
  if (x >= points_.back().x()) return points_.back().y();
  const auto hi = std::upper_bound(points_.begin(), points_.end(), x, [](double v, const Vec2& p) { return v < p.x(); });
  const Vec2& p1 = *hi;
  const Vec2& p0 = *(hi - 1);
  const double w = (x - p0.x()) / (p1.x() - p0.x());
  return p0.y() + w * (p1.y() - p0.y());
}

namespace {

// Adds the integrals of max(q, 0) (1 - s) and max(q, 0) s over [s0, s1], q linear from q0
// to q1 on it: cut where q = 0, then Simpson's rule (exact for the quadratic integrand).
void add_piece(double s0, double s1, double q0, double q1, double& i0, double& i1) {
  if (q0 <= 0.0 && q1 <= 0.0) return;
  if (q0 < 0.0 || q1 < 0.0) {
    const double sz = s0 + (s1 - s0) * q0 / (q0 - q1);
    if (q0 < 0.0) s0 = sz, q0 = 0.0;
    else s1 = sz, q1 = 0.0;
  }
  const double h = s1 - s0;
  if (!(h > 0.0)) return;
  const double sm = 0.5 * (s0 + s1);
  const double qm = 0.5 * (q0 + q1);
  i0 += h / 6.0 * (q0 * (1.0 - s0) + 4.0 * qm * (1.0 - sm) + q1 * (1.0 - s1));
  i1 += h / 6.0 * (q0 * s0 + 4.0 * qm * sm + q1 * s1);
}

// The traction -p n of the integrals i0 = int p N_a ds, i1 = int p N_b ds (s in [0, 1]):
// the outward normal of a solid on the left of a -> b, times the length, is (dy, -dx).
std::array<Vec2, 2> traction(Vec2 a, Vec2 b, double i0, double i1) {
  const Vec2 d = b - a;
  const Vec2 ln(d.y(), -d.x());
  return {Vec2(-i0 * ln), Vec2(-i1 * ln)};
}

}  // namespace

std::array<Vec2, 2> edge_forces(const PiezometricLine& line, double unit_weight, Vec2 a, Vec2 b) {
  auto q = [&](double s) {
    const Vec2 x = a + s * (b - a);
    return unit_weight * (line.elevation(x.x()) - x.y());
  };
  double i0 = 0.0, i1 = 0.0;
  const auto pts = line.points();
  const double dx = b.x() - a.x();
  double s_prev = 0.0, q_prev = q(0.0);
  if (dx != 0.0) {
    // The line's vertices strictly between a.x and b.x, in the order the edge meets them.
    const double lo = std::min(a.x(), b.x()), hi = std::max(a.x(), b.x());
    auto first = std::upper_bound(pts.begin(), pts.end(), lo, [](double v, const Vec2& p) { return v < p.x(); });
    auto last = std::lower_bound(pts.begin(), pts.end(), hi, [](const Vec2& p, double v) { return p.x() < v; });
    const std::ptrdiff_t n = last - first;
    for (std::ptrdiff_t k = 0; k < n; ++k) {
      const Vec2& v = dx > 0.0 ? first[k] : first[n - 1 - k];
      const double s = (v.x() - a.x()) / dx;
      const double qs = unit_weight * (v.y() - (a.y() + s * (b.y() - a.y())));
      add_piece(s_prev, s, q_prev, qs, i0, i1);
      s_prev = s, q_prev = qs;
    }
  }
  add_piece(s_prev, 1.0, q_prev, q(1.0), i0, i1);
  return traction(a, b, i0, i1);
}

std::array<Vec2, 2> edge_forces_to_level(double level, double unit_weight, Vec2 a, Vec2 b) {
  double i0 = 0.0, i1 = 0.0;
  add_piece(0.0, 1.0, unit_weight * (level - a.y()), unit_weight * (level - b.y()), i0, i1);
  return traction(a, b, i0, i1);
}

std::array<Vec2, 3> element_pore_forces(const std::array<Vec2, 3>& x, double p) {
  std::array<Vec2, 3> f;
  for (int k = 0; k < 3; ++k) {
    const Vec2& b = x[(k + 1) % 3];
    const Vec2& c = x[(k + 2) % 3];
    f[k] = 0.5 * p * Vec2(b.y() - c.y(), c.x() - b.x());  // p A grad N_k
  }
  return f;
}

std::array<Vec2, 3> triangle_forces(const TriangleWater& in, const PiezometricLine& line, double unit_weight) {
  std::array<Vec2, 3> f{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  const double lowest = std::min({in.x[0].y(), in.x[1].y(), in.x[2].y()});
  if (in.pore_pressure && lowest < line.highest()) {
    const Vec2 centroid = (in.x[0] + in.x[1] + in.x[2]) / 3.0;
    const double p = pressure(line, unit_weight, centroid);
    if (p > 0.0) f = element_pore_forces(in.x, p);
  }
  for (int k = 0; k < 3; ++k) {
    const Vec2& a = in.x[k];
    const Vec2& b = in.x[(k + 1) % 3];
    std::array<Vec2, 2> fe;
    if (in.edge[k] == EdgeWater::line) {
      if (std::min(a.y(), b.y()) >= line.highest()) continue;
      fe = edge_forces(line, unit_weight, a, b);
    } else if (in.edge[k] == EdgeWater::level) {
      if (std::min(a.y(), b.y()) >= in.level[k]) continue;
      fe = edge_forces_to_level(in.level[k], in.level_unit_weight, a, b);
    } else {
      continue;
    }
    f[k] += fe[0];
    f[(k + 1) % 3] += fe[1];
  }
  return f;
}

}  // namespace dsdem::water
