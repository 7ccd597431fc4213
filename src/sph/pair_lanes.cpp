#include "sph/pair_lanes.hpp"

#include <immintrin.h>

namespace dsdem::sph {

bool pair_lanes_avx2() {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}

template <bool fourtakas>
void density_lanes_scalar(const DensityPairConstants& k, const DensityPoint& pi, double vi, const DensityArrays& a,
                          const std::int32_t* js, DensityLanes& out) {
  for (int l = 0; l < 4; ++l) {
    const auto j = static_cast<std::size_t>(js[l]);
    const DensityPairTerms t =
        density_pair<fourtakas>(k, pi, DensityPoint{a.x[j], a.y[j], a.vx[j], a.vy[j], a.rho[j], a.gx[j], a.gy[j]});
    out.f[l] = t.f;
    out.ti[l] = t.c + t.q * a.vol[j];
    out.tj[l] = t.c - t.q * vi;
  }
}

template <bool grad>
void force_lanes_scalar(const ForcePairConstants& k, const ForcePoint& pi, double vi, const ForceArrays& a,
                        const std::int32_t* js, const double* f, ForceLanes& out) {
  for (int l = 0; l < 4; ++l) {
    const auto j = static_cast<std::size_t>(js[l]);
    const ForcePairTerms t = force_pair<grad>(k, pi, ForcePoint{a.x[j], a.y[j], a.vx[j], a.vy[j], a.rho[j], a.p[j]}, f[l]);
    const double vj = a.vol[j];
    out.ax[l] = t.ax;
    out.ay[l] = t.ay;
    const double w[5] = {t.xx, t.xy, t.yy, t.sx, t.sy};
    for (int c = 0; c < 5; ++c) {
      out.wi[c][l] = vj * w[c];
      out.wj[c][l] = vi * w[c];
    }
  }
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
DSDEM_LANES V div(V a, V b) { return _mm256_div_pd(a, b); }
DSDEM_LANES V neg(V a) { return _mm256_xor_pd(a, all(-0.0)); }
DSDEM_LANES V abs(V a) { return _mm256_andnot_pd(all(-0.0), a); }

// wendland_gradient_factor: q = sqrt(r2) / h, t = 1 - q/2, u = max(t, 0), c u^3.
DSDEM_LANES V gradient_factor(V r2, double inv_h, double c) {
  const V q = mul(_mm256_sqrt_pd(r2), all(inv_h));
  const V t = sub(all(1.0), mul(all(0.5), q));
  const V u = mul(all(0.5), add(t, abs(t)));
  return mul(mul(mul(all(c), u), u), u);
}
}  // namespace

template <bool fourtakas>
void density_lanes_avx2(const DensityPairConstants& k, const DensityPoint& pi,
                                                        double vi, const DensityArrays& a, const std::int32_t* js,
                                                        DensityLanes& out) {
  const V dx = sub(all(pi.x), gather(a.x, js)), dy = sub(all(pi.y), gather(a.y, js));
  const V rho_j = gather(a.rho, js);
  const V f = gradient_factor(add(mul(dx, dx), mul(dy, dy)), k.inv_h, k.grad_c);
  const V vr = add(mul(sub(all(pi.vx), gather(a.vx, js)), dx), mul(sub(all(pi.vy), gather(a.vy, js)), dy));
  const V c = mul(mul(all(k.mass), f), vr);
  const V diffusion = mul(all(-2.0 * k.delta_h_c0), f);  // density_diffusion without its rho difference
  V q;
  if constexpr (fourtakas) {
    // hydrostatic_density_difference(-(g . r), rho_i, rho_j): rho g.r_ji / (c0^2 (rho/rho0)^6).
    const V g_dot = neg(add(mul(all(k.gx), dx), mul(all(k.gy), dy)));
    const V rho = mul(all(0.5), add(all(pi.rho), rho_j));
    const V r = div(rho, all(k.rho0));
    const V r2 = mul(r, r);
    const V rho_h = div(mul(rho, g_dot), mul(mul(mul(all(k.c0 * k.c0), r2), r2), r2));
    q = mul(diffusion, sub(sub(rho_j, all(pi.rho)), rho_h));
  } else {
    const V gsum =
        neg(add(mul(add(all(pi.gx), gather(a.gx, js)), dx), mul(add(all(pi.gy), gather(a.gy, js)), dy)));
    q = add(mul(diffusion, sub(rho_j, all(pi.rho))), mul(mul(all(k.delta_h_c0), f), gsum));
  }
  _mm256_storeu_pd(out.f, f);
  _mm256_storeu_pd(out.ti, add(c, mul(q, gather(a.vol, js))));
  _mm256_storeu_pd(out.tj, sub(c, mul(q, all(vi))));
}

template <bool grad>
void force_lanes_avx2(const ForcePairConstants& k, const ForcePoint& pi, double vi,
                                                      const ForceArrays& a, const std::int32_t* js, const double* fp,
                                                      ForceLanes& out) {
  const V dx = sub(all(pi.x), gather(a.x, js)), dy = sub(all(pi.y), gather(a.y, js));
  const V rho_j = gather(a.rho, js), f = _mm256_loadu_pd(fp);
  const V vr = add(mul(sub(all(pi.vx), gather(a.vx, js)), dx), mul(sub(all(pi.vy), gather(a.vy, js)), dy));
  const V r2 = add(mul(dx, dx), mul(dy, dy));
  // artificial_viscosity: -2 alpha c h min(v.r, 0) / ((r^2 + 0.01 h^2) (rho_i + rho_j)).
  const V visc = div(mul(all(-2.0 * k.alpha_c * k.h), mul(all(0.5), sub(vr, abs(vr)))),
                     mul(add(r2, all(0.01 * k.h * k.h)), add(all(pi.rho), rho_j)));
  const V pressure = div(add(all(pi.p), gather(a.p, js)), mul(all(pi.rho), rho_j));  // pressure_term
  const V coef = mul(mul(all(-k.mass), add(pressure, visc)), f);
  _mm256_storeu_pd(out.ax, mul(coef, dx));
  _mm256_storeu_pd(out.ay, mul(coef, dy));
  const V vj = gather(a.vol, js), vi4 = all(vi);
  V w[5];
  if constexpr (grad) {
    const V fdx = mul(f, dx), fdy = mul(f, dy), dr = sub(rho_j, all(pi.rho));
    w[0] = mul(fdx, dx);
    w[1] = mul(fdx, dy);
    w[2] = mul(fdy, dy);
    w[3] = mul(dr, fdx);
    w[4] = mul(dr, fdy);
  } else {
    for (V& x : w) x = all(0.0);
  }
  for (int c = 0; c < 5; ++c) {
    _mm256_storeu_pd(out.wi[c], mul(vj, w[c]));
    _mm256_storeu_pd(out.wj[c], mul(vi4, w[c]));
  }
}
template void density_lanes_avx2<true>(const DensityPairConstants&, const DensityPoint&, double, const DensityArrays&,
                                       const std::int32_t*, DensityLanes&);
template void density_lanes_avx2<false>(const DensityPairConstants&, const DensityPoint&, double, const DensityArrays&,
                                        const std::int32_t*, DensityLanes&);
template void force_lanes_avx2<true>(const ForcePairConstants&, const ForcePoint&, double, const ForceArrays&,
                                     const std::int32_t*, const double*, ForceLanes&);
template void force_lanes_avx2<false>(const ForcePairConstants&, const ForcePoint&, double, const ForceArrays&,
                                      const std::int32_t*, const double*, ForceLanes&);
#undef DSDEM_LANES
#pragma GCC pop_options

template void density_lanes_scalar<true>(const DensityPairConstants&, const DensityPoint&, double,
                                         const DensityArrays&, const std::int32_t*, DensityLanes&);
template void density_lanes_scalar<false>(const DensityPairConstants&, const DensityPoint&, double,
                                          const DensityArrays&, const std::int32_t*, DensityLanes&);
template void force_lanes_scalar<true>(const ForcePairConstants&, const ForcePoint&, double, const ForceArrays&,
                                       const std::int32_t*, const double*, ForceLanes&);
template void force_lanes_scalar<false>(const ForcePairConstants&, const ForcePoint&, double, const ForceArrays&,
                                        const std::int32_t*, const double*, ForceLanes&);

}  // namespace dsdem::sph
