#include "contact/narrow_phase.hpp"

#include <algorithm>
#include <cmath>

namespace dsdem::contact {

CoreClosest closest_on_core(const Vec2& p, const std::array<Vec2, 3>& core) {
  const double area2 = cross(core[1] - core[0], core[2] - core[0]);
  const double orient = area2 >= 0.0 ? 1.0 : -1.0;  // outward normal side for CW cores
  std::array<Vec2, 3> n_out;
  std::array<double, 3> signed_dist;
  double max_len2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const Vec2 e = core[(k + 1) % 3] - core[k];
    const double len2 = e.squaredNorm();
    max_len2 = std::max(max_len2, len2);
    n_out[k] = len2 > 0.0 ? Vec2(orient * Vec2(e.y(), -e.x()) / std::sqrt(len2)) : Vec2::Zero();
    signed_dist[k] = (p - core[k]).dot(n_out[k]);
  }

  CoreClosest c;
  // Inside a non-degenerate core: all signed distances <= 0. Use the least deep edge.
  const bool proper = std::abs(area2) > 1e-14 * max_len2;
  if (proper && signed_dist[0] <= 0.0 && signed_dist[1] <= 0.0 && signed_dist[2] <= 0.0) {
    int k = 0;
    if (signed_dist[1] > signed_dist[k]) k = 1;
    if (signed_dist[2] > signed_dist[k]) k = 2;
    const Vec2 e = core[(k + 1) % 3] - core[k];
    c.edge = k;
    c.t = std::clamp((p - core[k]).dot(e) / e.squaredNorm(), 0.0, 1.0);
    c.distance = signed_dist[k];
    c.normal = n_out[k];
    c.point = p - signed_dist[k] * n_out[k];
    c.at_vertex = false;
    c.vertex = k;
    return c;
  }

  // Outside: nearest point over the three segments; the first edge wins a tie (both
  // edges of a vertex region clamp to the same vertex, so the result is the same).
  double best_d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const Vec2& a = core[k];
    const Vec2& b = core[(k + 1) % 3];
    const Vec2 e = b - a;
    const double len2 = e.squaredNorm();
    double t = len2 > 0.0 ? (p - a).dot(e) / len2 : 0.0;
    Vec2 q;
    // Clamped ends are the exact vertex, so both sides see the same vertex-vertex distance.
    if (t <= 0.0) {
      t = 0.0;
      q = a;
    } else if (t >= 1.0) {
      t = 1.0;
      q = b;
    } else {
      q = a + t * e;
    }
    const double d2 = (p - q).squaredNorm();
    if (k == 0 || d2 < best_d2) {
      best_d2 = d2;
      c.edge = k;
      c.t = t;
      c.point = q;
    }
  }
  c.distance = std::sqrt(best_d2);
  c.at_vertex = c.t <= 0.0 || c.t >= 1.0;
  c.vertex = c.t >= 1.0 ? (c.edge + 1) % 3 : c.edge;
  if (c.distance > 0.0) {
    c.normal = (p - c.point) / c.distance;
  } else if (n_out[c.edge].squaredNorm() > 0.0) {
    c.normal = n_out[c.edge];  // p on the boundary: the edge's outward normal
  } else {
    c.normal = Vec2::UnitX();  // p on a core collapsed to a point: any direction
  }
  return c;
}

int narrow_phase(const Spheropolygon& a, const Spheropolygon& b,
                 std::array<ContactGeometry, kMaxContactsPerPair>& out) {
  const double rsum = a.r + b.r;
  std::array<CoreClosest, 3> ca, cb;  // vertex of a on core of b, vertex of b on core of a
  for (int v = 0; v < 3; ++v) {
    ca[v] = closest_on_core(a.core[v], b.core);
    cb[v] = closest_on_core(b.core[v], a.core);
  }
  auto mutual_vv_a = [&](int v) {  // a's vertex v and b's vertex ca[v].vertex see each other
    const CoreClosest& o = cb[ca[v].vertex];
    return ca[v].at_vertex && o.at_vertex && o.vertex == v;
  };

  int n = 0;
  for (int v = 0; v < 3; ++v) {  // side 0: vertex of a (i) on the core of b (j)
    const CoreClosest& c = ca[v];
    const double overlap = rsum - c.distance;
    if (!(overlap > 0.0)) continue;
    if (c.at_vertex && !mutual_vv_a(v)) continue;  // one-sided vertex-vertex: see header
    ContactGeometry& g = out[n++];
    g.feature = static_cast<std::uint8_t>(v);
    g.kind = c.at_vertex ? ContactKind::VertexVertex : ContactKind::VertexEdge;
    g.other = static_cast<std::uint8_t>(c.at_vertex ? c.vertex : c.edge);
    g.t = c.t;
    g.distance = c.distance;
    g.overlap = overlap;
    g.normal = c.normal;  // from b's core toward a's vertex: j -> i
    // Midway between b's surface (point + r_b n) and a's surface (vertex - r_a n).
    g.point = c.point + (0.5 * (c.distance + b.r - a.r)) * c.normal;
  }
  for (int v = 0; v < 3; ++v) {  // side 1: vertex of b (j) on the core of a (i)
    const CoreClosest& c = cb[v];
    const double overlap = rsum - c.distance;
    if (!(overlap > 0.0)) continue;
    // Every vertex-vertex contact kept is mutual and was counted on side 0.
    if (c.at_vertex) continue;
    ContactGeometry& g = out[n++];
    g.feature = static_cast<std::uint8_t>(3 + v);
    g.kind = ContactKind::VertexEdge;
    g.other = static_cast<std::uint8_t>(c.edge);
    g.t = c.t;
    g.distance = c.distance;
    g.overlap = overlap;
    g.normal = -c.normal;  // c.normal points from a's core to b's vertex: i -> j
    g.point = c.point + (0.5 * (c.distance + a.r - b.r)) * c.normal;
  }
  return n;
}

}  // namespace dsdem::contact
