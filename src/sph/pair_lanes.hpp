#pragma once
// One fluid particle's sums over its partners (sph::Fluid's pair passes, docs/theory.md §11),
// four pairs at a time: the terms of pair_terms.hpp evaluated lane by lane (AVX2 where the
// CPU has it: each lane does the scalar kernels' operations in their order, without fused
// multiply-adds) and summed in four lanes, lane l taking partners l, l + 4, l + 8, ... in
// list order, the lanes then added as (s0 + s2) + (s1 + s3). The *_scalar functions do the
// same in the same order: the same bits on any CPU. The sums depend only on the list
// (the partners within the support, ascending), not on the thread count. A partner's values
// come from its record, one cache line (DensityRecord, ForceRecord).
#include <cstddef>
#include <cstdint>

#include "sph/pair_terms.hpp"

namespace dsdem::sph {

// A partner's values read by a pass, packed in one cache line: the lanes load four
// partners' lines and transpose them, instead of gathering each value from its own array.
struct alignas(64) DensityRecord {
  double x, y, vx, vy, rho, gx, gy, vol;
};
struct alignas(64) ForceRecord {
  double x, y, vx, vy, rho, p, vol, unused;
};

// True when the CPU runs the AVX2 lanes.
bool pair_lanes_avx2();

// drho_i/dt's fluid part, sum over the partners js[0..n) of c + q V_j (density_pair(i, j));
// each pair's F (wendland_gradient_factor) written to fs[0..n) for the force pass.
template <bool fourtakas>
double density_sum_scalar(const DensityPairConstants& k, const DensityPoint& pi, const DensityRecord* a,
                          const std::int32_t* js, std::size_t n, double* fs);
template <bool fourtakas>
double density_sum_avx2(const DensityPairConstants& k, const DensityPoint& pi, const DensityRecord* a,
                        const std::int32_t* js, std::size_t n, double* fs);

// i's force sums over the partners js[0..n) with their F fs[0..n) from the density pass (the
// same positions): the accelerations of force_pair(i, j), M = -sum V_j F r r^T and
// sum V_j (rho_j - rho_i) F r.
template <bool grad>
ForceSums force_sum_scalar(const ForcePairConstants& k, const ForcePoint& pi, const ForceRecord* a,
                           const std::int32_t* js, const double* fs, std::size_t n);
template <bool grad>
ForceSums force_sum_avx2(const ForcePairConstants& k, const ForcePoint& pi, const ForceRecord* a,
                         const std::int32_t* js, const double* fs, std::size_t n);

}  // namespace dsdem::sph
