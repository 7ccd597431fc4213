#pragma once
// Execution layer: reductions that give bit-identical results for any thread count. The
// sum is split into fixed-size chunks (independent of the number of threads), each chunk
// summed in order, and the chunk sums added serially (docs/developer-guide.md §3).
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <cstddef>
#include <utility>
#include <vector>

#include "model/types.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace dsdem::exec {

// Small, so that a thread's chunks end at most 63 indices past its share of the node loops
// (see deterministic_sums); the partial sums cost K doubles per 64 indices.
constexpr std::size_t kReductionChunk = 64;

// Boundaries b[0] = 0 <= b[1] <= ... <= b[T] = n of T contiguous index ranges of [0, n),
// range k holding the counted items of ranks floor(total cum[k]) up to floor(total
// cum[k + 1]) (cum: cumulative shares, cum[0] = 0, cum[T] = 1; prefix[i]: counted items
// before index i, size n + 1, total = prefix[n]). Shares of the costly items wherever
// they are numbered: a static split of the index range can give one thread all of them.
inline void counted_share_bounds(std::span<const Index> prefix, std::span<const double> cum,
                                 std::vector<std::size_t>& bounds) {
  const std::size_t n = prefix.size() - 1, T = cum.size() - 1;
  const double total = static_cast<double>(prefix[n]);
  bounds.resize(T + 1);
  bounds[0] = 0;
  for (std::size_t k = 1; k < T; ++k) {
    const auto rank = static_cast<Index>(std::floor(total * cum[k]));
    bounds[k] = static_cast<std::size_t>(std::lower_bound(prefix.begin(), prefix.end(), rank) - prefix.begin());
    bounds[k] = std::max(bounds[k], bounds[k - 1]);
  }
  bounds[T] = n;
}

namespace detail {
// Thread t of T: the chunks [first, end) of [0, n) that start in [n t / T, n (t + 1) / T).
inline std::pair<std::size_t, std::size_t> own_chunks(std::size_t n, std::size_t t, std::size_t T) {
  constexpr std::size_t C = kReductionChunk;
  auto first_chunk = [n, T](std::size_t k) { return (n * k / T + C - 1) / C; };  // at or after n k / T
  return {first_chunk(t), first_chunk(t + 1)};
}
// Thread t of T: its chunks from bounds (T + 1 chunk bounds, ascending, the last one the
// chunk count) when given for T threads, else own_chunks().
inline std::pair<std::size_t, std::size_t> chunks_of(std::size_t n, std::size_t t, std::size_t T,
                                                     std::span<const std::size_t> bounds) {
  if (bounds.size() == T + 1) return {bounds[t], bounds[t + 1]};
  return own_chunks(n, t, T);
}
// The indices of those chunks, [begin, end).
inline std::pair<std::size_t, std::size_t> chunk_indices(std::size_t n, std::size_t t, std::size_t T,
                                                         std::span<const std::size_t> bounds) {
  const auto [c_begin, c_end] = chunks_of(n, t, T, bounds);
  return {std::min(n, c_begin * kReductionChunk), std::min(n, c_end * kReductionChunk)};
}
// Thread t of T: the partial sums (K per chunk, into partial) of its chunks (chunks_of),
// each chunk summed in index order.
template <std::size_t K, class Term>
void sum_own_chunks(std::size_t n, const Term& term, double* partial, std::size_t t, std::size_t T,
                    std::span<const std::size_t> bounds = {}) {
  constexpr std::size_t C = kReductionChunk;
  const auto [c_begin, c_end] = chunks_of(n, t, T, bounds);
  for (std::size_t c = c_begin; c < c_end; ++c) {
    const std::size_t end = std::min(n, (c + 1) * C);
    std::array<double, K> s{};
    for (std::size_t i = c * C; i < end; ++i) {
      const std::array<double, K> v = term(i);
      for (std::size_t k = 0; k < K; ++k) s[k] += v[k];
    }
    for (std::size_t k = 0; k < K; ++k) partial[K * c + k] = s[k];
  }
}
// The chunks' partial sums added in chunk order.
template <std::size_t K>
std::array<double, K> add_partials(const double* partial, std::size_t chunks) {
  std::array<double, K> total{};
  for (std::size_t c = 0; c < chunks; ++c)
    for (std::size_t k = 0; k < K; ++k) total[k] += partial[K * c + k];
  return total;
}
inline std::size_t reduction_chunks(std::size_t n) { return (n + kReductionChunk - 1) / kReductionChunk; }
// This thread's number and its team's size ({0, 1} outside a parallel region).
inline std::pair<std::size_t, std::size_t> thread_in_team() {
#ifdef _OPENMP
  return {static_cast<std::size_t>(omp_get_thread_num()), static_cast<std::size_t>(omp_get_num_threads())};
#else
  return {0, 1};
#endif
}
}  // namespace detail

// K sums over the same index range in one pass (one parallel region instead of K);
// term(i) returns std::array<double, K>. Fixed chunks of kReductionChunk indices, each
// summed in index order, then the chunk sums in chunk order: the same bits for any
// thread count. scratch holds K doubles per chunk.
// Thread t of T sums the chunks that start in [n t / T, n (t + 1) / T), the share of the
// node loops (kick, velocities) in which it wrote these nodes, so each node's cache lines
// stay on one core.
template <std::size_t K, class Term>
std::array<double, K> deterministic_sums(std::size_t n, Term term, std::vector<double>& scratch, bool parallel = true) {
  const std::size_t chunks = detail::reduction_chunks(n);
  if (scratch.size() < K * chunks) scratch.resize(K * chunks);
  double* partial = scratch.data();
#pragma omp parallel if (parallel && chunks > 1)
  {
    const auto [t, T] = detail::thread_in_team();
    detail::sum_own_chunks<K>(n, term, partial, t, T);
  }
  return detail::add_partials<K>(partial, chunks);
}

// Sums over two index ranges (the nodes and the triangles) in one parallel region: each
// result the bits of deterministic_sums on its range, one fork and join instead of two.
// prepare1(begin, end) runs first, on the indices of range 1 whose chunks this thread
// sums: whole chunks, each index on exactly one thread. So a node loop whose results the
// sums read (the velocity update) runs in the same region with no barrier, as long as
// term1(i) reads only index i of what prepare1 writes. chunks1_of: range 1's chunk bounds
// per thread (detail::chunks_of; the solver's node chunks), when given for this team.
template <std::size_t K1, std::size_t K2, class Prepare1, class Term1, class Term2>
std::pair<std::array<double, K1>, std::array<double, K2>> deterministic_sums(std::size_t n1, Prepare1 prepare1,
                                                                             Term1 term1, std::size_t n2,
                                                                             Term2 term2, std::vector<double>& scratch,
                                                                             bool parallel = true,
                                                                             std::span<const std::size_t> chunks1_of = {}) {
  const std::size_t chunks1 = detail::reduction_chunks(n1), chunks2 = detail::reduction_chunks(n2);
  if (scratch.size() < K1 * chunks1 + K2 * chunks2) scratch.resize(K1 * chunks1 + K2 * chunks2);
  double* partial1 = scratch.data();
  double* partial2 = partial1 + K1 * chunks1;
#pragma omp parallel if (parallel && (chunks1 > 1 || chunks2 > 1))
  {
    const auto [t, T] = detail::thread_in_team();
    const auto [begin1, end1] = detail::chunk_indices(n1, t, T, chunks1_of);
    prepare1(begin1, end1);
    detail::sum_own_chunks<K1>(n1, term1, partial1, t, T, chunks1_of);
    detail::sum_own_chunks<K2>(n2, term2, partial2, t, T);
  }
  return {detail::add_partials<K1>(partial1, chunks1), detail::add_partials<K2>(partial2, chunks2)};
}
template <std::size_t K1, std::size_t K2, class Term1, class Term2>
std::pair<std::array<double, K1>, std::array<double, K2>> deterministic_sums(std::size_t n1, Term1 term1, std::size_t n2,
                                                                             Term2 term2, std::vector<double>& scratch,
                                                                             bool parallel = true) {
  return deterministic_sums<K1, K2>(n1, [](std::size_t, std::size_t) {}, term1, n2, term2, scratch, parallel);
}

}  // namespace dsdem::exec
