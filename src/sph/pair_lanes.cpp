#include "sph/pair_lanes.hpp"

#include <immintrin.h>

namespace dsdem::sph {

bool pair_lanes_avx2() {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}

namespace {
// The four lanes' sums, added in the fixed order.
inline double reduce(const double (&s)[4]) { return (s[0] + s[2]) + (s[1] + s[3]); }
}  // namespace

// The reference: lane l = pair m + l of each group of four; a group's missing pairs add 0.
template <bool fourtakas>
double density_sum_scalar(const DensityPairConstants& k, const DensityPoint& pi, const DensityRecord* a,
                          const std::int32_t* js, std::size_t n, double* fs) {
  double s[4] = {0.0, 0.0, 0.0, 0.0};
  for (std::size_t m = 0; m < n; m += 4)
    for (std::size_t l = 0; l < 4; ++l) {
      if (m + l >= n) {
        s[l] += 0.0;
        continue;
      }
      const DensityRecord& b = a[js[m + l]];
      const DensityPairTerms t = density_pair<fourtakas>(k, pi, DensityPoint{b.x, b.y, b.vx, b.vy, b.rho, b.gx, b.gy});
      fs[m + l] = t.f;
      s[l] += t.c + t.q * b.vol;
    }
  return reduce(s);
}

template <bool grad>
ForceSums force_sum_scalar(const ForcePairConstants& k, const ForcePoint& pi, const ForceRecord* a,
                           const std::int32_t* js, const double* fs, std::size_t n) {
  double s[7][4] = {};
  for (std::size_t m = 0; m < n; m += 4)
    for (std::size_t l = 0; l < 4; ++l) {
      if (m + l >= n) {
        for (auto& c : s) c[l] += 0.0;
        continue;
      }
      const ForceRecord& b = a[js[m + l]];
      const ForcePairTerms t = force_pair<grad>(k, pi, ForcePoint{b.x, b.y, b.vx, b.vy, b.rho, b.p}, fs[m + l]);
      const double v = b.vol;
      const double terms[7] = {t.ax, t.ay, v * t.xx, v * t.xy, v * t.yy, v * t.sx, v * t.sy};
      for (int c = 0; c < 7; ++c) s[c][l] += terms[c];
    }
  return {reduce(s[0]), reduce(s[1]), -reduce(s[2]), -reduce(s[3]), -reduce(s[4]), reduce(s[5]), reduce(s[6]), 0.0};
}

// The AVX2 lanes: each line the scalar kernel's operation, in its order (kernels.hpp). AVX2
// alone, without FMA: no product is fused with a sum. (A pragma: GCC drops a target
// attribute on a function template.)
#pragma GCC push_options
#pragma GCC target("avx2")
#define DSDEM_LANES __attribute__((always_inline)) inline
namespace {
using V = __m256d;
DSDEM_LANES V all(double x) { return _mm256_set1_pd(x); }
// Four records' eight values, lane l from record js[l]: v[c] holds value c of each (two
// 4 x 4 transposes of the records' halves).
template <class Record>
DSDEM_LANES void load_records(const Record* a, const std::int32_t* js, V (&v)[8]) {
  static_assert(sizeof(Record) == 8 * sizeof(double) && alignof(Record) == 64);
  const auto half_of = [&](int l, int half) { return _mm256_load_pd(reinterpret_cast<const double*>(a + js[l]) + 4 * half); };
  for (int half = 0; half < 2; ++half) {
    const V r0 = half_of(0, half), r1 = half_of(1, half), r2 = half_of(2, half), r3 = half_of(3, half);
    const V lo01 = _mm256_unpacklo_pd(r0, r1), hi01 = _mm256_unpackhi_pd(r0, r1);  // (0 0 2 2), (1 1 3 3)
    const V lo23 = _mm256_unpacklo_pd(r2, r3), hi23 = _mm256_unpackhi_pd(r2, r3);
    v[4 * half + 0] = _mm256_permute2f128_pd(lo01, lo23, 0x20);
    v[4 * half + 1] = _mm256_permute2f128_pd(hi01, hi23, 0x20);
    v[4 * half + 2] = _mm256_permute2f128_pd(lo01, lo23, 0x31);
    v[4 * half + 3] = _mm256_permute2f128_pd(hi01, hi23, 0x31);
  }
}
DSDEM_LANES V add(V a, V b) { return _mm256_add_pd(a, b); }
DSDEM_LANES V sub(V a, V b) { return _mm256_sub_pd(a, b); }
DSDEM_LANES V mul(V a, V b) { return _mm256_mul_pd(a, b); }
DSDEM_LANES V vdiv(V a, V b) { return _mm256_div_pd(a, b); }
DSDEM_LANES V neg(V a) { return _mm256_xor_pd(a, all(-0.0)); }
DSDEM_LANES V vabs(V a) { return _mm256_andnot_pd(all(-0.0), a); }
DSDEM_LANES double reduce(V s) {
  double x[4];
  _mm256_storeu_pd(x, s);
  return (x[0] + x[2]) + (x[1] + x[3]);
}

// wendland_gradient_factor: q = sqrt(r2) / h, t = 1 - q/2, u = max(t, 0), c u^3.
DSDEM_LANES V gradient_factor(V r2, double inv_h, double c) {
  const V q = mul(_mm256_sqrt_pd(r2), all(inv_h));
  const V t = sub(all(1.0), mul(all(0.5), q));
  const V u = mul(all(0.5), add(t, vabs(t)));
  return mul(mul(mul(all(c), u), u), u);
}

// A group of w < 4 pairs: its indices padded with the first (terms computed, masked to 0).
struct Group {
  std::int32_t js[4];
  alignas(32) double fs[4] = {0.0, 0.0, 0.0, 0.0};  // the force pass's F, 0 in the padding
  V mask;
  Group(const std::int32_t* js0, std::size_t w, const double* fs0 = nullptr) {
    for (std::size_t l = 0; l < 4; ++l) js[l] = js0[l < w ? l : 0];
    if (fs0 != nullptr)
      for (std::size_t l = 0; l < w; ++l) fs[l] = fs0[l];
    mask = _mm256_castsi256_pd(_mm256_set_epi64x(w > 3 ? -1 : 0, w > 2 ? -1 : 0, w > 1 ? -1 : 0, -1));
  }
};

// density_pair's c + q V_j for the four pairs (i, js[l]); f: their F.
template <bool fourtakas>
DSDEM_LANES V density_terms(const DensityPairConstants& k, const DensityPoint& pi, const DensityRecord* a,
                            const std::int32_t* js, V& f) {
  V b[8];  // x, y, vx, vy, rho, gx, gy, vol
  load_records(a, js, b);
  const V dx = sub(all(pi.x), b[0]), dy = sub(all(pi.y), b[1]);
  const V rho_j = b[4];
  f = gradient_factor(add(mul(dx, dx), mul(dy, dy)), k.inv_h, k.grad_c);
  const V vr = add(mul(sub(all(pi.vx), b[2]), dx), mul(sub(all(pi.vy), b[3]), dy));
  const V c = mul(mul(all(k.mass), f), vr);
  const V diffusion = mul(all(-2.0 * k.delta_h_c0), f);  // density_diffusion without its rho difference
  V q;
  if constexpr (fourtakas) {
    // hydrostatic_density_difference(-(g . r), rho_i, rho_j): rho g.r_ji / (c0^2 (rho/rho0)^6).
    const V g_dot = neg(add(mul(all(k.gx), dx), mul(all(k.gy), dy)));
    const V rho = mul(all(0.5), add(all(pi.rho), rho_j));
    const V r = vdiv(rho, all(k.rho0));
    const V r2 = mul(r, r);
    const V rho_h = vdiv(mul(rho, g_dot), mul(mul(mul(all(k.c0 * k.c0), r2), r2), r2));
    q = mul(diffusion, sub(sub(rho_j, all(pi.rho)), rho_h));
  } else {
    const V gsum = neg(add(mul(add(all(pi.gx), b[5]), dx), mul(add(all(pi.gy), b[6]), dy)));
    q = add(mul(diffusion, sub(rho_j, all(pi.rho))), mul(mul(all(k.delta_h_c0), f), gsum));
  }
  return add(c, mul(q, b[7]));
}

// force_pair's terms for the four pairs (i, js[l]), into the seven lane sums (the
// gradient's products times V_j).
template <bool grad>
DSDEM_LANES void add_force_terms(const ForcePairConstants& k, const ForcePoint& pi, const ForceRecord* a,
                                 const std::int32_t* js, V f, V mask, V (&s)[7]) {
  V b[8];  // x, y, vx, vy, rho, p, vol, unused
  load_records(a, js, b);
  const V dx = sub(all(pi.x), b[0]), dy = sub(all(pi.y), b[1]);
  const V rho_j = b[4];
  const V vr = add(mul(sub(all(pi.vx), b[2]), dx), mul(sub(all(pi.vy), b[3]), dy));
  const V r2 = add(mul(dx, dx), mul(dy, dy));
  // artificial_viscosity: -2 alpha c h min(v.r, 0) / ((r^2 + 0.01 h^2) (rho_i + rho_j)).
  const V visc = vdiv(mul(all(-2.0 * k.alpha_c * k.h), mul(all(0.5), sub(vr, vabs(vr)))),
                      mul(add(r2, all(0.01 * k.h * k.h)), add(all(pi.rho), rho_j)));
  const V pressure = vdiv(add(all(pi.p), b[5]), mul(all(pi.rho), rho_j));  // pressure_term
  const V coef = mul(mul(all(-k.mass), add(pressure, visc)), f);
  V t[7] = {mul(coef, dx), mul(coef, dy), all(0.0), all(0.0), all(0.0), all(0.0), all(0.0)};
  if constexpr (grad) {
    const V v = b[6];
    const V fdx = mul(f, dx), fdy = mul(f, dy), dr = sub(rho_j, all(pi.rho));
    t[2] = mul(v, mul(fdx, dx));
    t[3] = mul(v, mul(fdx, dy));
    t[4] = mul(v, mul(fdy, dy));
    t[5] = mul(v, mul(dr, fdx));
    t[6] = mul(v, mul(dr, fdy));
  }
  for (int c = 0; c < 7; ++c) s[c] = add(s[c], _mm256_and_pd(t[c], mask));
}
}  // namespace

template <bool fourtakas>
double density_sum_avx2(const DensityPairConstants& k, const DensityPoint& pi, const DensityRecord* a,
                        const std::int32_t* js, std::size_t n, double* fs) {
  V s = all(0.0), fv;
  std::size_t m = 0;
  for (; m + 4 <= n; m += 4) {
    s = add(s, density_terms<fourtakas>(k, pi, a, js + m, fv));
    _mm256_storeu_pd(fs + m, fv);
  }
  if (m < n) {
    const Group g(js + m, n - m);
    s = add(s, _mm256_and_pd(density_terms<fourtakas>(k, pi, a, g.js, fv), g.mask));
    alignas(32) double f4[4];
    _mm256_store_pd(f4, fv);
    for (std::size_t l = 0; m + l < n; ++l) fs[m + l] = f4[l];
  }
  return reduce(s);
}

template <bool grad>
ForceSums force_sum_avx2(const ForcePairConstants& k, const ForcePoint& pi, const ForceRecord* a,
                         const std::int32_t* js, const double* fs, std::size_t n) {
  V s[7];
  for (V& x : s) x = all(0.0);
  const V every = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  std::size_t m = 0;
  for (; m + 4 <= n; m += 4) add_force_terms<grad>(k, pi, a, js + m, _mm256_loadu_pd(fs + m), every, s);
  if (m < n) {
    const Group g(js + m, n - m, fs + m);
    add_force_terms<grad>(k, pi, a, g.js, _mm256_load_pd(g.fs), g.mask, s);
  }
  return {reduce(s[0]), reduce(s[1]), -reduce(s[2]), -reduce(s[3]), -reduce(s[4]), reduce(s[5]), reduce(s[6]), 0.0};
}

template double density_sum_avx2<true>(const DensityPairConstants&, const DensityPoint&, const DensityRecord*,
                                       const std::int32_t*, std::size_t, double*);
template double density_sum_avx2<false>(const DensityPairConstants&, const DensityPoint&, const DensityRecord*,
                                        const std::int32_t*, std::size_t, double*);
template ForceSums force_sum_avx2<true>(const ForcePairConstants&, const ForcePoint&, const ForceRecord*,
                                        const std::int32_t*, const double*, std::size_t);
template ForceSums force_sum_avx2<false>(const ForcePairConstants&, const ForcePoint&, const ForceRecord*,
                                         const std::int32_t*, const double*, std::size_t);
#undef DSDEM_LANES
#pragma GCC pop_options

template double density_sum_scalar<true>(const DensityPairConstants&, const DensityPoint&, const DensityRecord*,
                                         const std::int32_t*, std::size_t, double*);
template double density_sum_scalar<false>(const DensityPairConstants&, const DensityPoint&, const DensityRecord*,
                                          const std::int32_t*, std::size_t, double*);
template ForceSums force_sum_scalar<true>(const ForcePairConstants&, const ForcePoint&, const ForceRecord*,
                                          const std::int32_t*, const double*, std::size_t);
template ForceSums force_sum_scalar<false>(const ForcePairConstants&, const ForcePoint&, const ForceRecord*,
                                           const std::int32_t*, const double*, std::size_t);

}  // namespace dsdem::sph
