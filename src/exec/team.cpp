#include "exec/team.hpp"

#include "exec/deterministic_sums.hpp"

#include <algorithm>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace dsdem::exec {

double wall_seconds() {
#ifdef _OPENMP
  return omp_get_wtime();
#else
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
#endif
}

int max_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

Team::Team(bool parallel, bool automatic) : parallel_(parallel), automatic_(automatic && parallel && max_threads() > 1) {}

bool Team::end_step(long steps_done) {
  if (!automatic_) return false;
  return record_step(std::chrono::duration<double>(std::chrono::steady_clock::now() - step_start_).count(), steps_done);
}

bool Team::record_step(double step_seconds, long steps_done) {
  if (!automatic_) return false;
  const bool before = parallel_;
  const long k = steps_done - 1 - probe_start_;
  if (parallel_ && k < -1 && parallel_median_ > 0.0) {  // between windows, on the threads
    slow_ += step_seconds > kSlowdown * parallel_median_ ? 1 : 0;
    if (++watched_ == kWatchSteps) {
      if (2 * slow_ > kWatchSteps) probe_start_ = steps_done + 1;  // a window from the step after next
      watched_ = slow_ = 0;
    }
  }
  probe(step_seconds, steps_done);
  return parallel_ != before;
}

void Team::probe(double step_seconds, long steps_done) {
  // The probe window is steps probe_start_ .. + 2 kProbeSteps - 1: the first half on one
  // thread, the second on the threads; then the faster mode runs until the next window.
  if (!parallel_) ++serial_steps_chosen_;
  const long k = steps_done - 1 - probe_start_;  // position of the step just done in the window
  if (k == -1) parallel_ = false;  // the window starts with the next step
  if (k < 0) return;
  if (k >= 2 * kProbeSteps) {  // e.g. after a restore: start a window now
    probe_start_ = steps_done;
    parallel_ = false;
    return;
  }
  if (k < kProbeSteps)
    probe_serial_[static_cast<std::size_t>(k)] = step_seconds;
  else
    probe_parallel_[static_cast<std::size_t>(k - kProbeSteps)] = step_seconds;
  if (k + 1 == kProbeSteps) {
    parallel_ = true;
  } else if (k + 1 == 2 * kProbeSteps) {
    // One thread is re-checked soon, then less and less often while it stays faster: a
    // slow spell of the other core does not hold the run on one thread for long, and a
    // busy machine pays few probes.
    parallel_ = choose_parallel(probe_serial_, probe_parallel_);
    std::array<double, kProbeSteps> sorted = probe_parallel_;
    std::sort(sorted.begin(), sorted.end());
    parallel_median_ = 0.5 * (sorted[kProbeSteps / 2 - 1] + sorted[kProbeSteps / 2]);
    watched_ = slow_ = 0;
    if (parallel_) {
      probe_start_ = steps_done + kProbeInterval;
      serial_recheck_ = kRecheckInterval;
    } else {
      probe_start_ = steps_done + serial_recheck_;
      serial_recheck_ = std::min(2 * serial_recheck_, kProbeInterval);
    }
  }
}

void Team::set_node_chunks_from(std::span<const Index> node_bounds, int threads, std::size_t n_nodes) {
  node_chunks_.clear();
  const std::size_t chunks = detail::reduction_chunks(n_nodes);
  if (threads < 2 || node_bounds.size() != static_cast<std::size_t>(threads) + 1 || chunks < 2) return;
  // Each bound to the nearest chunk start, ascending.
  node_chunks_.resize(node_bounds.size());
  for (std::size_t t = 0; t < node_bounds.size(); ++t) {
    const auto node = static_cast<std::size_t>(node_bounds[t]);
    const std::size_t c = t + 1 == node_bounds.size() ? chunks : std::min(chunks, (node + kReductionChunk / 2) / kReductionChunk);
    node_chunks_[t] = t == 0 ? 0 : std::max(c, node_chunks_[t - 1]);
  }
}

void Team::flush_node_pass(std::size_t n_nodes) {
  const NodePass pass = take_node_pass();
  if (!pass) return;
#pragma omp parallel num_threads(threads()) if (parallel_)
  {
    const auto [t, T] = detail::thread_in_team();
    const auto [begin, end] = detail::chunk_indices(n_nodes, t, T, node_chunks_);
    pass(begin, end);
  }
}

}  // namespace dsdem::exec
