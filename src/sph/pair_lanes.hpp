#pragma once
// Four fluid pairs (i, j_0..j_3) of sph::Fluid's pair passes at once (DESIGN.md §13): the
// terms of pair_terms.hpp evaluated lane by lane with AVX2 where the CPU has it. Each lane
// does the scalar kernels' operations in the same order (no fused multiply-add), so a lane
// gives the scalar function's bits; the sums that take the terms stay scalar and in order.
// The *_scalar functions are the reference (and the path without AVX2).
#include <cstdint>

#include "sph/pair_terms.hpp"

namespace dsdem::sph {

// The fluid's arrays read by the lanes.
struct DensityArrays {
  const double *x, *y, *vx, *vy, *rho, *gx, *gy, *vol;
};
struct ForceArrays {
  const double *x, *y, *vx, *vy, *rho, *p, *vol;
};

// Pair l: F, drho_i/dt's term c + q V_j and drho_j/dt's term c - q V_i (density_pair).
struct DensityLanes {
  double f[4], ti[4], tj[4];
};
// Pair l: i's acceleration from j (j's is minus it) and the gradient's products F r r^T
// (xx, xy, yy) and (rho_j - rho_i) F r (sx, sy) times V_j (wi, for i's sums) and times V_i
// (wj, for j's), as add_pair() forms them.
struct ForceLanes {
  double ax[4], ay[4], wi[5][4], wj[5][4];
};

// True when the CPU runs the AVX2 lanes.
bool pair_lanes_avx2();

template <bool fourtakas>
void density_lanes_scalar(const DensityPairConstants& k, const DensityPoint& pi, double vi, const DensityArrays& a,
                          const std::int32_t* js, DensityLanes& out);
template <bool fourtakas>
void density_lanes_avx2(const DensityPairConstants& k, const DensityPoint& pi, double vi, const DensityArrays& a,
                        const std::int32_t* js, DensityLanes& out);
// f: the pairs' gradient factors (from the density pass).
template <bool grad>
void force_lanes_scalar(const ForcePairConstants& k, const ForcePoint& pi, double vi, const ForceArrays& a,
                        const std::int32_t* js, const double* f, ForceLanes& out);
template <bool grad>
void force_lanes_avx2(const ForcePairConstants& k, const ForcePoint& pi, double vi, const ForceArrays& a,
                      const std::int32_t* js, const double* f, ForceLanes& out);

}  // namespace dsdem::sph
