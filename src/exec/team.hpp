#pragma once
// Execution layer: the thread team of one solver. It decides whether a step's loops run
// on OpenMP threads or on one thread (by size, by hand, or by timing both now and then),
// which node chunks each thread takes in the node loops, and it carries a node pass that
// a phase asked for to the next region that walks the nodes (phase fusion, docs/developer-guide.md §2:
// one fork and join fewer per fused pass, declared here and nowhere else).
// Physics code never calls OpenMP; it hands this layer per-item kernels.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "model/types.hpp"

namespace dsdem::exec {

// Seconds of wall time on this thread's clock, for busy timers (OpenMP's clock when built
// with OpenMP).
double wall_seconds();

// Threads OpenMP would give a region (1 without OpenMP).
int max_threads();

// A non-owning reference to a callable void(std::size_t begin, std::size_t end): a node
// pass handed from one phase to the region that runs it, with no allocation.
class NodePass {
 public:
  NodePass() = default;
  template <class F>
  explicit NodePass(F& f) : object_(&f), call_([](void* o, std::size_t b, std::size_t e) { (*static_cast<F*>(o))(b, e); }) {}
  explicit operator bool() const { return call_ != nullptr; }
  void operator()(std::size_t begin, std::size_t end) const { call_(object_, begin, end); }

 private:
  void* object_ = nullptr;
  void (*call_)(void*, std::size_t, std::size_t) = nullptr;
};

// The automatic choice between one thread and OpenMP: keep the threads unless their median
// step time is above the serial median by more than `margin`. Medians, so that a few steps
// slowed by something else in one window do not decide; the margin, because on a VM the
// second core's speed comes and goes and one thread gains little when the two are close.
template <std::size_t N>
bool choose_parallel(std::array<double, N> serial, std::array<double, N> parallel, double margin = 1.1);

class Team {
 public:
  // Large models on more than one thread choose between OpenMP and one thread by timing
  // kProbeSteps steps of each every kProbeInterval steps. On a machine shared with busy
  // processes the threads of a region wait for a descheduled partner at every barrier
  // and a run can be many times slower than on one thread; results are bit-identical
  // either way. A verdict for one thread is checked again after kRecheckInterval steps,
  // then after twice as many, up to kProbeInterval.
  static constexpr long kProbeInterval = 4000;
  static constexpr long kRecheckInterval = 500;
  static constexpr int kProbeSteps = 8;

  // parallel: start on OpenMP threads; automatic: choose by timing (only with > 1 thread).
  Team(bool parallel, bool automatic);

  bool parallel() const { return parallel_; }
  // Threads the next region asks for: all of OpenMP's when parallel, else 1.
  int threads() const { return parallel_ ? max_threads() : 1; }
  // By hand: turns the automatic choice off.
  void set_parallel(bool on) {
    automatic_ = false;
    parallel_ = on;
  }
  bool automatic() const { return automatic_; }
  // Steps run on one thread by the automatic choice (probe windows included).
  long serial_steps_chosen() const { return serial_steps_chosen_; }

  // The step's wall clock for the automatic choice: begin_step() before the step's first
  // phase, end_step(steps done) after its last. Returns true when the choice changed
  // (the caller passes it on to phases that keep their own parallel flag).
  void begin_step() { step_start_ = std::chrono::steady_clock::now(); }
  bool end_step(long steps_done);
  // end_step with the step's wall time given (tests).
  bool record_step(double step_seconds, long steps_done);
  // While on the threads: a probe window starts early when more than half of the last
  // kWatchSteps steps took over kSlowdown times the threads' median of the last window
  // (the machine got busy: other processes now deschedule a thread at the barriers).
  static constexpr int kWatchSteps = 32;
  static constexpr double kSlowdown = 1.5;

  // Each thread's node chunks in the node loops (kick, velocities, node sums): T + 1
  // chunk bounds for T threads, or empty for the equal shares of detail::own_chunks.
  std::span<const std::size_t> node_chunks() const { return node_chunks_; }
  // Chunk bounds from node index bounds for `threads` threads (threads + 1, ascending):
  // each thread then walks the nodes its other phases read most (e.g. the contact phase's
  // partition). Other sizes, or fewer than 2 threads: the equal shares.
  void set_node_chunks_from(std::span<const Index> node_bounds, int threads, std::size_t n_nodes);
  void clear_node_chunks() { node_chunks_.clear(); }

  // Phase fusion: `pass` (node-local, on node ranges that cover every node once) runs at
  // the start of the next region over the nodes, on each thread's node chunks, instead of
  // in a region of its own. The region that takes it says whether a barrier follows
  // (exec::ElementRegion: yes; deterministic sums: no, each thread reads only its nodes).
  void defer_node_pass(NodePass pass) { pending_ = pass; }
  // The pending pass, cleared; an empty pass when none.
  NodePass take_node_pass() { return std::exchange(pending_, NodePass{}); }
  // Runs a pending pass in a region of its own (when no fused region follows).
  void flush_node_pass(std::size_t n_nodes);

 private:
  void probe(double step_seconds, long steps_done);

  bool parallel_ = false;
  bool automatic_ = false;
  long probe_start_ = kProbeSteps;  // step at which the next probe window starts
  long serial_recheck_ = kRecheckInterval;
  long serial_steps_chosen_ = 0;
  std::array<double, kProbeSteps> probe_serial_{}, probe_parallel_{};
  double parallel_median_ = 0.0;  // s: the threads' median step in the last window
  int watched_ = 0, slow_ = 0;    // steps watched since the window, and how many were slow
  std::chrono::steady_clock::time_point step_start_{};
  std::vector<std::size_t> node_chunks_;
  NodePass pending_;
};

// f(i) for every i in [0, n), on the team's threads when parallel (a static schedule):
// for loops whose items are independent.
template <class F>
void parallel_for(const Team& team, std::size_t n, F&& f) {
#pragma omp parallel for schedule(static) if (team.parallel())
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) f(static_cast<std::size_t>(i));
}

template <std::size_t N>
bool choose_parallel(std::array<double, N> serial, std::array<double, N> parallel, double margin) {
  static_assert(N > 0);
  auto median = [](std::array<double, N>& t) {
    std::sort(t.begin(), t.end());
    return N % 2 == 1 ? t[N / 2] : 0.5 * (t[N / 2 - 1] + t[N / 2]);
  };
  return median(parallel) <= margin * median(serial);
}

}  // namespace dsdem::exec
