#pragma once
// Execution layer: the traversals of the contact phase (docs/theory.md §1 step 5; docs/developer-guide.md §3), each in
// one thread region per call. Physics hands them per-thread kernels; this file alone holds
// their plumbing: the tuned splits, busy timers, barriers, worksharing, the stamps that
// order one partition's runs, and rebalancing. Which thread computes an item changes no
// result (the kernels write their own slots, or sum in a fixed order).
#include <atomic>
#include <cstddef>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>  // _mm_pause
#endif

#include "exec/deterministic_sums.hpp"
#include "exec/team.hpp"
#include "exec/work_split.hpp"

namespace dsdem::exec {

// f(i) for i in [0, n), shared by the threads of the enclosing region (static, no barrier
// after): every thread of the team must call it. Outside a region, all on the caller.
template <class F>
void shared_for_nowait(std::size_t n, F&& f) {
#pragma omp for schedule(static) nowait
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) f(static_cast<std::size_t>(i));
}

// One loop split into contiguous runs, one per thread, tuned from the threads' busy times:
// k(begin, end) on each thread's run of [0, n) returns status bits, ORed together. The
// kernel may also call shared_for_nowait (every thread calls it once).
class TunedRegion {
 public:
  // threads > 1: a region of that many threads; else all on the caller.
  template <class K>
  int run(int threads, std::size_t n, K&& k);
  const TunedSplit& split() const { return split_; }

 private:
  TunedSplit split_;
};

// One partition of a loop's items (e.g. contact triangles and the pairs whose first
// triangle they hold) into per-thread runs, tuned from each thread's busy time over all its
// phases. The kernels, as a class with these members (t of T; T = 1: everything):
//   bool first(int t, int T)              phase 1 of run t; true: stop (every thread sees it)
//   long second(int t, int T, Later& l)   phase 2; before reading a later run's phase-1 data
//                                         it calls l.wait(); returns a count, summed
//   void third(int t, int T, bool stop)   phase 3, after phase 2 on the same thread (the
//                                         first thread sees every run's phase 1 first)
//   void gather(int t, int T)             after a barrier, unless stopped (T > 1 only)
// No thread waits at a barrier for the others' phase 1: a run reads only its own and later
// runs' phase-1 data, after seeing their stamps.
class PartitionedRegion {
  struct alignas(64) Stamp {  // one cache line per thread: each writes its own
    std::atomic<long> call{0};
  };

 public:
  // The stamps of the later runs' phase 1, waited for once.
  class Later {
   public:
    bool seen() const { return seen_; }
    void wait() {
      if (seen_) return;
      for (int u = t_ + 1; u < T_; ++u)
        while (stamps_[u].call.load(std::memory_order_acquire) != call_) {
#if defined(__SSE2__)
          _mm_pause();
#endif
        }
      seen_ = true;
    }

   private:
    friend class PartitionedRegion;
    Later(const Stamp* stamps, long call, int t, int T)
        : stamps_(stamps), call_(call), t_(t), T_(T), seen_(t + 1 >= T) {}
    const Stamp* stamps_;
    long call_;
    int t_, T_;
    bool seen_;
  };
  struct Result {
    bool stopped = false;  // some first() returned true (its runs' gather skipped)
    int threads = 1;       // threads that ran the runs (1: a smaller team than asked for)
    long count = 0;        // the sum of second()'s counts
  };

  // Before run(): the split for `threads` (so the caller can place the runs' bounds).
  void prepare(int threads);
  // Thread u's run of n items: [begin(n, u), begin(n, u + 1)).
  std::size_t begin(std::size_t n, int u) const { return split_.begin(n, u); }
  // Fixed shares instead of tuned ones (TunedSplit::pin).
  void pin(std::vector<double> shares) { split_.pin(std::move(shares)); }
  template <class K>
  Result run(int threads, K& k);

 private:
  TunedSplit split_;
  std::unique_ptr<Stamp[]> stamps_;
  int n_stamps_ = 0;
  long calls_ = 0;
  std::atomic<int> stop_{0};
};

// The contact phase's split path: three loops each split on its own, in one region. The
// kernels, as a class with these members:
//   long filter(int t, int T, std::size_t b, std::size_t e)   items [b, e) of n; a count, summed
//   bool split(int T)              after a barrier: split what follows (false: thread 0 alone)
//   bool scales()                  whether the serial collect + per-item loop below runs
//   void collect(int T)            serial; then item(s) for s in [0, items())
//   std::size_t items() const;  void item(std::size_t s)
//   void prepare(int t, int T, bool split)     each thread, before its pair loop
//   void pairs(int t, int T, bool split, std::span<const double> cum)   cum: the tuned
//                                  cumulative shares of the pair loop (empty: equal shares)
//   void gather(int t, int T)      after a barrier, when split
class SplitRegion {
 public:
  struct Result {
    int threads = 1;     // the team's size
    bool split = false;  // the pair loop ran on several threads
    long count = 0;      // the sum of filter()'s counts
  };
  template <class K>
  Result run(int threads, std::size_t n, K& k);
  std::span<const double> pair_share() const { return pair_split_.share(); }
  void pin_pairs(std::vector<double> shares) { pair_split_.pin(std::move(shares)); }

 private:
  TunedSplit filter_split_, pair_split_;
};

template <class K>
int TunedRegion::run(int threads, std::size_t n, K&& k) {
  split_.prepare(threads);
  int bits = 0;
  bool tuned_team = false;
#pragma omp parallel num_threads(threads) reduction(| : bits) if (threads > 1)
  {
    const auto [th, team] = detail::thread_in_team();
    const int t = static_cast<int>(th);
    const bool tuned = static_cast<int>(team) == threads && team > 1;
    const double busy_from = tuned ? wall_seconds() : 0.0;
    const std::size_t b = tuned ? split_.begin(n, t) : n * th / team;
    const std::size_t e = tuned ? split_.begin(n, t + 1) : n * (th + 1) / team;
    bits |= k(b, e);
    if (tuned) split_.set_busy(t, wall_seconds() - busy_from);
    if (t == 0) tuned_team = tuned;
  }
  if (tuned_team) split_.rebalance();
  return bits;
}

inline void PartitionedRegion::prepare(int threads) {
  split_.prepare(threads);
  if (n_stamps_ < threads) {  // once per thread count: not in the time loop
    stamps_ = std::make_unique<Stamp[]>(static_cast<std::size_t>(threads));
    n_stamps_ = threads;
  }
}

template <class K>
PartitionedRegion::Result PartitionedRegion::run(int threads, K& k) {
  const long call = ++calls_;
  stop_.store(0, std::memory_order_relaxed);
  Result result;
  long count = 0;
  bool tuned_team = false;
#pragma omp parallel num_threads(threads) reduction(+ : count)
  {
    const auto [th, team] = detail::thread_in_team();
    const int t = static_cast<int>(th);
    // A smaller team than asked for (nested parallelism, a thread limit): its first
    // thread alone does everything.
    const int P = static_cast<int>(team) == threads ? threads : 1;
    const int T = P;
    if (t < P) {
      // Busy: all three phases, waits included (a thread that waits for another's phase 1
      // should get less to do).
      const double started = wall_seconds();
      if (k.first(t, T)) stop_.store(1, std::memory_order_relaxed);
      stamps_[t].call.store(call, std::memory_order_release);
      Later later(stamps_.get(), call, t, T);
      count += k.second(t, T, later);
      // The first thread sees every run's phase 1 before phase 3 in any case (its stop flag).
      if (t == 0) later.wait();
      const bool stop = t == 0 && stop_.load(std::memory_order_relaxed) != 0;
      k.third(t, T, stop);
      if (P > 1) split_.set_busy(t, wall_seconds() - started);
      if (t == 0) {
        result.threads = T;
        tuned_team = P > 1;
      }
    }
    // Every thread sees the stop flag after the barrier.
    if (P > 1) {
#pragma omp barrier
      if (stop_.load(std::memory_order_relaxed) == 0) k.gather(t, T);
    }
  }
  result.count = count;
  result.stopped = stop_.load(std::memory_order_relaxed) != 0;
  if (!result.stopped && tuned_team) split_.rebalance();
  return result;
}

template <class K>
SplitRegion::Result SplitRegion::run(int threads, std::size_t n, K& k) {
  if (threads > 1) {
    pair_split_.prepare(threads);
    filter_split_.prepare(threads);
  }
  Result result;
  long count = 0;
#pragma omp parallel num_threads(threads) if (threads > 1) reduction(+ : count)
  {
    const auto [th, team] = detail::thread_in_team();
    const int t = static_cast<int>(th), T = static_cast<int>(team);
    const bool tuned = T == threads && T > 1;
    const std::size_t b = tuned ? filter_split_.begin(n, t) : n * th / team;
    const std::size_t e = tuned ? filter_split_.begin(n, t + 1) : n * (th + 1) / team;
    double busy_from = tuned ? wall_seconds() : 0.0;
    count += k.filter(t, T, b, e);
    if (tuned) filter_split_.set_busy(t, wall_seconds() - busy_from);
    if (t == 0) result.threads = T;
#pragma omp barrier
    // The same on every thread: the worksharing constructs below are met by all or none.
    const bool split = T > 1 && k.split(T);
    if (t == 0) result.split = split;
    if (k.scales()) {
      if (split) {
#pragma omp single
        k.collect(T);
        const auto ns = static_cast<std::ptrdiff_t>(k.items());
#pragma omp for schedule(static)
        for (std::ptrdiff_t s = 0; s < ns; ++s) k.item(static_cast<std::size_t>(s));
      } else if (t == 0) {
        k.collect(T);
        const std::size_t ns = k.items();
        for (std::size_t s = 0; s < ns; ++s) k.item(s);
      }
    }
    k.prepare(t, T, split);
    if (split) busy_from = wall_seconds();
    k.pairs(t, T, split, tuned ? pair_split_.cum() : std::span<const double>());
    if (split) {
      // Busy: the pair loop alone. Every gather starts after the barrier, so the phase
      // ends at the slowest pair loop plus the longest gather (the caller's gather makes
      // the last thread's the longest, whatever the split).
      if (tuned) pair_split_.set_busy(t, wall_seconds() - busy_from);
#pragma omp barrier
      k.gather(t, T);
    }
  }
  result.count = count;
  if (result.threads > 1 && result.threads == threads) {
    if (result.split) pair_split_.rebalance();
    filter_split_.rebalance();
  }
  return result;
}

}  // namespace dsdem::exec
