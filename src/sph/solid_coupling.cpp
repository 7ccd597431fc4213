#include "sph/solid_coupling.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <unordered_map>

#include "sph/setup.hpp"

namespace dsdem::sph {

namespace {

// The edges near each cell of a grid over the edges (set-up only): edge e is listed in every
// cell its bounding box, grown by `reach`, overlaps.
struct EdgeGrid {
  double x0 = 0.0, y0 = 0.0, cell = 1.0;
  int nx = 1, ny = 1;
  std::vector<std::vector<std::size_t>> cells;

  EdgeGrid(std::span<const SolidEdge> edges, std::span<const Vec2> x, double reach, double cell_size) : cell(cell_size) {
    double x1 = -INFINITY, y1 = -INFINITY;
    x0 = y0 = INFINITY;
    for (const auto& e : edges)
      for (Index n : {e.a, e.b}) {
        x0 = std::min(x0, x[n].x() - reach);
        y0 = std::min(y0, x[n].y() - reach);
        x1 = std::max(x1, x[n].x() + reach);
        y1 = std::max(y1, x[n].y() + reach);
      }
    if (edges.empty()) x0 = y0 = x1 = y1 = 0.0;
    nx = std::max(1, static_cast<int>(std::ceil((x1 - x0) / cell)));
    ny = std::max(1, static_cast<int>(std::ceil((y1 - y0) / cell)));
    cells.resize(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
    for (std::size_t k = 0; k < edges.size(); ++k) {
      const Vec2 &a = x[edges[k].a], &b = x[edges[k].b];
      const int i0 = ix(std::min(a.x(), b.x()) - reach), i1 = ix(std::max(a.x(), b.x()) + reach);
      const int j0 = iy(std::min(a.y(), b.y()) - reach), j1 = iy(std::max(a.y(), b.y()) + reach);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) cells[static_cast<std::size_t>(j) * nx + i].push_back(k);
    }
  }
  int ix(double x) const { return std::clamp(static_cast<int>(std::floor((x - x0) / cell)), 0, nx - 1); }
  int iy(double y) const { return std::clamp(static_cast<int>(std::floor((y - y0) / cell)), 0, ny - 1); }
  const std::vector<std::size_t>& at(const Vec2& p) const {
    return cells[static_cast<std::size_t>(iy(p.y())) * nx + ix(p.x())];
  }
};

// Edge o is a face of the same triangle as edge e (both name their third node).
bool same_triangle(const SolidEdge& e, const SolidEdge& o) {
  if (e.c == kNoIndex || o.c == kNoIndex) return false;
  auto in_e = [&](Index n) { return n == e.a || n == e.b || n == e.c; };
  return in_e(o.a) && in_e(o.b) && in_e(o.c);
}

// p inside the triangle (a, b, c) or on its sides (to a relative tolerance).
bool inside_triangle(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  auto cross = [](const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
  const double area = cross(b - a, c - a), tol = -1e-9 * std::abs(area);
  const double sign = area < 0.0 ? -1.0 : 1.0;
  return sign * cross(b - a, p - a) >= tol && sign * cross(c - b, p - b) >= tol && sign * cross(a - c, p - c) >= tol;
}

void fill_reflex_corners(BoundaryParticles& walls, std::span<const SolidEdge> edges, std::span<const Vec2> x,
                         int layers, const FluidParameters& par, double surface);

// Where face e's stations fall: at arc lengths (i + 1/2) spacing from its run's start, the
// face beginning `offset` along the run. A run is a chain of continuous faces each starting
// where the last ended and turning by under 30 degrees (a straight bank the mesh cut into
// faces of any length), spaced length / round(length / dp) over the whole run: the
// stations keep the fluid's spacing dp, as the wall rows do across it, where rounding each
// face's own count (a 0.5 m face at dp = 0.2 m: 2 stations 0.25 m apart) would leave the
// wall a fifth lighter than the water it holds and let the water creep into it. A fragment's
// face is a run of its own.
struct StationRun {
  double offset = 0.0, spacing = 0.0;
  int alone = 0;  // a run of this face only: its station count (s = (i + 1/2) / alone)
};
std::vector<StationRun> station_runs(std::span<const SolidEdge> edges, std::span<const Vec2> x, double dp);

// Face e's stations and `layers` rows (k + 1/2) dp behind it, into `out`, each kept
// unless another face is nearer behind which it also lies: a continuous face competes with the
// continuous ones, a fragment's face with its own triangle's (and keeps its points inside it).
struct RowPoint {
  Vec2 p;
  double d, s;
};
void station_rows(std::vector<RowPoint>& out, std::size_t e, std::span<const SolidEdge> edges, std::span<const Vec2> x,
                  const EdgeGrid& grid, int layers, double dp, const StationRun& run) {
  const double reach = layers * dp, tol = 1e-9 * dp;
  out.clear();
  const Vec2 &a = x[edges[e].a], &b = x[edges[e].b];
  const double length = (b - a).norm();
  if (!(length > 0.0)) throw std::invalid_argument("sph::lay_edge_particles: an edge of zero length");
  const Vec2 n = edge_normal(a, b);
  const bool owned = edges[e].c != kNoIndex;
  // The run's stations on [offset, offset + length), to a relative tolerance.
  const double first = std::ceil((run.offset - 1e-9 * run.spacing) / run.spacing - 0.5);
  for (double i = first; (i + 0.5) * run.spacing < run.offset + length - 1e-9 * run.spacing; i += 1.0)
    for (int k = 0; k < layers; ++k) {
      const double s = run.alone > 0 ? (i + 0.5) / run.alone : ((i + 0.5) * run.spacing - run.offset) / length;
      const double d = (k + 0.5) * dp;
      const Vec2 p = (1.0 - s) * a + s * b - d * n;
      if (owned && !inside_triangle(p, a, b, x[edges[e].c])) continue;
      bool kept = true;
      for (std::size_t o : grid.at(p)) {
        if (o == e || (owned ? !same_triangle(edges[e], edges[o]) : edges[o].c != kNoIndex)) continue;
        const Vec2 &oa = x[edges[o].a], &ob = x[edges[o].b];
        const Vec2 ot = ob - oa;
        const double os = (p - oa).dot(ot) / ot.squaredNorm();
        // Not behind o at its very ends: a run's station at the node two faces share belongs
        // to the later face, which competes with the earlier one only there.
        if (os < 1e-9 || os > 1.0 - 1e-9) continue;
        const double od = -(p - oa).dot(edge_normal(oa, ob));
        if (od <= 0.0 || od > reach) continue;
        if (od < d - tol || (od <= d + tol && o < e)) {
          kept = false;
          break;
        }
      }
      if (kept) out.push_back({p, d, s});
    }
}

void add_riding(BoundaryParticles& walls, const Vec2& p, const Vec2& n, double d, double s, std::size_t e,
                const FluidParameters& par, double surface) {
  walls.add_fixed(p.x(), p.y(), hydrostatic_density(surface - p.y(), par), n, d);
  walls.edge.back() = static_cast<Index>(e);
  walls.s.back() = s;
}

// A fragment's triangle is cut by its angle bisectors into three parts, one per face (the
// points nearer that face than the others). Face e's part (a, b, incentre I) gets rows
// parallel to the face, `rows` of them delta = r / rows apart (r the inradius; delta = dp
// once the triangle is deeper than the walls), each row's stations about dp^2 / delta apart:
// about one particle per dp^2 of the triangle, however small, inside it, each behind its
// nearest face. `owed` carries the rows' fractions of a particle from face to face of the
// triangle (rounded once over the triangle, not per row). Returns how many it laid.
int lay_fragment_face(BoundaryParticles& walls, std::size_t e, const Vec2& a, const Vec2& b, const Vec2& c,
                      int layers, const FluidParameters& par, double surface, double& owed) {
  const double dp = par.dp, la = (c - b).norm(), lb = (a - c).norm(), lc = (b - a).norm();
  const double perimeter = la + lb + lc;
  const double area = 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
  const double r = 2.0 * area / perimeter;
  const Vec2 incentre = (la * a + lb * b + lc * c) / perimeter, n = edge_normal(a, b);
  const bool deep = r >= layers * dp;
  const int rows = deep ? layers : std::max(1, static_cast<int>(std::lround(r / dp)));
  const double delta = deep ? dp : r / rows;
  int laid = 0;
  for (int k = 0; k < rows; ++k) {
    const double d = (k + 0.5) * delta, f = d / r;
    const Vec2 p0 = a + f * (incentre - a), p1 = b + f * (incentre - b);  // the row between the bisectors
    const double share = (p1 - p0).norm() * delta / (dp * dp);
    const int stations = std::max(0, static_cast<int>(std::lround(owed + share)));
    owed += share - stations;
    for (int i = 0; i < stations; ++i, ++laid) {
      const Vec2 p = p0 + (i + 0.5) / stations * (p1 - p0);
      add_riding(walls, p, n, d, (p - a).dot(b - a) / (lc * lc), e, par, surface);
    }
  }
  return laid;
}

}  // namespace

void lay_edge_particles(BoundaryParticles& walls, std::span<const SolidEdge> edges, std::span<const Vec2> x,
                        int layers, const FluidParameters& par, double surface) {
  const double dp = par.dp, reach = layers * dp;
  const EdgeGrid grid(edges, x, reach, std::max(reach, dp));
  std::vector<RowPoint> points;
  const std::vector<StationRun> runs = station_runs(edges, x, dp);
  // A fragment's triangle that these rows leave with under half its share of particles (its
  // area / dp^2, at least one; an inradius under about dp: the grains of a granular slide)
  // is filled by lay_fragment_face instead, so the water cannot flow through it.
  struct Fragment {
    std::size_t first = 0;  // its first face
    int rows = 0, laid = 0;
    double owed = 0.0;
  };
  std::map<std::array<Index, 3>, Fragment> fragment;  // by its sorted nodes
  auto key = [&](std::size_t e) {
    std::array<Index, 3> k{edges[e].a, edges[e].b, edges[e].c};
    std::sort(k.begin(), k.end());
    return k;
  };
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (edges[e].c != kNoIndex) {
      station_rows(points, e, edges, x, grid, layers, dp, runs[e]);
      fragment.try_emplace(key(e), Fragment{e, 0, 0, 0.0}).first->second.rows += static_cast<int>(points.size());
    }
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const Vec2 &a = x[edges[e].a], &b = x[edges[e].b];
    const Vec2 n = edge_normal(a, b);
    if (edges[e].c != kNoIndex) {
      Fragment& f = fragment.at(key(e));
      const Vec2& c = x[edges[e].c];
      const double area = 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
      if (f.rows < 0.5 * std::max(1.0, area / (dp * dp))) {
        f.laid += lay_fragment_face(walls, e, a, b, c, layers, par, surface, f.owed);
        continue;
      }
    }
    station_rows(points, e, edges, x, grid, layers, dp, runs[e]);
    for (const RowPoint& q : points) add_riding(walls, q.p, n, q.d, q.s, e, par, surface);
    if (edges[e].c != kNoIndex) fragment.at(key(e)).laid += static_cast<int>(points.size());
  }
  for (const auto& [nodes, frag] : fragment) {
    if (frag.laid > 0) continue;
    const SolidEdge& f = edges[frag.first];
    const Vec2 &a = x[f.a], &b = x[f.b], &c = x[f.c];
    const double la = (c - b).norm(), lb = (a - c).norm(), lc = (b - a).norm();
    const Vec2 incentre = (la * a + lb * b + lc * c) / (la + lb + lc), n = edge_normal(a, b);
    add_riding(walls, incentre, n, -(incentre - a).dot(n), (incentre - a).dot(b - a) / (lc * lc), frag.first, par, surface);
  }
  fill_reflex_corners(walls, edges, x, layers, par, surface);
  walls.mass = par.mass();
}

namespace {

std::vector<StationRun> station_runs(std::span<const SolidEdge> edges, std::span<const Vec2> x, double dp) {
  const std::size_t none = edges.size();
  std::vector<std::size_t> next(edges.size(), none), prev(edges.size(), none);
  std::unordered_map<Index, std::size_t> starting;  // continuous faces by their start node (the first)
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (edges[e].c == kNoIndex) starting.emplace(edges[e].a, e);
  const double cos_turn = std::cos(kPi / 6.0);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (edges[e].c != kNoIndex) continue;
    const auto it = starting.find(edges[e].b);
    if (it == starting.end() || it->second == e || prev[it->second] != none) continue;
    const SolidEdge& f = edges[it->second];
    const Vec2 t1 = (x[edges[e].b] - x[edges[e].a]).normalized(), t2 = (x[f.b] - x[f.a]).normalized();
    if (t1.dot(t2) < cos_turn) continue;
    next[e] = it->second;
    prev[it->second] = e;
  }
  std::vector<StationRun> runs(edges.size());
  std::vector<bool> done(edges.size(), false);
  auto lay = [&](std::size_t start) {  // the run from `start` along next (a closed one once round)
    double total = 0.0;
    for (std::size_t e = start; e != none && !done[e]; e = next[e]) {
      done[e] = true;
      runs[e].offset = total;
      total += (x[edges[e].b] - x[edges[e].a]).norm();
      if (next[e] == start) break;
    }
    const int count = std::max(1, static_cast<int>(std::lround(total / dp)));
    const double spacing = total / count;
    for (std::size_t e = start; e != none; e = next[e]) {
      runs[e].spacing = spacing;
      if (next[e] == start) break;
    }
    if (next[start] == none) runs[start].alone = count;
  };
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (prev[e] == none) lay(e);
  for (std::size_t e = 0; e < edges.size(); ++e)  // closed runs (a smooth loop): from their first face
    if (!done[e]) lay(e);
  return runs;
}

// Where a continuous face e1 ends at node N and the next face e2 turns to the right (the
// solid's angle at N over 180 degrees: a bed meeting a wall), neither face's strip of
// particles covers the wedge behind N and the water would leak through the corner. The
// wedge gets e2's rows continued behind its start (s < 0; they ride e2 by extrapolation),
// kept where they lie behind e1's line past its end.
void fill_reflex_corners(BoundaryParticles& walls, std::span<const SolidEdge> edges, std::span<const Vec2> x,
                         int layers, const FluidParameters& par, double surface) {
  const double dp = par.dp;
  std::unordered_map<Index, std::size_t> ending;  // continuous faces by their end node
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (edges[e].c == kNoIndex) ending.emplace(edges[e].b, e);
  for (std::size_t e2 = 0; e2 < edges.size(); ++e2) {
    if (edges[e2].c != kNoIndex) continue;
    const auto it = ending.find(edges[e2].a);
    if (it == ending.end()) continue;
    const Vec2 &a1 = x[edges[it->second].a], &n = x[edges[e2].a], &b2 = x[edges[e2].b];
    const Vec2 t1 = (n - a1).normalized(), t2 = (b2 - n).normalized();
    if (t1.x() * t2.y() - t1.y() * t2.x() >= -1e-9) continue;  // straight on or turning left: covered
    const Vec2 n1 = edge_normal(a1, n), n2 = edge_normal(n, b2);
    const double l1 = (n - a1).norm(), l2 = (b2 - n).norm();
    for (int i = 1; i <= layers; ++i)
      for (int k = 0; k < layers; ++k) {
        const double sigma = -(i - 0.5) * dp, d = (k + 0.5) * dp;
        const Vec2 p = n + sigma * t2 - d * n2;
        // Past e1's end, or just at it (under the corner node, on neither face's strip).
        if (-(p - a1).dot(n1) <= 0.0 || (p - a1).dot(t1) < l1 - 1e-9 * dp) continue;
        walls.add_fixed(p.x(), p.y(), hydrostatic_density(surface - p.y(), par), n2, d);
        walls.edge.back() = static_cast<Index>(e2);
        walls.s.back() = sigma / l2;
      }
  }
}

}  // namespace

SolidCoupling::SolidCoupling(std::vector<SolidEdge> edges, Fluid& fluid, std::span<const Vec2> x) {
  for (const auto& e : edges) {
    nodes_.push_back(e.a);
    nodes_.push_back(e.b);
  }
  std::sort(nodes_.begin(), nodes_.end());
  nodes_.erase(std::unique(nodes_.begin(), nodes_.end()), nodes_.end());
  auto local = [&](Index n) {
    return static_cast<std::size_t>(std::lower_bound(nodes_.begin(), nodes_.end(), n) - nodes_.begin());
  };
  for (const auto& e : edges) edges_.push_back({local(e.a), local(e.b)});
  const BoundaryParticles& b = fluid.boundary();
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (b.edge[i] == kNoIndex) continue;
    if (b.edge[i] < 0 || static_cast<std::size_t>(b.edge[i]) >= edges_.size())
      throw std::invalid_argument("sph::SolidCoupling: a boundary particle rides an edge that is not coupled");
    riding_.push_back(i);
  }
  const std::size_t nn = nodes_.size();
  x_last_.resize(nn);
  for (std::size_t k = 0; k < nn; ++k) x_last_[k] = x[nodes_[k]];
  x_next_ = x_last_;
  x_sub_ = x_last_;
  v_.assign(nn, Vec2::Zero());
  force_.assign(nn, Vec2::Zero());
  place(fluid, x_last_, v_);
  fluid.set_record_boundary_forces(true);
  gather(fluid, force_, particle_sum_);
}

int SolidCoupling::advance(Fluid& fluid, double dt) {
  const std::size_t nn = nodes_.size();
  const int n = fluid.substeps(dt);
  const double dt_sub = dt / n, inv_dt = 1.0 / dt;
  for (std::size_t k = 0; k < nn; ++k) {
    v_[k] = (x_next_[k] - x_last_[k]) * inv_dt;
    force_[k].setZero();
  }
  particle_sum_.setZero();
  for (int j = 1; j <= n; ++j) {
    if (j == n) {
      place(fluid, x_next_, v_);
    } else {
      const double frac = static_cast<double>(j) / n;
      for (std::size_t k = 0; k < nn; ++k) x_sub_[k] = x_last_[k] + frac * (x_next_[k] - x_last_[k]);
      place(fluid, x_sub_, v_);
    }
    fluid.step(dt_sub);
    gather(fluid, force_, particle_sum_);
    if (observer_) observer_(fluid);
  }
  const double mean = 1.0 / n;
  for (std::size_t k = 0; k < nn; ++k) force_[k] *= mean;
  particle_sum_ *= mean;
  std::copy(x_next_.begin(), x_next_.end(), x_last_.begin());
  return n;
}

void SolidCoupling::place(Fluid& fluid, std::span<const Vec2> x, std::span<const Vec2> v) const {
  BoundaryParticles& b = fluid.moving_boundary();
  for (std::size_t i : riding_) {
    const LocalEdge& e = edges_[static_cast<std::size_t>(b.edge[i])];
    const double s = b.s[i], d = b.wall_distance[i];
    const Vec2 n = edge_normal(x[e.a], x[e.b]);
    const Vec2 p = (1.0 - s) * x[e.a] + s * x[e.b] - d * n;
    const Vec2 u = (1.0 - s) * v[e.a] + s * v[e.b];
    b.x[i] = p.x();
    b.y[i] = p.y();
    b.vx[i] = u.x();
    b.vy[i] = u.y();
    b.nx[i] = n.x();
    b.ny[i] = n.y();
  }
}

void SolidCoupling::gather(const Fluid& fluid, std::vector<Vec2>& sum, Vec2& particle_sum) const {
  const BoundaryParticles& b = fluid.boundary();
  const auto fx = fluid.recorded_boundary_force_x(), fy = fluid.recorded_boundary_force_y();
  for (std::size_t i : riding_) {
    const LocalEdge& e = edges_[static_cast<std::size_t>(b.edge[i])];
    const double s = b.s[i];
    const Vec2 f(fx[i], fy[i]);
    sum[e.a] += (1.0 - s) * f;
    sum[e.b] += s * f;
    particle_sum += f;
  }
}

}  // namespace dsdem::sph
