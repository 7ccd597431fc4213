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
double density_sum_scalar(const DensityPairConstants& k, const DensityPoint& pi, const DensityArrays& a,
                          const std::int32_t* js, std::size_t n) {
  double s[4] = {0.0, 0.0, 0.0, 0.0};
  for (std::size_t m = 0; m < n; m += 4)
    for (std::size_t l = 0; l < 4; ++l) {
      if (m + l >= n) {
        s[l] += 0.0;
        continue;
      }
      const auto j = static_cast<std::size_t>(js[m + l]);
      const DensityPairTerms t =
          density_pair<fourtakas>(k, pi, DensityPoint{a.x[j], a.y[j], a.vx[j], a.vy[j], a.rho[j], a.gx[j], a.gy[j]});
      s[l] += t.c + t.q * a.vol[j];
    }
  return reduce(s);
}

template <bool grad>
ForceSums force_sum_scalar(const ForcePairConstants& k, const ForcePoint& pi, const ForceArrays& a,
                           const std::int32_t* js, std::size_t n) {
  double s[7][4] = {};
  for (std::size_t m = 0; m < n; m += 4)
    for (std::size_t l = 0; l < 4; ++l) {
      if (m + l >= n) {
        for (auto& c : s) c[l] += 0.0;
        continue;
      }
      const auto j = static_cast<std::size_t>(js[m + l]);
      const double dx = pi.x - a.x[j], dy = pi.y - a.y[j];
      const double f = wendland_gradient_factor(dx * dx + dy * dy, k.inv_h, k.grad_c);
      const ForcePairTerms t =
          force_pair<grad>(k, pi, ForcePoint{a.x[j], a.y[j], a.vx[j], a.vy[j], a.rho[j], a.p[j]}, f);
      const double v = a.vol[j];
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
DSDEM_LANES V gather(const double* a, const std::int32_t* js) { return _mm256_set_pd(a[js[3]], a[js[2]], a[js[1]], a[js[0]]); }
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
  V mask;
  Group(const std::int32_t* js0, std::size_t w) {
    for (std::size_t l = 0; l < 4; ++l) js[l] = js0[l < w ? l : 0];
    mask = _mm256_castsi256_pd(_mm256_set_epi64x(w > 3 ? -1 : 0, w > 2 ? -1 : 0, w > 1 ? -1 : 0, -1));
  }
};

// density_pair's c + q V_j for the four pairs (i, js[l]); f: their F.
template <bool fourtakas>
DSDEM_LANES V density_terms(const DensityPairConstants& k, const DensityPoint& pi, const DensityArrays& a,
                            const std::int32_t* js, V& f) {
  const V dx = sub(all(pi.x), gather(a.x, js)), dy = sub(all(pi.y), gather(a.y, js));
  const V rho_j = gather(a.rho, js);
  f = gradient_factor(add(mul(dx, dx), mul(dy, dy)), k.inv_h, k.grad_c);
  const V vr = add(mul(sub(all(pi.vx), gather(a.vx, js)), dx), mul(sub(all(pi.vy), gather(a.vy, js)), dy));
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
    const V gsum = neg(add(mul(add(all(pi.gx), gather(a.gx, js)), dx), mul(add(all(pi.gy), gather(a.gy, js)), dy)));
    q = add(mul(diffusion, sub(rho_j, all(pi.rho))), mul(mul(all(k.delta_h_c0), f), gsum));
  }
  return add(c, mul(q, gather(a.vol, js)));
}

// force_pair's terms for the four pairs (i, js[l]), into the seven lane sums (the
// gradient's products times V_j).
template <bool grad>
DSDEM_LANES void add_force_terms(const ForcePairConstants& k, const ForcePoint& pi, const ForceArrays& a,
                                 const std::int32_t* js, V mask, V (&s)[7]) {
  const V dx = sub(all(pi.x), gather(a.x, js)), dy = sub(all(pi.y), gather(a.y, js));
  const V rho_j = gather(a.rho, js);
  const V vr = add(mul(sub(all(pi.vx), gather(a.vx, js)), dx), mul(sub(all(pi.vy), gather(a.vy, js)), dy));
  const V r2 = add(mul(dx, dx), mul(dy, dy));
  const V f = gradient_factor(r2, k.inv_h, k.grad_c);
  // artificial_viscosity: -2 alpha c h min(v.r, 0) / ((r^2 + 0.01 h^2) (rho_i + rho_j)).
  const V visc = vdiv(mul(all(-2.0 * k.alpha_c * k.h), mul(all(0.5), sub(vr, vabs(vr)))),
                      mul(add(r2, all(0.01 * k.h * k.h)), add(all(pi.rho), rho_j)));
  const V pressure = vdiv(add(all(pi.p), gather(a.p, js)), mul(all(pi.rho), rho_j));  // pressure_term
  const V coef = mul(mul(all(-k.mass), add(pressure, visc)), f);
  V t[7] = {mul(coef, dx), mul(coef, dy), all(0.0), all(0.0), all(0.0), all(0.0), all(0.0)};
  if constexpr (grad) {
    const V v = gather(a.vol, js);
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
double density_sum_avx2(const DensityPairConstants& k, const DensityPoint& pi, const DensityArrays& a,
                        const std::int32_t* js, std::size_t n) {
  V s = all(0.0), fv;
  std::size_t m = 0;
  for (; m + 4 <= n; m += 4) s = add(s, density_terms<fourtakas>(k, pi, a, js + m, fv));
  if (m < n) {
    const Group g(js + m, n - m);
    s = add(s, _mm256_and_pd(density_terms<fourtakas>(k, pi, a, g.js, fv), g.mask));
  }
  return reduce(s);
}

template <bool grad>
ForceSums force_sum_avx2(const ForcePairConstants& k, const ForcePoint& pi, const ForceArrays& a,
                         const std::int32_t* js, std::size_t n) {
  V s[7];
  for (V& x : s) x = all(0.0);
  const V every = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  std::size_t m = 0;
  for (; m + 4 <= n; m += 4) add_force_terms<grad>(k, pi, a, js + m, every, s);
  if (m < n) {
    const Group g(js + m, n - m);
    add_force_terms<grad>(k, pi, a, g.js, g.mask, s);
  }
  return {reduce(s[0]), reduce(s[1]), -reduce(s[2]), -reduce(s[3]), -reduce(s[4]), reduce(s[5]), reduce(s[6]), 0.0};
}

template double density_sum_avx2<true>(const DensityPairConstants&, const DensityPoint&, const DensityArrays&,
                                       const std::int32_t*, std::size_t);
template double density_sum_avx2<false>(const DensityPairConstants&, const DensityPoint&, const DensityArrays&,
                                        const std::int32_t*, std::size_t);
template ForceSums force_sum_avx2<true>(const ForcePairConstants&, const ForcePoint&, const ForceArrays&,
                                        const std::int32_t*, std::size_t);
template ForceSums force_sum_avx2<false>(const ForcePairConstants&, const ForcePoint&, const ForceArrays&,
                                         const std::int32_t*, std::size_t);
#undef DSDEM_LANES
#pragma GCC pop_options

template double density_sum_scalar<true>(const DensityPairConstants&, const DensityPoint&, const DensityArrays&,
                                         const std::int32_t*, std::size_t);
template double density_sum_scalar<false>(const DensityPairConstants&, const DensityPoint&, const DensityArrays&,
                                          const std::int32_t*, std::size_t);
template ForceSums force_sum_scalar<true>(const ForcePairConstants&, const ForcePoint&, const ForceArrays&,
                                          const std::int32_t*, std::size_t);
template ForceSums force_sum_scalar<false>(const ForcePairConstants&, const ForcePoint&, const ForceArrays&,
                                           const std::int32_t*, std::size_t);

}  // namespace dsdem::sph
