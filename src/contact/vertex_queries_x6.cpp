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
#undef DSDEM_AVX512

__attribute__((target("avx512f"))) void queries_avx512(const std::array<Vec2, 3>& a, const CoreEdges& ea,
                                                       const std::array<Vec2, 3>& b, const CoreEdges& eb,
                                                       double reach, std::array<CoreClosest, 3>& out_a,
                                                       std::array<CoreClosest, 3>& out_b) {
  const V px = _mm512_set_pd(b[2].x(), b[2].x(), b[1].x(), b[0].x(), a[2].x(), a[2].x(), a[1].x(), a[0].x());
  const V py = _mm512_set_pd(b[2].y(), b[2].y(), b[1].y(), b[0].y(), a[2].y(), a[2].y(), a[1].y(), a[0].y());
  // The core queried in each half and its edge data: b's for lanes 0-3, a's for 4-7.
  const std::array<Vec2, 3>& core_lo = b;
  const std::array<Vec2, 3>& core_hi = a;
  const CoreEdges& ce_lo = eb;
  const CoreEdges& ce_hi = ea;
  const V zero = _mm512_setzero_pd(), one = bc(1.0), inf = bc(std::numeric_limits<double>::infinity());
  // The box test and the edge distances (closest_within).
  M far = lt(px, bc2(ce_lo.lo.x() - reach, ce_hi.lo.x() - reach)) | lt(bc2(ce_lo.hi.x() + reach, ce_hi.hi.x() + reach), px) |
          lt(py, bc2(ce_lo.lo.y() - reach, ce_hi.lo.y() - reach)) | lt(bc2(ce_lo.hi.y() + reach, ce_hi.hi.y() + reach), py);
  V dx[3], dy[3], sd[3];
  for (int k = 0; k < 3; ++k) {
    dx[k] = sub(px, bc2(core_lo[k].x(), core_hi[k].x()));
    dy[k] = sub(py, bc2(core_lo[k].y(), core_hi[k].y()));
    sd[k] = add(mul(dx[k], bc2(ce_lo.n_out[k].x(), ce_hi.n_out[k].x())),
                mul(dy[k], bc2(ce_lo.n_out[k].y(), ce_hi.n_out[k].y())));
  }
  const V beyond = add(bc(reach * (1.0 + 1e-6)), mul(bc(1e-12), add(abs_of(px), abs_of(py))));
  far |= lt(beyond, sd[0]) | lt(beyond, sd[1]) | lt(beyond, sd[2]);
  const M far_bits = far & kQueryLanes;
  if (far_bits == kQueryLanes) {  // rare (examined pairs touch or nearly), cheap anyway
    for (auto* out : {&out_a, &out_b})
      for (CoreClosest& c : *out) {
        c = CoreClosest{};
        c.distance = std::numeric_limits<double>::infinity();
      }
    return;
  }
  // Outside: the nearest point of the three segments, the first edge winning a tie.
  V t_raw[3];
  V best = inf, edge = zero, t = zero, qx = zero, qy = zero;
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const V ax = bc2(core_lo[k].x(), core_hi[k].x()), ay = bc2(core_lo[k].y(), core_hi[k].y());
    const V bx = bc2(core_lo[k1].x(), core_hi[k1].x()), by = bc2(core_lo[k1].y(), core_hi[k1].y());
    const V ex = bc2(ce_lo.e[k].x(), ce_hi.e[k].x()), ey = bc2(ce_lo.e[k].y(), ce_hi.e[k].y());
    t_raw[k] = mul(add(mul(dx[k], ex), mul(dy[k], ey)), bc2(ce_lo.inv_len2[k], ce_hi.inv_len2[k]));
    const M at_a = le(t_raw[k], zero), at_b = le(one, t_raw[k]);
    const V cx = sel(at_a, ax, sel(at_b, bx, add(ax, mul(t_raw[k], ex))));
    const V cy = sel(at_a, ay, sel(at_b, by, add(ay, mul(t_raw[k], ey))));
    const V tk = sel(at_a, zero, sel(at_b, one, t_raw[k]));
    const V ux = sub(px, cx), uy = sub(py, cy);
    const V d2 = add(mul(ux, ux), mul(uy, uy));
    const M better = lt(d2, best);
    best = sel(better, d2, best);
    edge = sel(better, bc(k), edge);
    t = sel(better, tk, t);
    qx = sel(better, cx, qx);
    qy = sel(better, cy, qy);
  }
  const V dist = root(best);
  const M apart = lt(zero, dist);
  V nx = div(sub(px, qx), dist), ny = div(sub(py, qy), dist);
  if (((apart | far_bits) & kQueryLanes) != kQueryLanes) {
    // p on the boundary (rare): the edge's own normal, or x on a core collapsed to a point.
    const M e1 = eq(edge, one), e2 = eq(edge, bc(2.0));
    const M has_edge = lt(zero, pick(e1, e2, bc2(ce_lo.inv_len2[0], ce_hi.inv_len2[0]),
                                     bc2(ce_lo.inv_len2[1], ce_hi.inv_len2[1]), bc2(ce_lo.inv_len2[2], ce_hi.inv_len2[2])));
    const V nox = pick(e1, e2, bc2(ce_lo.n_out[0].x(), ce_hi.n_out[0].x()), bc2(ce_lo.n_out[1].x(), ce_hi.n_out[1].x()),
                       bc2(ce_lo.n_out[2].x(), ce_hi.n_out[2].x()));
    const V noy = pick(e1, e2, bc2(ce_lo.n_out[0].y(), ce_hi.n_out[0].y()), bc2(ce_lo.n_out[1].y(), ce_hi.n_out[1].y()),
                       bc2(ce_lo.n_out[2].y(), ce_hi.n_out[2].y()));
    nx = sel(apart, nx, sel(has_edge, nox, one));
    ny = sel(apart, ny, sel(has_edge, noy, zero));
  }
  // Outside lanes: an edge end is a vertex (closest_from's at_vertex and vertex).
  const M at_end = le(t, zero) | le(one, t);
  V vertex = sel(le(one, t), sel(eq(edge, bc(2.0)), zero, add(edge, one)), edge);
  V dist_out = dist;
  // Inside a proper core (closest_from's first branch): the least deep edge k.
  const M proper = static_cast<M>((ce_lo.proper ? 0x0f : 0) | (ce_hi.proper ? 0xf0 : 0));
  M inside = le(sd[0], zero) & le(sd[1], zero) & le(sd[2], zero) & proper;
  if (inside & ~far_bits & kQueryLanes) {  // rare: a vertex inside the other core
    const M m1 = lt(sd[0], sd[1]);
    const V sd01 = sel(m1, sd[1], sd[0]);
    const M m2 = lt(sd01, sd[2]);
    const V sdk = sel(m2, sd[2], sd01);
    const V k_in = sel(m2, bc(2.0), sel(m1, one, zero));
    const V nkx = pick(m1, m2, bc2(ce_lo.n_out[0].x(), ce_hi.n_out[0].x()), bc2(ce_lo.n_out[1].x(), ce_hi.n_out[1].x()),
                       bc2(ce_lo.n_out[2].x(), ce_hi.n_out[2].x()));
    const V nky = pick(m1, m2, bc2(ce_lo.n_out[0].y(), ce_hi.n_out[0].y()), bc2(ce_lo.n_out[1].y(), ce_hi.n_out[1].y()),
                       bc2(ce_lo.n_out[2].y(), ce_hi.n_out[2].y()));
    V t_in = sel(m2, t_raw[2], sel(m1, t_raw[1], t_raw[0]));
    t_in = sel(lt(t_in, zero), zero, sel(lt(one, t_in), one, t_in));  // std::clamp(t, 0, 1)
    dist_out = sel(inside, sdk, dist_out);
    qx = sel(inside, sub(px, mul(sdk, nkx)), qx);
    qy = sel(inside, sub(py, mul(sdk, nky)), qy);
    nx = sel(inside, nkx, nx);
    ny = sel(inside, nky, ny);
    edge = sel(inside, k_in, edge);
    vertex = sel(inside, k_in, vertex);
    t = sel(inside, t_in, t);
  } else {
    inside = 0;
  }
  // Far lanes: CoreClosest{} with an infinite distance.
  const M keep = static_cast<M>(~far);
  alignas(64) double r_dist[8], r_px[8], r_py[8], r_nx[8], r_ny[8], r_edge[8], r_t[8], r_vertex[8];
  _mm512_store_pd(r_dist, sel(far, inf, dist_out));
  _mm512_store_pd(r_px, _mm512_maskz_mov_pd(keep, qx));
  _mm512_store_pd(r_py, _mm512_maskz_mov_pd(keep, qy));
  _mm512_store_pd(r_nx, _mm512_maskz_mov_pd(keep, nx));
  _mm512_store_pd(r_ny, _mm512_maskz_mov_pd(keep, ny));
  _mm512_store_pd(r_edge, _mm512_maskz_mov_pd(keep, edge));
  _mm512_store_pd(r_t, _mm512_maskz_mov_pd(keep, t));
  _mm512_store_pd(r_vertex, _mm512_maskz_mov_pd(keep, vertex));
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
