#pragma once
// std::max and std::min of doubles as one MAXSD / MINSD instruction, never a branch: the
// same value for every input, NaN and signed zeros included, as (a < b) ? b : a and
// (b < a) ? b : a (the instructions return their second operand on equal or unordered
// inputs). GCC 12 compiles many std::max / std::min of the joint law as branches, and
// the damaged joints' mixed states mispredict them. Used where the data decide at
// random: the joint law's general branch; not its elastic fast path, where the
// branches predict well and MAXSD's latency would cost more than it saves.
#include <algorithm>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace dsdem {

inline double branchless_max(double a, double b) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(b), _mm_set_sd(a)));
#else
  return std::max(a, b);
#endif
}

inline double branchless_min(double a, double b) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_min_sd(_mm_set_sd(b), _mm_set_sd(a)));
#else
  return std::min(a, b);
#endif
}

// std::clamp(v, lo, hi) for lo <= hi (or either NaN, where both give v unless v < lo).
inline double branchless_clamp(double v, double lo, double hi) { return branchless_min(branchless_max(v, lo), hi); }

}  // namespace dsdem
