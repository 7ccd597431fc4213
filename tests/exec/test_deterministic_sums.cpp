// The execution layer's thread choice, splits and deterministic sums (docs/developer-guide.md §3):
// the same bits for any thread count and chunk count.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "exec/deterministic_sums.hpp"
#include "exec/team.hpp"
#include "exec/work_split.hpp"

using namespace dsdem;
using namespace dsdem::exec;

// The timed thread choice compares medians: one slow step in either window (a broad-phase
// rebuild, a page-fault burst) does not decide; a window that is slow throughout does,
// once the threads are slower than one thread by more than the margin (10 %).
TEST(ThreadChoice, MedianStepTimeDecidesNotOneOutlier) {
  const std::array<double, 8> serial{3.0, 3.1, 2.9, 3.0, 3.2, 3.0, 2.9, 3.1};  // ms
  std::array<double, 8> parallel{1.7, 1.8, 1.7, 1.7, 1.8, 1.7, 1.7, 1.8};
  EXPECT_TRUE(choose_parallel(serial, parallel));
  parallel[0] = 30.0;  // one step 17x slower: a sum would say 1 thread (43.4 > 24.4 ms)
  EXPECT_TRUE(choose_parallel(serial, parallel));
  std::array<double, 8> outlier_serial = serial;
  outlier_serial[3] = 0.1;  // one impossibly fast serial step does not flip it either
  EXPECT_TRUE(choose_parallel(outlier_serial, parallel));
  const std::array<double, 8> busy{9.0, 8.5, 30.0, 9.5, 8.8, 1.8, 9.1, 9.9};  // threads waiting at barriers
  EXPECT_FALSE(choose_parallel(serial, busy));
  // Within the margin the threads stay (a slow spell of the second core, measured on Dr2:
  // serial median 2.59 ms, parallel 2.70 ms); beyond it, one thread.
  const std::array<double, 8> dr2_serial{5.20, 3.02, 2.58, 2.59, 2.55, 2.55, 2.59, 2.58};
  const std::array<double, 8> dr2_close{2.89, 2.67, 2.71, 2.69, 2.65, 2.62, 2.98, 2.92};
  const std::array<double, 8> dr2_slow{3.02, 2.99, 2.78, 3.18, 3.37, 3.45, 2.87, 2.97};
  EXPECT_TRUE(choose_parallel(dr2_serial, dr2_close));
  EXPECT_FALSE(choose_parallel(dr2_serial, dr2_slow));
  EXPECT_TRUE(choose_parallel(serial, serial));  // a tie keeps the threads
}

// The own-triangle loop splits its work by count, not by index: Dr2 numbers its 3 233
// own (zone A) triangles first and its 5 385 shared ones after, and a split of the index
// range gave one thread all of the own triangles. Shares come from the threads' speeds
// (exec/work_split.hpp).
TEST(WorkSplit, SharesOfTheCountedItemsWhereverTheyAreNumbered) {
  auto prefix_of = [](std::size_t n, auto counted) {
    std::vector<Index> prefix(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + (counted(i) ? 1 : 0);
    return prefix;
  };
  const std::size_t n = 8618, n_own = 3233;
  auto own_first = [&](std::size_t i) { return i < n_own; };
  const std::vector<Index> prefix = prefix_of(n, own_first);
  std::vector<std::size_t> b;
  std::vector<double> cum;
  for (int T : {1, 2, 3, 4}) {
    cumulative_shares(std::vector<double>(static_cast<std::size_t>(T), 1.0), cum);
    counted_share_bounds(prefix, cum, b);
    ASSERT_EQ(b.size(), static_cast<std::size_t>(T) + 1);
    EXPECT_EQ(b.front(), 0u);
    EXPECT_EQ(b.back(), n);
    for (int k = 0; k < T; ++k) {
      std::size_t share = 0;
      for (std::size_t i = b[k]; i < b[k + 1]; ++i) share += own_first(i) ? 1 : 0;
      EXPECT_NEAR(static_cast<double>(share), static_cast<double>(n_own) / T, 1.0) << "T = " << T << ", range " << k;
    }
  }
  // Unequal shares: 1/4 and 3/4 of the own triangles.
  counted_share_bounds(prefix, std::vector<double>{0.0, 0.25, 1.0}, b);
  EXPECT_EQ(b, (std::vector<std::size_t>{0, 808, n}));
  // Every third index counted, and none at all: ranges still tile [0, n).
  counted_share_bounds(prefix_of(10, [](std::size_t i) { return i % 3 == 0; }), std::vector<double>{0.0, 0.5, 1.0}, b);
  EXPECT_EQ(b, (std::vector<std::size_t>{0, 4, 10}));  // counted 0, 3 | 6, 9
  counted_share_bounds(prefix_of(5, [](std::size_t) { return false; }), std::vector<double>{0.0, 0.5, 1.0}, b);
  EXPECT_EQ(b, (std::vector<std::size_t>{0, 0, 5}));
  counted_share_bounds(std::vector<Index>{0}, std::vector<double>{0.0, 0.5, 1.0}, b);
  EXPECT_EQ(b, (std::vector<std::size_t>{0, 0, 0}));
}

// The energy sums (deterministic_sums) run on the threads from two chunks on, each thread
// on the chunks that start in its share of the indices (reading the other thread's nodes
// would send their lines across the cores). Chunk counts from 1 to 5 and 16,
// shares that end inside a chunk, on 1, 2 and 3 threads: the bits of the serial sum of
// chunk sums, each chunk summed in index order.
TEST(DeterministicSums, BitIdenticalForAnyThreadCountAndChunkCount) {
  std::vector<double> scratch;
  for (const std::size_t n : {std::size_t{1}, kReductionChunk, kReductionChunk + 1, 2 * kReductionChunk + 17,
                              4 * kReductionChunk, 4 * kReductionChunk + 5, 16 * kReductionChunk - 3}) {
    // Terms of mixed magnitude and sign, so that any other order of addition changes bits.
    auto term = [](std::size_t i) {
      const double x = static_cast<double>(i);
      return std::array<double, 2>{1.0 / (1.0 + x) * (i % 3 == 0 ? -1e8 : 1.0), 1e-3 * x * x + (i % 7 == 0 ? 1e12 : 0.0)};
    };
    std::array<double, 2> expected{};
    for (std::size_t c = 0; c * kReductionChunk < n; ++c) {
      std::array<double, 2> s{};
      for (std::size_t i = c * kReductionChunk; i < std::min(n, (c + 1) * kReductionChunk); ++i)
        for (int k = 0; k < 2; ++k) s[k] += term(i)[k];
      for (int k = 0; k < 2; ++k) expected[k] += s[k];
    }
    for (const int threads : {1, 2, 3}) {
#ifdef _OPENMP
      omp_set_num_threads(threads);
#endif
      for (const bool parallel : {false, true}) {
        std::fill(scratch.begin(), scratch.end(), std::nan(""));  // a chunk no thread summed shows
        const std::array<double, 2> got = deterministic_sums<2>(n, term, scratch, parallel);
        for (int k = 0; k < 2; ++k)
          EXPECT_EQ(std::memcmp(&got[k], &expected[k], sizeof(double)), 0)
              << "n = " << n << ", threads = " << threads << ", parallel = " << parallel << ", sum " << k;
      }
    }
#ifdef _OPENMP
    omp_set_num_threads(1);
#endif
  }
}

// The energies' node and triangle sums in one region (deterministic_sums over two ranges)
// give each range's bits of the one-range sums, on 1 to 3 threads, whichever range is
// longer, one of them empty or of a single chunk.
// The prepare step fused into the sums (the velocity update): every index of
// range 1 prepared exactly once, by the thread that then sums it, before its term is read.
TEST(DeterministicSums, PrepareRunsOnceOnEachIndexBeforeTheThreadSumsIt) {
  const std::size_t C = kReductionChunk;
  std::vector<double> scratch, scratch_alone;
  for (const std::size_t n1 : {std::size_t{0}, std::size_t{3}, C, 5 * C + 3, 11 * C - 5}) {
    const std::size_t n2 = 2 * C + 1;
    auto term2 = [](std::size_t i) { return std::array<double, 1>{1.0 / (1.0 + static_cast<double>(i))}; };
    // Each prepared value is i + 0.5, and i % 3 == 0 made large: a term read before its
    // index was prepared (0) or an index prepared twice (2 i + 1) changes the sum's bits.
    auto value = [](std::size_t i) { return (static_cast<double>(i) + 0.5) * (i % 3 == 0 ? 1e9 : 1e-3); };
#ifdef _OPENMP
    omp_set_num_threads(1);
#endif
    const std::array<double, 1> expected1 =
        deterministic_sums<1>(n1, [&](std::size_t i) { return std::array<double, 1>{value(i)}; }, scratch_alone, false);
    for (const int threads : {1, 2, 3}) {
#ifdef _OPENMP
      omp_set_num_threads(threads);
#endif
      std::vector<double> prepared(n1, 0.0);
      std::vector<int> times(n1, 0);
      const auto prepare = [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          prepared[i] += value(i);
          ++times[i];
        }
      };
      const auto read = [&](std::size_t i) { return std::array<double, 1>{prepared[i]}; };
      const auto [got1, got2] = deterministic_sums<1, 1>(n1, prepare, read, n2, term2, scratch, true);
      for (std::size_t i = 0; i < n1; ++i) ASSERT_EQ(times[i], 1) << "index " << i << " of " << n1 << ", threads " << threads;
      EXPECT_EQ(std::memcmp(&got1[0], &expected1[0], sizeof(double)), 0) << n1 << " threads " << threads;
      // Range 1's chunks given per thread (the solver's node chunks from the contact
      // partition): uneven, one thread with none, or bounds for another thread count
      // (ignored). Each index still prepared once, the same bits.
      const std::size_t chunks = (n1 + C - 1) / C;
      std::vector<std::vector<std::size_t>> bound_sets{std::vector<std::size_t>(threads + 1, chunks),
                                                       std::vector<std::size_t>(threads + 2, 0)};
      bound_sets[0][0] = 0;
      if (threads > 1) bound_sets[0][1] = chunks / 3;
      bound_sets[1].back() = chunks;
      for (const auto& bounds : bound_sets) {
        std::fill(prepared.begin(), prepared.end(), 0.0);
        std::fill(times.begin(), times.end(), 0);
        const auto [b1, b2] = deterministic_sums<1, 1>(n1, prepare, read, n2, term2, scratch, true, bounds);
        for (std::size_t i = 0; i < n1; ++i) ASSERT_EQ(times[i], 1) << "index " << i << " of " << n1 << ", bounds";
        EXPECT_EQ(std::memcmp(&b1[0], &expected1[0], sizeof(double)), 0) << n1 << " threads " << threads;
        EXPECT_EQ(std::memcmp(&b2[0], &got2[0], sizeof(double)), 0) << n1 << " threads " << threads;
      }
      const std::array<double, 1> expected2 = deterministic_sums<1>(n2, term2, scratch_alone, false);
      EXPECT_EQ(std::memcmp(&got2[0], &expected2[0], sizeof(double)), 0) << n1 << " threads " << threads;
    }
  }
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
}

TEST(DeterministicSums, TwoRangesInOneRegionGiveTheBitsOfEachRangeAlone) {
  auto term1 = [](std::size_t i) {
    const double x = static_cast<double>(i);
    return std::array<double, 2>{1.0 / (1.0 + x) * (i % 3 == 0 ? -1e8 : 1.0), 1e-3 * x * x + (i % 7 == 0 ? 1e12 : 0.0)};
  };
  auto term2 = [](std::size_t i) {
    return std::array<double, 1>{std::sin(static_cast<double>(i)) * (i % 5 == 0 ? 1e9 : 1e-2)};
  };
  const std::size_t C = kReductionChunk;
  const std::vector<std::pair<std::size_t, std::size_t>> sizes{{0, 5 * C + 3}, {7 * C + 1, 0}, {C, 3 * C + 9},
                                                               {11 * C - 5, 2 * C}, {3, 4}};
  std::vector<double> scratch, scratch_alone;
  for (const auto& [n1, n2] : sizes) {
#ifdef _OPENMP
    omp_set_num_threads(1);
#endif
    const std::array<double, 2> expected1 = deterministic_sums<2>(n1, term1, scratch_alone, false);
    const std::array<double, 1> expected2 = deterministic_sums<1>(n2, term2, scratch_alone, false);
    for (const int threads : {1, 2, 3}) {
#ifdef _OPENMP
      omp_set_num_threads(threads);
#endif
      std::fill(scratch.begin(), scratch.end(), std::nan(""));
      const auto [got1, got2] = deterministic_sums<2, 1>(n1, term1, n2, term2, scratch, true);
      for (int k = 0; k < 2; ++k)
        EXPECT_EQ(std::memcmp(&got1[k], &expected1[k], sizeof(double)), 0) << n1 << " " << n2 << " threads " << threads;
      EXPECT_EQ(std::memcmp(&got2[0], &expected2[0], sizeof(double)), 0) << n1 << " " << n2 << " threads " << threads;
    }
  }
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
}
