#pragma once
// Execution layer: splitting a loop between threads by their measured speed. On a VM
// one core often runs slower than the other for a while, and a split by count then
// leaves the faster thread waiting at every barrier. The phases that may give
// any thread any item (the contact pair loop, the element loops: every item writes its
// own slots or its own nodes) keep each thread on a contiguous share, tuned each step;
// which thread computes an item never changes a result.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace dsdem::exec {

// The shares that would make every thread finish together if each kept the rate it
// showed (share / busy seconds), moved `gain` of the way there (one step's timing is
// noisy), each at least 0.1 / T and summing to 1. No timing (busy <= 0 or not finite)
// or sizes that differ: unchanged.
void balance_shares(std::span<double> share, std::span<const double> busy, double gain = 0.1);

// Cumulative shares, normalised: cum[0] = 0, cum[T] = 1 (T = share.size()).
void cumulative_shares(std::span<const double> share, std::vector<double>& cum);

// One loop's split between T threads into contiguous runs, tuned from the threads' busy
// times (balance_shares): prepare(T) before the loop, begin(n, t) .. begin(n, t + 1) is
// thread t's run of n items, set_busy(t, s) from inside it, rebalance() after it. A new
// thread count starts from equal shares. No allocation once T has been seen.
class TunedSplit {
 public:
  void prepare(int T) {
    const auto n = static_cast<std::size_t>(T);
    if (share_.size() != n) {  // a new thread count (or a pinned split for another)
      share_.assign(n, 1.0 / T);
      pinned_ = false;
    }
    if (busy_.size() < n) busy_.resize(n);
    seconds_.resize(n);
    cumulative_shares(share_, cum_);
  }
  std::size_t begin(std::size_t n, int t) const {
    const auto k = static_cast<std::size_t>(t);
    return k + 1 >= cum_.size() ? n : static_cast<std::size_t>(static_cast<double>(n) * cum_[k]);
  }
  std::span<const double> cum() const { return cum_; }
  std::span<const double> share() const { return share_; }
  void set_busy(int t, double seconds) { busy_[static_cast<std::size_t>(t)].seconds = seconds; }
  // Fixed shares (each > 0, need not sum to 1) instead of tuned ones, until the thread
  // count changes; empty: tuned again. For tests: results do not depend on the split.
  void pin(std::vector<double> shares) {
    share_ = std::move(shares);
    pinned_ = !share_.empty();
  }
  void rebalance() {
    if (pinned_ || seconds_.size() != share_.size()) return;
    for (std::size_t t = 0; t < share_.size(); ++t) seconds_[t] = busy_[t].seconds;
    balance_shares(share_, seconds_);
  }

 private:
  struct alignas(64) Busy {  // one cache line per thread: each writes its own
    double seconds = 0.0;
  };
  std::vector<double> share_, cum_, seconds_;
  bool pinned_ = false;
  std::vector<Busy> busy_;
};

// A loop's contiguous runs, one per thread (the bounds of a TunedSplit), claimed in chunks:
// a thread that has finished its own run takes the chunks still unclaimed in the others'
// runs, from their fronts, through the same counters (no chunk is done twice). The tuned
// split follows a thread's speed over steps; this takes up what one step's timing changes
// (a joint that starts to soften, a moment when the VM slows one core) instead of leaving
// the other thread waiting at the barrier. Only for loops where which thread computes an
// item changes no result. No allocation once T has been seen.
class StealingRuns {
 public:
  // Before the parallel region: thread t's run is [bounds[t], bounds[t + 1]).
  void reset(std::span<const std::size_t> bounds) {
    const int T = static_cast<int>(bounds.size()) - 1;
    if (T != n_) {
      runs_ = std::make_unique<Run[]>(static_cast<std::size_t>(std::max(T, 0)));
      n_ = T;
    }
    for (int t = 0; t < T; ++t) {
      runs_[t].next.store(bounds[t], std::memory_order_relaxed);
      runs_[t].end = bounds[t + 1];
    }
  }
  // Inside the region, thread t (< the reset's T): f(begin, end) on chunks of at most
  // `chunk` items, its own run first, then the others' in thread order from t + 1.
  // Returns the number of items this thread did.
  template <class F>
  std::size_t run(int t, std::size_t chunk, F&& f) {
    std::size_t done = 0;
    for (int k = 0; k < n_; ++k) {
      Run& r = runs_[(t + k) % n_];
      for (;;) {
        const std::size_t b = r.next.fetch_add(chunk, std::memory_order_relaxed);
        if (b >= r.end) break;
        const std::size_t e = std::min(b + chunk, r.end);
        f(b, e);
        done += e - b;
      }
    }
    return done;
  }
  // The busy time to give a TunedSplit for thread t: the time its own run would have
  // taken at the rate it showed (`seconds` for `done` items, `own` items in its run), so
  // that stolen work does not read as a slow thread. Unchanged when it did nothing.
  static double busy_for_own_run(double seconds, std::size_t own, std::size_t done) {
    return done > 0 ? seconds * static_cast<double>(own) / static_cast<double>(done) : seconds;
  }

 private:
  struct alignas(64) Run {  // one cache line per run: its owner claims from it most
    std::atomic<std::size_t> next{0};
    std::size_t end = 0;
  };
  std::unique_ptr<Run[]> runs_;
  int n_ = 0;
};

}  // namespace dsdem::exec
