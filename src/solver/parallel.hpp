#pragma once
// Reductions that give bit-identical results for any thread count: the sum is split
// into fixed-size chunks (independent of the number of threads), each chunk summed in
// order, and the chunk sums added serially (DESIGN.md §9, issue 7).
#include <cstddef>
#include <vector>

namespace dsdem {

constexpr std::size_t kReductionChunk = 2048;

template <class Term>
double deterministic_sum(std::size_t n, Term term, std::vector<double>& scratch) {
  const std::size_t chunks = (n + kReductionChunk - 1) / kReductionChunk;
  if (scratch.size() < chunks) scratch.resize(chunks);
#pragma omp parallel for schedule(static) if (chunks > 4)
  for (std::ptrdiff_t c = 0; c < static_cast<std::ptrdiff_t>(chunks); ++c) {
    const std::size_t begin = static_cast<std::size_t>(c) * kReductionChunk;
    const std::size_t end = begin + kReductionChunk < n ? begin + kReductionChunk : n;
    double s = 0.0;
    for (std::size_t i = begin; i < end; ++i) s += term(i);
    scratch[static_cast<std::size_t>(c)] = s;
  }
  double total = 0.0;
  for (std::size_t c = 0; c < chunks; ++c) total += scratch[c];
  return total;
}

}  // namespace dsdem
