#pragma once
// Splitting a loop between threads by their measured speed (issue 7). On a VM one core
// often runs slower than the other for a while (another guest on it), and a split by
// count then leaves the faster thread waiting at every barrier. The phases that may give
// any thread any item (the contact pair loop, the element loops: every item writes its
// own slots or its own nodes) keep each thread on a contiguous share, tuned each step;
// which thread computes an item never changes a result.
#include <span>
#include <utility>
#include <vector>

namespace dsdem {

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

}  // namespace dsdem
