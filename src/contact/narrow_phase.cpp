#include "contact/narrow_phase.hpp"

#include "contact/vertex_queries_x6.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define DSDEM_QUERIES_X4 1
#endif

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

#if defined(DSDEM_QUERIES_X4)
namespace {

// closest_within() in the four lanes of AVX registers: the scalar code's data-dependent
// branches become compares and blends (branches remain only where all three lanes agree
// or for rare cases), and each lane does the scalar code's IEEE operations in the same
// order (no fused multiply-add), so each lane's result is the scalar one bit for bit
// (test VertexQueries.*).
#define DSDEM_AVX2 __attribute__((target("avx2"), always_inline)) inline
DSDEM_AVX2 __m256d bc(double v) { return _mm256_set1_pd(v); }
DSDEM_AVX2 __m256d add(__m256d a, __m256d b) { return _mm256_add_pd(a, b); }
DSDEM_AVX2 __m256d sub(__m256d a, __m256d b) { return _mm256_sub_pd(a, b); }
DSDEM_AVX2 __m256d mul(__m256d a, __m256d b) { return _mm256_mul_pd(a, b); }
// Where m: a, else b.
DSDEM_AVX2 __m256d sel(__m256d m, __m256d a, __m256d b) { return _mm256_blendv_pd(b, a, m); }
DSDEM_AVX2 __m256d lt(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
DSDEM_AVX2 __m256d le(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
DSDEM_AVX2 __m256d bit_or(__m256d a, __m256d b) { return _mm256_or_pd(a, b); }
DSDEM_AVX2 __m256d bit_and(__m256d a, __m256d b) { return _mm256_and_pd(a, b); }
// (ax - cx) bx + (ay - cy) by, as Vec2 (a - c).dot(b).
DSDEM_AVX2 __m256d dot_from(__m256d ax, __m256d ay, double cx, double cy, __m256d bx, __m256d by) {
  return add(mul(sub(ax, bc(cx)), bx), mul(sub(ay, bc(cy)), by));
}
// Lane-wise v[k] where k = 2 in m2, else 1 in m1, else 0.
DSDEM_AVX2 __m256d pick(__m256d m1, __m256d m2, double v0, double v1, double v2) {
  return sel(m2, bc(v2), sel(m1, bc(v1), bc(v0)));
}

// p - core[k] (dx, dy), which serves both the edge distance and the edge parameter, as in
// the scalar code (the same values), and the signed edge distances sd (edge_distances()).
struct Offsets4 {
  __m256d dx[3], dy[3], sd[3];
};
DSDEM_AVX2 Offsets4 offsets_to_core(__m256d px, __m256d py, const std::array<Vec2, 3>& core, const CoreEdges& ce) {
  Offsets4 o;
  for (int k = 0; k < 3; ++k) {
    o.dx[k] = sub(px, bc(core[k].x()));
    o.dy[k] = sub(py, bc(core[k].y()));
    o.sd[k] = add(mul(o.dx[k], bc(ce.n_out[k].x())), mul(o.dy[k], bc(ce.n_out[k].y())));
  }
  return o;
}

// closest_within()'s rejection, in two parts: outside the core's box grown by reach ...
DSDEM_AVX2 __m256d outside_box(__m256d px, __m256d py, const CoreEdges& ce, double reach) {
  return bit_or(bit_or(lt(px, bc(ce.lo.x() - reach)), lt(bc(ce.hi.x() + reach), px)),
                bit_or(lt(py, bc(ce.lo.y() - reach)), lt(bc(ce.hi.y() + reach), py)));
}
// ... or beyond an edge line by more than reach and the margin.
DSDEM_AVX2 __m256d beyond_edges(__m256d px, __m256d py, double reach, const Offsets4& o) {
  const __m256d sign = bc(-0.0);
  const __m256d beyond =
      add(bc(reach * (1.0 + 1e-6)), mul(bc(1e-12), add(_mm256_andnot_pd(sign, px), _mm256_andnot_pd(sign, py))));
  return bit_or(lt(beyond, o.sd[0]), bit_or(lt(beyond, o.sd[1]), lt(beyond, o.sd[2])));
}

// The lanes' CoreClosest fields (edge and vertex as doubles).
struct Closest4 {
  __m256d dist, qx, qy, nx, ny, edge, t, vertex;
};

// closest_from()'s outside branch: the nearest point of the three segments, the first edge
// winning a tie. t_raw[k]: the unclamped parameter along edge k (the inside branch's).
DSDEM_AVX2 Closest4 nearest_on_edges(__m256d px, __m256d py, const std::array<Vec2, 3>& core, const CoreEdges& ce,
                                     const Offsets4& o, __m256d (&t_raw)[3], __m256d& best) {
  const __m256d zero = _mm256_setzero_pd(), one = bc(1.0);
  Closest4 r;
  best = bc(std::numeric_limits<double>::infinity());
  r.edge = zero, r.t = zero, r.qx = zero, r.qy = zero;
  for (int k = 0; k < 3; ++k) {
    const Vec2& a = core[k];
    const Vec2& b = core[(k + 1) % 3];
    const __m256d ex = bc(ce.e[k].x()), ey = bc(ce.e[k].y());
    t_raw[k] = mul(add(mul(o.dx[k], ex), mul(o.dy[k], ey)), bc(ce.inv_len2[k]));
    const __m256d at_a = le(t_raw[k], zero), at_b = le(one, t_raw[k]);
    const __m256d cx = sel(at_a, bc(a.x()), sel(at_b, bc(b.x()), add(bc(a.x()), mul(t_raw[k], ex))));
    const __m256d cy = sel(at_a, bc(a.y()), sel(at_b, bc(b.y()), add(bc(a.y()), mul(t_raw[k], ey))));
    const __m256d tk = sel(at_a, zero, sel(at_b, one, t_raw[k]));
    const __m256d ux = sub(px, cx), uy = sub(py, cy);
    const __m256d d2 = add(mul(ux, ux), mul(uy, uy));
    const __m256d better = lt(d2, best);
    best = sel(better, d2, best);
    r.edge = sel(better, bc(k), r.edge);
    r.t = sel(better, tk, r.t);
    r.qx = sel(better, cx, r.qx);
    r.qy = sel(better, cy, r.qy);
  }
  return r;
}

// The distance, the normal and the vertex of the outside branch, from the squared
// distance `best` of nearest_on_edges().
DSDEM_AVX2 void outside_result(__m256d px, __m256d py, const CoreEdges& ce, int far_bits, __m256d best, Closest4& r) {
  const __m256d zero = _mm256_setzero_pd(), one = bc(1.0);
  r.dist = _mm256_sqrt_pd(best);
  const __m256d apart = lt(zero, r.dist);
  r.nx = _mm256_div_pd(sub(px, r.qx), r.dist), r.ny = _mm256_div_pd(sub(py, r.qy), r.dist);
  if (((_mm256_movemask_pd(apart) | far_bits) & 7) != 7) {
    // p on the boundary (rare): the edge's own normal, or x on a core collapsed to a point.
    const __m256d e1 = _mm256_cmp_pd(r.edge, one, _CMP_EQ_OQ), e2 = _mm256_cmp_pd(r.edge, bc(2.0), _CMP_EQ_OQ);
    const __m256d has_edge = lt(zero, pick(e1, e2, ce.inv_len2[0], ce.inv_len2[1], ce.inv_len2[2]));
    r.nx = sel(apart, r.nx, sel(has_edge, pick(e1, e2, ce.n_out[0].x(), ce.n_out[1].x(), ce.n_out[2].x()), one));
    r.ny = sel(apart, r.ny, sel(has_edge, pick(e1, e2, ce.n_out[0].y(), ce.n_out[1].y(), ce.n_out[2].y()), zero));
  }
  // An edge end is a vertex (closest_from's vertex).
  r.vertex = sel(le(one, r.t), sel(_mm256_cmp_pd(r.edge, bc(2.0), _CMP_EQ_OQ), zero, add(r.edge, one)), r.edge);
}

// closest_from()'s first branch, in the lanes whose vertex is inside a proper core (rare):
// the least deep edge k. Returns those lanes (none when no near lane is inside).
DSDEM_AVX2 __m256d inside_result(__m256d px, __m256d py, const CoreEdges& ce, int far_bits, const Offsets4& o,
                                 const __m256d (&t_raw)[3], Closest4& r) {
  const __m256d zero = _mm256_setzero_pd(), one = bc(1.0);
  const __m256d* sd = o.sd;
  __m256d inside = bit_and(bit_and(le(sd[0], zero), le(sd[1], zero)), le(sd[2], zero));
  if (!ce.proper) inside = zero;
  if (!(_mm256_movemask_pd(inside) & ~far_bits & 7)) return zero;
  const __m256d m1 = lt(sd[0], sd[1]);
  const __m256d sd01 = sel(m1, sd[1], sd[0]);
  const __m256d m2 = lt(sd01, sd[2]);
  const __m256d sdk = sel(m2, sd[2], sd01);
  const __m256d k_in = sel(m2, bc(2.0), sel(m1, one, zero));
  const __m256d nkx = pick(m1, m2, ce.n_out[0].x(), ce.n_out[1].x(), ce.n_out[2].x());
  const __m256d nky = pick(m1, m2, ce.n_out[0].y(), ce.n_out[1].y(), ce.n_out[2].y());
  __m256d t_in = sel(m2, t_raw[2], sel(m1, t_raw[1], t_raw[0]));
  t_in = sel(lt(t_in, zero), zero, sel(lt(one, t_in), one, t_in));  // std::clamp(t, 0, 1)
  r.dist = sel(inside, sdk, r.dist);
  r.qx = sel(inside, sub(px, mul(sdk, nkx)), r.qx);
  r.qy = sel(inside, sub(py, mul(sdk, nky)), r.qy);
  r.nx = sel(inside, nkx, r.nx);
  r.ny = sel(inside, nky, r.ny);
  r.edge = sel(inside, k_in, r.edge);
  r.vertex = sel(inside, k_in, r.vertex);
  r.t = sel(inside, t_in, r.t);
  return inside;
}

// Writes lanes 0-2 to out; far lanes are CoreClosest{} with an infinite distance.
// at_end: the outside branch's at_vertex (the edge parameter at an end).
DSDEM_AVX2 void store_closest(const Closest4& r, __m256d far, __m256d inside, __m256d at_end,
                              std::array<CoreClosest, 3>& out) {
  const __m256d keep = _mm256_andnot_pd(far, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)));
  alignas(32) double r_dist[4], r_px[4], r_py[4], r_nx[4], r_ny[4], r_edge[4], r_t[4], r_vertex[4];
  _mm256_store_pd(r_dist, sel(far, bc(std::numeric_limits<double>::infinity()), r.dist));
  _mm256_store_pd(r_px, bit_and(keep, r.qx));
  _mm256_store_pd(r_py, bit_and(keep, r.qy));
  _mm256_store_pd(r_nx, bit_and(keep, r.nx));
  _mm256_store_pd(r_ny, bit_and(keep, r.ny));
  _mm256_store_pd(r_edge, bit_and(keep, r.edge));
  _mm256_store_pd(r_t, bit_and(keep, r.t));
  _mm256_store_pd(r_vertex, bit_and(keep, r.vertex));
  const int at_vertex_bits = _mm256_movemask_pd(_mm256_andnot_pd(bit_or(far, inside), at_end));
  for (int v = 0; v < 3; ++v) {
    CoreClosest& c = out[v];
    c.distance = r_dist[v];
    c.point = Vec2(r_px[v], r_py[v]);
    c.normal = Vec2(r_nx[v], r_ny[v]);
    c.edge = static_cast<int>(r_edge[v]);
    c.t = r_t[v];
    c.at_vertex = (at_vertex_bits >> v) & 1;
    c.vertex = static_cast<int>(r_vertex[v]);
  }
}
#undef DSDEM_AVX2

__attribute__((target("avx2"))) void closest_within_avx2(const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& core,
                                                          const CoreEdges& ce, double reach,
                                                          std::array<CoreClosest, 3>& out) {
  // Lane v = vertex v; lane 3 repeats vertex 2 (not read).
  const __m256d px = _mm256_set_pd(p[2].x(), p[2].x(), p[1].x(), p[0].x());
  const __m256d py = _mm256_set_pd(p[2].y(), p[2].y(), p[1].y(), p[0].y());
  const __m256d box_far = outside_box(px, py, ce, reach);
  const Offsets4 o = offsets_to_core(px, py, core, ce);
  const __m256d far = bit_or(box_far, beyond_edges(px, py, reach, o));
  const int far_bits = _mm256_movemask_pd(far) & 7;
  if (far_bits == 7) {  // all three far (common): no more work for them
    for (CoreClosest& c : out) {
      c = CoreClosest{};
      c.distance = std::numeric_limits<double>::infinity();
    }
    return;
  }
  __m256d t_raw[3], best;
  Closest4 r = nearest_on_edges(px, py, core, ce, o, t_raw, best);
  outside_result(px, py, ce, far_bits, best, r);
  const __m256d at_end = bit_or(le(r.t, _mm256_setzero_pd()), le(bc(1.0), r.t));
  const __m256d inside = inside_result(px, py, ce, far_bits, o, t_raw, r);
  store_closest(r, far, inside, at_end, out);
}

bool detect_avx2() {
  __builtin_cpu_init();  // may run before the constructors that would call it
  return __builtin_cpu_supports("avx2");
}
const bool kHaveAvx2 = detect_avx2();

}  // namespace
#endif

namespace {
bool use_x4 =
#if defined(DSDEM_QUERIES_X4)
    kHaveAvx2;
#else
    false;
#endif
}  // namespace

bool closest_within_x3_vectorised() { return use_x4; }

bool set_closest_within_x3_vectorised(bool on) {
#if defined(DSDEM_QUERIES_X4)
  use_x4 = on && kHaveAvx2;
#else
  (void)on;
#endif
  return use_x4;
}

void closest_within_x3(const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& core, const CoreEdges& ce,
                       double reach, std::array<CoreClosest, 3>& out) {
#if defined(DSDEM_QUERIES_X4)
  if (use_x4) return closest_within_avx2(p, core, ce, reach, out);
#endif
  for (int v = 0; v < 3; ++v) out[v] = closest_within(p[v], core, ce, reach);
}

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
// nearest points are two corners, which no edge normal separates).
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
  // Vertices of a on the core of b, vertices of b on the core of a.
  std::array<CoreClosest, 3> ca, cb;
  if (vertex_queries_x6_enabled()) {  // both sides in one pass of eight lanes
    vertex_queries_x6(a.core, ea, b.core, eb, rsum, ca, cb);
  } else {
    closest_within_x3(a.core, b.core, eb, rsum, ca);
    closest_within_x3(b.core, a.core, ea, rsum, cb);
  }
  // Which of the six queries make a contact, as bits (side 0, a's vertex v on b's core:
  // bit v; side 1, b's vertex v on a's core: bit 3 + v), without a branch per query: such
  // data-dependent branches are mispredicted often.
  // Side 0 keeps a vertex-vertex contact only where it is mutual (a's vertex v and b's
  // vertex ca[v].vertex see each other; see header); side 1 keeps none (each kept one is
  // mutual and was counted on side 0). A far query has vertex 0 and at_vertex false.
  unsigned keep = 0;
  for (int v = 0; v < 3; ++v) {
    const CoreClosest& c = ca[v];
    const CoreClosest& o = cb[c.vertex];
    const bool mutual = c.at_vertex & o.at_vertex & (o.vertex == v);
    keep |= static_cast<unsigned>((rsum - c.distance > 0.0) & (!c.at_vertex | mutual)) << v;
  }
  for (int v = 0; v < 3; ++v) {
    const CoreClosest& c = cb[v];
    keep |= static_cast<unsigned>((rsum - c.distance > 0.0) & !c.at_vertex) << (3 + v);
  }
  // The contacts in bit order (side 0, then side 1, as two loops over the queries gave
  // them), each side's values picked by index, not by a branch.
  const std::array<const CoreClosest*, 2> queries{ca.data(), cb.data()};
  const double r_self[2] = {a.r, b.r}, r_other[2] = {b.r, a.r};
  const double to_i[2] = {1.0, -1.0};  // side 0: c.normal points from b's core to a's vertex, j -> i
  int n = 0;
  for (unsigned bits = keep; bits != 0; bits &= bits - 1) {
    const int feature = std::countr_zero(bits);
    const int side = feature / 3, v = feature - 3 * side;
    const CoreClosest& c = queries[side][v];
    ContactGeometry& g = out[n++];
    g.feature = static_cast<std::uint8_t>(feature);
    g.kind = c.at_vertex ? ContactKind::VertexVertex : ContactKind::VertexEdge;
    g.other = static_cast<std::uint8_t>(c.at_vertex ? c.vertex : c.edge);
    g.t = c.t;
    g.distance = c.distance;
    g.overlap = rsum - c.distance;
    g.normal = to_i[side] * c.normal;  // * -1.0 is the negation of any number (a NaN stops the run anyway)
    // Midway between the core's surface (point + r_other n) and the vertex's (vertex - r_self n).
    g.point = c.point + (0.5 * (c.distance + r_other[side] - r_self[side])) * c.normal;
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
