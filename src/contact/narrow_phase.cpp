#include "contact/narrow_phase.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dsdem::contact {

CoreEdgeScales core_edge_scales(const std::array<Vec2, 3>& core) {
  CoreEdgeScales s;
  const double area2 = cross(core[1] - core[0], core[2] - core[0]);
  const double orient = area2 >= 0.0 ? 1.0 : -1.0;  // outward = right of the edge if CCW
  double max_len2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const Vec2 e = core[(k + 1) % 3] - core[k];
    const double len2 = e.squaredNorm();
    max_len2 = std::max(max_len2, len2);
    s.inv_len2[k] = len2 > 0.0 ? 1.0 / len2 : 0.0;
    s.n_scale[k] = len2 > 0.0 ? orient / std::sqrt(len2) : 0.0;
  }
  s.proper = std::abs(area2) > 1e-14 * max_len2;
  return s;
}

CoreEdges core_edges(const std::array<Vec2, 3>& core) { return expand(core, core_edge_scales(core)); }

namespace {

// Signed distances of p to the core's edge lines (outward positive).
std::array<double, 3> edge_distances(const Vec2& p, const std::array<Vec2, 3>& core, const CoreEdges& ce) {
  return {(p - core[0]).dot(ce.n_out[0]), (p - core[1]).dot(ce.n_out[1]), (p - core[2]).dot(ce.n_out[2])};
}

// closest_on_core() from the edge distances.
CoreClosest closest_from(const Vec2& p, const std::array<Vec2, 3>& core, const CoreEdges& ce,
                         const std::array<double, 3>& sd) {
  CoreClosest c;
  // Inside a non-degenerate core: all signed distances <= 0. Use the least deep edge.
  if (ce.proper && sd[0] <= 0.0 && sd[1] <= 0.0 && sd[2] <= 0.0) {
    int k = 0;
    if (sd[1] > sd[k]) k = 1;
    if (sd[2] > sd[k]) k = 2;
    c.edge = k;
    c.t = std::clamp((p - core[k]).dot(ce.e[k]) * ce.inv_len2[k], 0.0, 1.0);
    c.distance = sd[k];
    c.normal = ce.n_out[k];
    c.point = p - sd[k] * ce.n_out[k];
    c.at_vertex = false;
    c.vertex = k;
    return c;
  }

  // Outside: nearest point over the three segments; the first edge wins a tie (both
  // edges of a vertex region clamp to the same vertex, so the result is the same).
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const Vec2& a = core[k];
    double t = (p - a).dot(ce.e[k]) * ce.inv_len2[k];
    Vec2 q;
    // Clamped ends are the exact vertex, so both sides see the same vertex-vertex distance.
    if (t <= 0.0) {
      t = 0.0;
      q = a;
    } else if (t >= 1.0) {
      t = 1.0;
      q = core[(k + 1) % 3];
    } else {
      q = a + t * ce.e[k];
    }
    const double d2 = (p - q).squaredNorm();
    if (d2 < best_d2) {
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
  } else if (ce.inv_len2[c.edge] > 0.0) {
    c.normal = ce.n_out[c.edge];  // p on the boundary: the edge's outward normal
  } else {
    c.normal = Vec2::UnitX();  // p on a core collapsed to a point: any direction
  }
  return c;
}

}  // namespace

CoreClosest closest_on_core(const Vec2& p, const std::array<Vec2, 3>& core, const CoreEdges& ce) {
  return closest_from(p, core, ce, edge_distances(p, core, ce));
}

namespace {

// Vertices farther than `reach` from the core's box, or beyond an edge line by more than
// `reach` plus a margin far above rounding (so the computed distance would exceed reach
// too), cannot touch it: skip the query. (A vertex skipped this way is not needed by the
// mutual vertex-vertex test either: the vertex of a contact is within reach of the core.)
CoreClosest closest_within(const Vec2& p, const std::array<Vec2, 3>& core, const CoreEdges& ce,
                           double reach) {
  CoreClosest far;
  far.distance = std::numeric_limits<double>::infinity();
  if (p.x() < ce.lo.x() - reach || p.x() > ce.hi.x() + reach || p.y() < ce.lo.y() - reach ||
      p.y() > ce.hi.y() + reach) {
    return far;
  }
  const std::array<double, 3> sd = edge_distances(p, core, ce);
  const double beyond = reach * (1.0 + 1e-6) + 1e-12 * (std::abs(p.x()) + std::abs(p.y()));
  if (sd[0] > beyond || sd[1] > beyond || sd[2] > beyond) return far;
  return closest_from(p, core, ce, sd);
}

}  // namespace

namespace {

// How far all of q lies beyond p's edge k, past `limit`, along its outward unit normal n
// (p lies on the inner side of the edge line, at or below p[k] . n); 0 when some vertex
// of q is not beyond, found at q's first such vertex (where most pairs not apart end).
[[gnu::always_inline]] inline double beyond_edge(const Vec2& n, const std::array<Vec2, 3>& p, int k,
                                                 const std::array<Vec2, 3>& q, double limit) {
  const double pk = p[k].dot(n);
  const double d0 = q[0].dot(n) - pk;
  if (!(d0 > limit)) return 0.0;
  const double d1 = q[1].dot(n) - pk;
  if (!(d1 > limit)) return 0.0;
  const double d2 = q[2].dot(n) - pk;
  if (!(d2 > limit)) return 0.0;
  return std::min({d0, d1, d2}) - limit;
}

}  // namespace

// The gap two cores must exceed along a unit axis for the rounded shapes not to touch.
// The distance of two convex sets is at least their gap along any unit axis. The
// computed vertex distances (and the edge line's position, p[k] or p[k+1]) err by a
// few ulps of the coordinates: the margin covers that many times over, so a pair
// rejected with it has no contact in narrow_phase().
double clearance_limit(const Spheropolygon& a, const Spheropolygon& b) {
  const double scale = std::abs(a.core[0].x()) + std::abs(a.core[0].y()) + std::abs(b.core[0].x()) + std::abs(b.core[0].y());
  return (a.r + b.r) * (1.0 + 1e-6) + 1e-12 * scale;
}

double cores_clearance(const Spheropolygon& a, const std::array<Vec2, 3>& na, const Spheropolygon& b,
                       const std::array<Vec2, 3>& nb) {
  // A zero normal (zero-length edge) never rejects.
  const double limit = clearance_limit(a, b);
  for (int k = 0; k < 3; ++k) {
    const double ca = beyond_edge(na[k], a.core, k, b.core, limit);
    if (ca > 0.0) return ca;
    const double cb = beyond_edge(nb[k], b.core, k, a.core, limit);
    if (cb > 0.0) return cb;
  }
  return 0.0;
}

int narrow_phase(const Spheropolygon& a, const Spheropolygon& b,
                 std::array<ContactGeometry, kMaxContactsPerPair>& out) {
  return narrow_phase(a, core_edges(a.core), b, core_edges(b.core), out);
}

namespace {

// Gap between p (on the + side) and q along the axis n: min p.n - max q.n.
double gap_along(const Vec2& n, const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& q) {
  return std::min({p[0].dot(n), p[1].dot(n), p[2].dot(n)}) - std::max({q[0].dot(n), q[1].dot(n), q[2].dot(n)});
}

// Clearance of a pair that contacts_of() found without contact, from the six vertex
// queries ca, cb: the gap along the direction of the nearest vertex query (for two
// disjoint convex cores that is their distance) or along x or y (the cores' boxes),
// beyond clearance_limit(); 0 when none exceeds it. Any axis bounds the distance from
// below, so a positive result is a valid cores_clearance() (vertex neighbours whose
// nearest points are two corners, which no edge normal separates, issue 7 disc profile).
double clearance_after(const Spheropolygon& a, const CoreEdges& ea, const Spheropolygon& b, const CoreEdges& eb,
                       const std::array<CoreClosest, 3>& ca, const std::array<CoreClosest, 3>& cb) {
  double best = std::numeric_limits<double>::infinity(), gap = -std::numeric_limits<double>::infinity();
  int side = -1, v = 0;
  for (int k = 0; k < 3; ++k) {
    if (ca[k].distance < best) best = ca[k].distance, side = 0, v = k;
    if (cb[k].distance < best) best = cb[k].distance, side = 1, v = k;
  }
  if (side == 0 && best > 0.0 && std::isfinite(best)) gap = gap_along(ca[v].normal, a.core, b.core);
  if (side == 1 && best > 0.0 && std::isfinite(best)) gap = gap_along(cb[v].normal, b.core, a.core);
  gap = std::max({gap, ea.lo.x() - eb.hi.x(), eb.lo.x() - ea.hi.x(), ea.lo.y() - eb.hi.y(), eb.lo.y() - ea.hi.y()});
  const double c = gap - clearance_limit(a, b);
  return c > 0.0 ? c : 0.0;
}

// narrow_phase() after the cores_apart() rejection. clearance (if given) receives
// clearance_after() when there is no contact.
int contacts_of(const Spheropolygon& a, const CoreEdges& ea, const Spheropolygon& b, const CoreEdges& eb,
                std::array<ContactGeometry, kMaxContactsPerPair>& out, double* clearance = nullptr) {
  const double rsum = a.r + b.r;
  // Vertex of a on the core of b, vertex of b on the core of a (built in place: no
  // default fill first). The same calls as one loop over v, in another order: each
  // query is independent.
  const std::array<CoreClosest, 3> ca{closest_within(a.core[0], b.core, eb, rsum),
                                      closest_within(a.core[1], b.core, eb, rsum),
                                      closest_within(a.core[2], b.core, eb, rsum)};
  const std::array<CoreClosest, 3> cb{closest_within(b.core[0], a.core, ea, rsum),
                                      closest_within(b.core[1], a.core, ea, rsum),
                                      closest_within(b.core[2], a.core, ea, rsum)};
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
  if (n == 0 && clearance) *clearance = clearance_after(a, ea, b, eb, ca, cb);
  return n;
}

}  // namespace

int narrow_phase(const Spheropolygon& a, const CoreEdges& ea, const Spheropolygon& b,
                 const CoreEdges& eb, std::array<ContactGeometry, kMaxContactsPerPair>& out) {
  if (cores_apart(a, ea, b, eb)) return 0;
  return contacts_of(a, ea, b, eb, out);
}

int narrow_phase(const Spheropolygon& a, const CoreEdgeScales& sa, const Spheropolygon& b,
                 const CoreEdgeScales& sb, std::array<ContactGeometry, kMaxContactsPerPair>& out,
                 double* clearance, bool check_apart) {
  if (clearance) *clearance = 0.0;
  // A pair in contact at its last check: straight to the vertex queries.
  if (!check_apart) return contacts_of(a, expand(a.core, sa), b, expand(b.core, sb), out, clearance);
  const std::array<Vec2, 3> na{edge_normal(a.core, sa, 0), edge_normal(a.core, sa, 1), edge_normal(a.core, sa, 2)};
  const std::array<Vec2, 3> nb{edge_normal(b.core, sb, 0), edge_normal(b.core, sb, 1), edge_normal(b.core, sb, 2)};
  const double c = cores_clearance(a, na, b, nb);
  if (c > 0.0) {
    if (clearance) *clearance = c;
    return 0;
  }
  return contacts_of(a, expand(a.core, sa, na), b, expand(b.core, sb, nb), out, clearance);
}

}  // namespace dsdem::contact
