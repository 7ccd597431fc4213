#pragma once
// Reductions that give bit-identical results for any thread count: the sum is split
// into fixed-size chunks (independent of the number of threads), each chunk summed in
// order, and the chunk sums added serially (DESIGN.md §9, issue 7).
#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace dsdem {

constexpr std::size_t kReductionChunk = 2048;

// The automatic choice between one thread and OpenMP (Solver::probe_parallel): keep the
// threads unless their median step time is above the serial median by more than
// `margin`. Medians, not sums: a few steps slowed by something else (a broad-phase
// rebuild, a page-fault burst) in one window must not decide. The margin, because on a
// virtual machine the second core's speed comes and goes: measured on late Dr2 windows,
// parallel medians of 1.6 to 2.9 ms against serial 2.5 to 2.7 ms; when the two are
// close, one thread gains little, and the threads gain much once the core is back.
template <std::size_t N>
bool choose_parallel(std::array<double, N> serial, std::array<double, N> parallel, double margin = 1.1) {
  static_assert(N > 0);
  auto median = [](std::array<double, N>& t) {
    std::sort(t.begin(), t.end());
    return N % 2 == 1 ? t[N / 2] : 0.5 * (t[N / 2 - 1] + t[N / 2]);
  };
  return median(parallel) <= margin * median(serial);
}

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

// K sums over the same index range in one pass (one parallel region instead of K);
// term(i) returns std::array<double, K>. Same fixed chunking, so each sum is
// bit-identical for any thread count. scratch holds K doubles per chunk.
template <std::size_t K, class Term>
std::array<double, K> deterministic_sums(std::size_t n, Term term, std::vector<double>& scratch, bool parallel = true) {
  const std::size_t chunks = (n + kReductionChunk - 1) / kReductionChunk;
  if (scratch.size() < K * chunks) scratch.resize(K * chunks);
#pragma omp parallel for schedule(static) if (parallel && chunks > 4)
  for (std::ptrdiff_t c = 0; c < static_cast<std::ptrdiff_t>(chunks); ++c) {
    const std::size_t begin = static_cast<std::size_t>(c) * kReductionChunk;
    const std::size_t end = begin + kReductionChunk < n ? begin + kReductionChunk : n;
    std::array<double, K> s{};
    for (std::size_t i = begin; i < end; ++i) {
      const std::array<double, K> t = term(i);
      for (std::size_t k = 0; k < K; ++k) s[k] += t[k];
    }
    for (std::size_t k = 0; k < K; ++k) scratch[K * static_cast<std::size_t>(c) + k] = s[k];
  }
  std::array<double, K> total{};
  for (std::size_t c = 0; c < chunks; ++c)
    for (std::size_t k = 0; k < K; ++k) total[k] += scratch[K * c + k];
  return total;
}

}  // namespace dsdem
