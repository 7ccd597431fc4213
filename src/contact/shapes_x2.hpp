#pragma once
// The shape update of two triangles at once: make_spheropolygon() and
// core_edge_scales() on the two lanes of SSE2 registers (x86-64's baseline, no
// dispatch). The shape update does 7 square roots and 10 divisions per triangle and
// little else, so it waits on the divider; the packed forms do two lanes for about the
// cost of one.
// The same IEEE operations in the same order per lane, no fused multiply-add: each lane
// equals the scalar functions bit for bit (test ShapesX2.*). Elsewhere: the scalar code.
#include <array>

#include "contact/narrow_phase.hpp"
#include "contact/spheropolygon.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#define DSDEM_SHAPES_X2 1
#endif

namespace dsdem::contact {

#if defined(DSDEM_SHAPES_X2)
// Triangles p[0] and p[1] (vertices in order) with rounding radii r[0], r[1]: their
// spheropolygons and, when scales != nullptr, their cores' edge scales.
inline void make_shapes_x2(const std::array<Vec2, 3>& p_a, const std::array<Vec2, 3>& p_b, double r_a, double r_b,
                           Spheropolygon& out_a, Spheropolygon& out_b, CoreEdgeScales* scales_a,
                           CoreEdgeScales* scales_b) {
  const __m128d zero = _mm_setzero_pd();
  const __m128d sign = _mm_set1_pd(-0.0);
  auto lanes = [](double a, double b) { return _mm_set_pd(b, a); };  // lane 0 = a, lane 1 = b
  const __m128d x0 = lanes(p_a[0].x(), p_b[0].x()), y0 = lanes(p_a[0].y(), p_b[0].y());
  const __m128d x1 = lanes(p_a[1].x(), p_b[1].x()), y1 = lanes(p_a[1].y(), p_b[1].y());
  const __m128d x2 = lanes(p_a[2].x(), p_b[2].x()), y2 = lanes(p_a[2].y(), p_b[2].y());
  const __m128d r = lanes(r_a, r_b);
  auto norm = [](__m128d dx, __m128d dy) { return _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy))); };
  // incircle(): edge lengths opposite each vertex, perimeter, incentre and inradius.
  const __m128d a = norm(_mm_sub_pd(x1, x2), _mm_sub_pd(y1, y2));
  const __m128d b = norm(_mm_sub_pd(x2, x0), _mm_sub_pd(y2, y0));
  const __m128d c = norm(_mm_sub_pd(x0, x1), _mm_sub_pd(y0, y1));
  const __m128d perimeter = _mm_add_pd(_mm_add_pd(a, b), c);
  const __m128d has_perimeter = _mm_cmpgt_pd(perimeter, zero);
  __m128d cx = _mm_div_pd(_mm_add_pd(_mm_add_pd(_mm_mul_pd(a, x0), _mm_mul_pd(b, x1)), _mm_mul_pd(c, x2)), perimeter);
  __m128d cy = _mm_div_pd(_mm_add_pd(_mm_add_pd(_mm_mul_pd(a, y0), _mm_mul_pd(b, y1)), _mm_mul_pd(c, y2)), perimeter);
  const __m128d ux = _mm_sub_pd(x1, x0), uy = _mm_sub_pd(y1, y0), vx = _mm_sub_pd(x2, x0), vy = _mm_sub_pd(y2, y0);
  const __m128d cross = _mm_sub_pd(_mm_mul_pd(ux, vy), _mm_mul_pd(uy, vx));
  __m128d radius = _mm_div_pd(_mm_andnot_pd(sign, cross), perimeter);
  // No perimeter: {p0, 0}.
  cx = _mm_or_pd(_mm_and_pd(has_perimeter, cx), _mm_andnot_pd(has_perimeter, x0));
  cy = _mm_or_pd(_mm_and_pd(has_perimeter, cy), _mm_andnot_pd(has_perimeter, y0));
  radius = _mm_and_pd(has_perimeter, radius);
  // make_spheropolygon(): s = radius > r ? (radius - r) / radius : 0.
  const __m128d shrink = _mm_cmpgt_pd(radius, r);
  const __m128d s = _mm_and_pd(shrink, _mm_div_pd(_mm_sub_pd(radius, r), radius));
  auto scaled = [&](__m128d p, __m128d centre) { return _mm_add_pd(centre, _mm_mul_pd(s, _mm_sub_pd(p, centre))); };
  const __m128d kx[3] = {scaled(x0, cx), scaled(x1, cx), scaled(x2, cx)};
  const __m128d ky[3] = {scaled(y0, cy), scaled(y1, cy), scaled(y2, cy)};
  alignas(16) double buf[2];
  for (int k = 0; k < 3; ++k) {
    _mm_store_pd(buf, kx[k]);
    out_a.core[k].x() = buf[0];
    out_b.core[k].x() = buf[1];
    _mm_store_pd(buf, ky[k]);
    out_a.core[k].y() = buf[0];
    out_b.core[k].y() = buf[1];
  }
  out_a.r = r_a;
  out_b.r = r_b;
  if (!scales_a) return;
  // core_edge_scales().
  const __m128d area2 = _mm_sub_pd(_mm_mul_pd(_mm_sub_pd(kx[1], kx[0]), _mm_sub_pd(ky[2], ky[0])),
                                   _mm_mul_pd(_mm_sub_pd(ky[1], ky[0]), _mm_sub_pd(kx[2], kx[0])));
  const __m128d one = _mm_set1_pd(1.0);
  const __m128d ccw = _mm_cmpge_pd(area2, zero);
  const __m128d orient = _mm_or_pd(_mm_and_pd(ccw, one), _mm_andnot_pd(ccw, _mm_set1_pd(-1.0)));
  __m128d max_len2 = zero;
  alignas(16) double inv[3][2], ns[3][2];
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const __m128d ex = _mm_sub_pd(kx[k1], kx[k]), ey = _mm_sub_pd(ky[k1], ky[k]);
    const __m128d len2 = _mm_add_pd(_mm_mul_pd(ex, ex), _mm_mul_pd(ey, ey));
    // std::max(max_len2, len2): len2 when max_len2 < len2.
    const __m128d grows = _mm_cmplt_pd(max_len2, len2);
    max_len2 = _mm_or_pd(_mm_and_pd(grows, len2), _mm_andnot_pd(grows, max_len2));
    const __m128d positive = _mm_cmpgt_pd(len2, zero);
    _mm_store_pd(inv[k], _mm_and_pd(positive, _mm_div_pd(one, len2)));
    _mm_store_pd(ns[k], _mm_and_pd(positive, _mm_div_pd(orient, _mm_sqrt_pd(len2))));
  }
  const __m128d proper = _mm_cmpgt_pd(_mm_andnot_pd(sign, area2), _mm_mul_pd(_mm_set1_pd(1e-14), max_len2));
  const int proper_bits = _mm_movemask_pd(proper);
  for (int k = 0; k < 3; ++k) {
    scales_a->inv_len2[k] = inv[k][0];
    scales_b->inv_len2[k] = inv[k][1];
    scales_a->n_scale[k] = ns[k][0];
    scales_b->n_scale[k] = ns[k][1];
  }
  scales_a->proper = (proper_bits & 1) != 0;
  scales_b->proper = (proper_bits & 2) != 0;
}
#endif

}  // namespace dsdem::contact
