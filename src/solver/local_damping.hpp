#pragma once
// Cundall's local non-viscous damping (docs/theory.md §9; Cundall 1987, as FLAC and UDEC
// use it to reach static equilibrium): each velocity component is opposed by a force of
// the unbalanced force's magnitude in that component times the coefficient (0.8 in FLAC).
// Unlike mass-proportional damping it vanishes at equilibrium and does not hold back a
// mass that keeps moving under a steady force, and it damps every mode by the same
// fraction per cycle, whatever its frequency.
#include <cmath>

namespace dsdem::solver {

// The damping force at a node of unbalanced force f moving at v: -coefficient |f_d| sign(v_d)
// per component d (a component at rest gets none). Any dimension (Eigen fixed vectors).
template <class Vec>
Vec local_damping_force(const Vec& f, const Vec& v, double coefficient) {
  Vec fd;
  for (int d = 0; d < static_cast<int>(Vec::RowsAtCompileTime); ++d) {
    const double magnitude = coefficient * std::abs(f[d]);
    fd[d] = v[d] > 0.0 ? -magnitude : v[d] < 0.0 ? magnitude : 0.0;
  }
  return fd;
}

}  // namespace dsdem::solver
