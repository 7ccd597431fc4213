#include "contact/vertex_queries_x6.hpp"

#include <limits>
#include <stdexcept>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define DSDEM_QUERIES_X6 1
#endif

namespace dsdem::contact {

#if defined(DSDEM_QUERIES_X6)
namespace {

// Lanes 0-3: a's vertices (lane 3 repeats vertex 2, not read) on b's core; lanes 4-7: b's
// vertices on a's core. Each operation is closest_within_x3()'s AVX2 one (narrow_phase.cpp)
// with its broadcasts of one core's data made two-valued, one value per half.
#define DSDEM_AVX512 __attribute__((target("avx512f"), always_inline)) inline
using V = __m512d;
using M = __mmask8;
constexpr M kQueryLanes = 0x77;
// Lanes 0-3 lo, lanes 4-7 hi.
DSDEM_AVX512 V bc2(double lo, double hi) { return _mm512_mask_blend_pd(static_cast<__mmask8>(0xf0), _mm512_set1_pd(lo), _mm512_set1_pd(hi)); }
DSDEM_AVX512 V bc(double v) { return _mm512_set1_pd(v); }
DSDEM_AVX512 V add(V a, V b) { return _mm512_add_pd(a, b); }
DSDEM_AVX512 V sub(V a, V b) { return _mm512_sub_pd(a, b); }
DSDEM_AVX512 V mul(V a, V b) { return _mm512_mul_pd(a, b); }
// Where m: a, else b.
DSDEM_AVX512 V sel(M m, V a, V b) { return _mm512_mask_blend_pd(m, b, a); }
DSDEM_AVX512 M lt(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
DSDEM_AVX512 M le(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
DSDEM_AVX512 M eq(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_EQ_OQ); }
// |a|, the sign bit cleared (not _mm512_abs_pd: GCC 12's reads an undefined register and warns).
DSDEM_AVX512 V abs_of(V a) {
  return _mm512_castsi512_pd(_mm512_and_si512(_mm512_castpd_si512(a), _mm512_set1_epi64(0x7fffffffffffffffLL)));
}
// sqrt and division in every lane (not the unmasked forms: as abs_of).
DSDEM_AVX512 V root(V a) { return _mm512_maskz_sqrt_pd(static_cast<M>(0xff), a); }
DSDEM_AVX512 V div(V a, V b) { return _mm512_maskz_div_pd(static_cast<M>(0xff), a, b); }
// Lane-wise v[k] where k = 2 in m2, else 1 in m1, else 0 (each v two-valued).
DSDEM_AVX512 V pick(M m1, M m2, V v0, V v1, V v2) { return sel(m2, v2, sel(m1, v1, v0)); }

// The core queried in each half and its edge data, broadcast two-valued: b's for lanes 0-3
// (a's vertices), a's for lanes 4-7 (b's vertices).
struct CorePair {
  const std::array<Vec2, 3>& lo;
  const std::array<Vec2, 3>& hi;
  const CoreEdges& ce_lo;
  const CoreEdges& ce_hi;
};
DSDEM_AVX512 V corner_x(const CorePair& c, int k) { return bc2(c.lo[k].x(), c.hi[k].x()); }
DSDEM_AVX512 V corner_y(const CorePair& c, int k) { return bc2(c.lo[k].y(), c.hi[k].y()); }
DSDEM_AVX512 V edge_x(const CorePair& c, int k) { return bc2(c.ce_lo.e[k].x(), c.ce_hi.e[k].x()); }
DSDEM_AVX512 V edge_y(const CorePair& c, int k) { return bc2(c.ce_lo.e[k].y(), c.ce_hi.e[k].y()); }
DSDEM_AVX512 V n_out_x(const CorePair& c, int k) { return bc2(c.ce_lo.n_out[k].x(), c.ce_hi.n_out[k].x()); }
DSDEM_AVX512 V n_out_y(const CorePair& c, int k) { return bc2(c.ce_lo.n_out[k].y(), c.ce_hi.n_out[k].y()); }
DSDEM_AVX512 V inv_len2(const CorePair& c, int k) { return bc2(c.ce_lo.inv_len2[k], c.ce_hi.inv_len2[k]); }

// closest_within()'s box test: outside the core's box grown by reach.
DSDEM_AVX512 M outside_box(V px, V py, const CorePair& c, double reach) {
  const CoreEdges &lo = c.ce_lo, &hi = c.ce_hi;
  return lt(px, bc2(lo.lo.x() - reach, hi.lo.x() - reach)) | lt(bc2(lo.hi.x() + reach, hi.hi.x() + reach), px) |
         lt(py, bc2(lo.lo.y() - reach, hi.lo.y() - reach)) | lt(bc2(lo.hi.y() + reach, hi.hi.y() + reach), py);
}

// p - core[k] (dx, dy), which serves both the edge distance and the edge parameter, and the
// signed edge distances sd (edge_distances()).
struct Offsets8 {
  V dx[3], dy[3], sd[3];
};
DSDEM_AVX512 Offsets8 offsets_to_core(V px, V py, const CorePair& c) {
  Offsets8 o;
  for (int k = 0; k < 3; ++k) {
    o.dx[k] = sub(px, corner_x(c, k));
    o.dy[k] = sub(py, corner_y(c, k));
    o.sd[k] = add(mul(o.dx[k], n_out_x(c, k)), mul(o.dy[k], n_out_y(c, k)));
  }
  return o;
}

// closest_within()'s other rejection: beyond an edge line by more than reach and the margin.
DSDEM_AVX512 M beyond_edges(V px, V py, double reach, const Offsets8& o) {
  const V beyond = add(bc(reach * (1.0 + 1e-6)), mul(bc(1e-12), add(abs_of(px), abs_of(py))));
  return lt(beyond, o.sd[0]) | lt(beyond, o.sd[1]) | lt(beyond, o.sd[2]);
}

// The lanes' CoreClosest fields (edge and vertex as doubles).
struct Closest8 {
  V dist, qx, qy, nx, ny, edge, t, vertex;
};

// closest_from()'s outside branch: the nearest point of the three segments, the first edge
// winning a tie. t_raw[k]: the unclamped parameter along edge k (the inside branch's);
// best: the squared distance.
DSDEM_AVX512 Closest8 nearest_on_edges(V px, V py, const CorePair& c, const Offsets8& o, V (&t_raw)[3], V& best) {
  const V zero = _mm512_setzero_pd(), one = bc(1.0);
  Closest8 r;
  best = bc(std::numeric_limits<double>::infinity());
  r.edge = zero, r.t = zero, r.qx = zero, r.qy = zero;
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const V ax = corner_x(c, k), ay = corner_y(c, k);
    const V bx = corner_x(c, k1), by = corner_y(c, k1);
    const V ex = edge_x(c, k), ey = edge_y(c, k);
    t_raw[k] = mul(add(mul(o.dx[k], ex), mul(o.dy[k], ey)), inv_len2(c, k));
    const M at_a = le(t_raw[k], zero), at_b = le(one, t_raw[k]);
    const V cx = sel(at_a, ax, sel(at_b, bx, add(ax, mul(t_raw[k], ex))));
    const V cy = sel(at_a, ay, sel(at_b, by, add(ay, mul(t_raw[k], ey))));
    const V tk = sel(at_a, zero, sel(at_b, one, t_raw[k]));
    const V ux = sub(px, cx), uy = sub(py, cy);
    const V d2 = add(mul(ux, ux), mul(uy, uy));
    const M better = lt(d2, best);
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
DSDEM_AVX512 void outside_result(V px, V py, const CorePair& c, M far_bits, V best, Closest8& r) {
  const V zero = _mm512_setzero_pd(), one = bc(1.0);
  r.dist = root(best);
  const M apart = lt(zero, r.dist);
  r.nx = div(sub(px, r.qx), r.dist), r.ny = div(sub(py, r.qy), r.dist);
  if (((apart | far_bits) & kQueryLanes) != kQueryLanes) {
    // p on the boundary (rare): the edge's own normal, or x on a core collapsed to a point.
    const M e1 = eq(r.edge, one), e2 = eq(r.edge, bc(2.0));
    const M has_edge = lt(zero, pick(e1, e2, inv_len2(c, 0), inv_len2(c, 1), inv_len2(c, 2)));
    const V nox = pick(e1, e2, n_out_x(c, 0), n_out_x(c, 1), n_out_x(c, 2));
    const V noy = pick(e1, e2, n_out_y(c, 0), n_out_y(c, 1), n_out_y(c, 2));
    r.nx = sel(apart, r.nx, sel(has_edge, nox, one));
    r.ny = sel(apart, r.ny, sel(has_edge, noy, zero));
  }
  // An edge end is a vertex (closest_from's vertex).
  r.vertex = sel(le(one, r.t), sel(eq(r.edge, bc(2.0)), zero, add(r.edge, one)), r.edge);
}

// closest_from()'s first branch, in the lanes whose vertex is inside a proper core (rare):
// the least deep edge k. Returns those lanes (none when no near lane is inside).
DSDEM_AVX512 M inside_result(V px, V py, const CorePair& c, M far_bits, const Offsets8& o, const V (&t_raw)[3],
                             Closest8& r) {
  const V zero = _mm512_setzero_pd(), one = bc(1.0);
  const V* sd = o.sd;
  const M proper = static_cast<M>((c.ce_lo.proper ? 0x0f : 0) | (c.ce_hi.proper ? 0xf0 : 0));
  const M inside = le(sd[0], zero) & le(sd[1], zero) & le(sd[2], zero) & proper;
  if (!(inside & ~far_bits & kQueryLanes)) return 0;
  const M m1 = lt(sd[0], sd[1]);
  const V sd01 = sel(m1, sd[1], sd[0]);
  const M m2 = lt(sd01, sd[2]);
  const V sdk = sel(m2, sd[2], sd01);
  const V k_in = sel(m2, bc(2.0), sel(m1, one, zero));
  const V nkx = pick(m1, m2, n_out_x(c, 0), n_out_x(c, 1), n_out_x(c, 2));
  const V nky = pick(m1, m2, n_out_y(c, 0), n_out_y(c, 1), n_out_y(c, 2));
  V t_in = sel(m2, t_raw[2], sel(m1, t_raw[1], t_raw[0]));
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

// Writes lanes 0-2 to out_a and 4-6 to out_b; far lanes are CoreClosest{} with an infinite
// distance. at_end: the outside branch's at_vertex (the edge parameter at an end).
DSDEM_AVX512 void store_closest(const Closest8& r, M far, M inside, M at_end, std::array<CoreClosest, 3>& out_a,
                                std::array<CoreClosest, 3>& out_b) {
  const M keep = static_cast<M>(~far);
  alignas(64) double r_dist[8], r_px[8], r_py[8], r_nx[8], r_ny[8], r_edge[8], r_t[8], r_vertex[8];
  _mm512_store_pd(r_dist, sel(far, bc(std::numeric_limits<double>::infinity()), r.dist));
  _mm512_store_pd(r_px, _mm512_maskz_mov_pd(keep, r.qx));
  _mm512_store_pd(r_py, _mm512_maskz_mov_pd(keep, r.qy));
  _mm512_store_pd(r_nx, _mm512_maskz_mov_pd(keep, r.nx));
  _mm512_store_pd(r_ny, _mm512_maskz_mov_pd(keep, r.ny));
  _mm512_store_pd(r_edge, _mm512_maskz_mov_pd(keep, r.edge));
  _mm512_store_pd(r_t, _mm512_maskz_mov_pd(keep, r.t));
  _mm512_store_pd(r_vertex, _mm512_maskz_mov_pd(keep, r.vertex));
  const unsigned at_vertex_bits = at_end & ~(far | inside) & 0xffu;
  for (int side = 0; side < 2; ++side) {
    std::array<CoreClosest, 3>& out = side == 0 ? out_a : out_b;
    for (int v = 0; v < 3; ++v) {
      const int l = 4 * side + v;
      CoreClosest& c = out[v];
      c.distance = r_dist[l];
      c.point = Vec2(r_px[l], r_py[l]);
      c.normal = Vec2(r_nx[l], r_ny[l]);
      c.edge = static_cast<int>(r_edge[l]);
      c.t = r_t[l];
      c.at_vertex = (at_vertex_bits >> l) & 1u;
      c.vertex = static_cast<int>(r_vertex[l]);
    }
  }
}
#undef DSDEM_AVX512

__attribute__((target("avx512f"))) void queries_avx512(const std::array<Vec2, 3>& a, const CoreEdges& ea,
                                                       const std::array<Vec2, 3>& b, const CoreEdges& eb,
                                                       double reach, std::array<CoreClosest, 3>& out_a,
                                                       std::array<CoreClosest, 3>& out_b) {
  const V px = _mm512_set_pd(b[2].x(), b[2].x(), b[1].x(), b[0].x(), a[2].x(), a[2].x(), a[1].x(), a[0].x());
  const V py = _mm512_set_pd(b[2].y(), b[2].y(), b[1].y(), b[0].y(), a[2].y(), a[2].y(), a[1].y(), a[0].y());
  const CorePair c{b, a, eb, ea};
  const M box_far = outside_box(px, py, c, reach);
  const Offsets8 o = offsets_to_core(px, py, c);
  const M far = box_far | beyond_edges(px, py, reach, o);
  const M far_bits = far & kQueryLanes;
  if (far_bits == kQueryLanes) {  // rare (examined pairs touch or nearly), cheap anyway
    for (auto* out : {&out_a, &out_b})
      for (CoreClosest& q : *out) {
        q = CoreClosest{};
        q.distance = std::numeric_limits<double>::infinity();
      }
    return;
  }
  V t_raw[3], best;
  Closest8 r = nearest_on_edges(px, py, c, o, t_raw, best);
  outside_result(px, py, c, far_bits, best, r);
  const M at_end = le(r.t, _mm512_setzero_pd()) | le(bc(1.0), r.t);
  const M inside = inside_result(px, py, c, far_bits, o, t_raw, r);
  store_closest(r, far, inside, at_end, out_a, out_b);
}

bool detect_avx512() {
  __builtin_cpu_init();  // may run before the constructors that would call it
  return __builtin_cpu_supports("avx512f");
}
const bool kHaveAvx512 = detect_avx512();
bool use_x6 = kHaveAvx512;

}  // namespace
#endif

bool vertex_queries_x6_enabled() {
#if defined(DSDEM_QUERIES_X6)
  return use_x6;
#else
  return false;
#endif
}

bool set_vertex_queries_x6(bool on) {
#if defined(DSDEM_QUERIES_X6)
  use_x6 = on && kHaveAvx512;
#else
  (void)on;
#endif
  return vertex_queries_x6_enabled();
}

void vertex_queries_x6(const std::array<Vec2, 3>& a, const CoreEdges& ea, const std::array<Vec2, 3>& b,
                       const CoreEdges& eb, double reach, std::array<CoreClosest, 3>& out_a,
                       std::array<CoreClosest, 3>& out_b) {
#if defined(DSDEM_QUERIES_X6)
  if (kHaveAvx512) return queries_avx512(a, ea, b, eb, reach, out_a, out_b);
#endif
  (void)a, (void)ea, (void)b, (void)eb, (void)reach, (void)out_a, (void)out_b;
  throw std::logic_error("vertex_queries_x6: this CPU has no AVX-512F (check vertex_queries_x6_enabled())");
}

}  // namespace dsdem::contact
