#pragma once
// Execution layer: the traversal of the element and joint phases (docs/theory.md §1 phases 3-4)
// in one thread region per step. Physics hands it per-item kernels; this file alone holds
// the region's plumbing: the deferred node pass, the tuned splits, work stealing, busy
// timers, barriers and rebalancing. Which thread computes an item changes no result.
//
// Order in the region:
//   0. the node pass deferred by an earlier phase (the integrator's kick and drift), on
//      each thread's node chunks, then a barrier: the element kernels read any node;
//   1. the shared triangles into their scatter slots and the joint blocks into their
//      buffers, with no barrier between the two loops;
//   2. after a barrier: the own triangles (forces straight into their nodes' sums, with
//      their joints' forces) and the gathered nodes (NodeScatter).
#include <cstddef>
#include <vector>

#include "exec/deterministic_sums.hpp"
#include "exec/node_scatter.hpp"
#include "exec/team.hpp"
#include "exec/work_split.hpp"

namespace dsdem::exec {

// The per-item kernels of the region, as a class with these members (all may run on any
// thread, each item once; each returns status bits that the region ORs together):
//   int shared(std::size_t slot)                 shared triangle of scatter slot `slot`
//   void joint_blocks(std::size_t b0, std::size_t b1)   joint blocks [b0, b1)
//   int own(std::size_t t0, std::size_t t1)      own triangles of [t0, t1) (skip shared ones)
//   void gathered(std::size_t g)                 gathered node g (NodeScatter::gather)
class ElementRegion {
 public:
  static constexpr std::size_t kOwnChunk = 32;  // own triangles per claim (~1-2 us of work)

  // Runs the region: n_nodes for the deferred node pass, the scatter's shared, own and
  // gathered items, n_joint_blocks joint blocks. Returns the OR of the kernels' bits.
  template <class Kernels>
  int run(Team& team, std::size_t n_nodes, const NodeScatter& scatter, std::size_t n_joint_blocks, Kernels& k);

 private:
  TunedSplit shared_split_, joint_split_, own_split_;
  std::vector<std::size_t> own_bound_;    // triangle index bounds of the own-triangle runs
  std::vector<std::size_t> joint_bound_;  // joint block bounds of the joint runs
  // A thread that ends its own run takes what is left of the other's (one step's
  // imbalance; the splits above follow the threads' speeds over steps).
  StealingRuns joint_runs_, own_runs_;
};

template <class Kernels>
int ElementRegion::run(Team& team, std::size_t n_nodes, const NodeScatter& scatter, std::size_t n_joint_blocks,
                       Kernels& k) {
  const int threads = team.threads();
  const NodePass node_pass = team.take_node_pass();
  const std::span<const std::size_t> node_chunks = team.node_chunks();
  const std::size_t n_triangles = scatter.own_prefix().size() - 1;
  const auto ns = static_cast<std::ptrdiff_t>(scatter.shared_count());
  const auto ng = static_cast<std::ptrdiff_t>(scatter.gathered_count());
  shared_split_.prepare(threads);
  joint_split_.prepare(threads);
  own_split_.prepare(threads);
  counted_share_bounds(scatter.own_prefix(), own_split_.cum(), own_bound_);
  if (threads > 1) {
    joint_bound_.resize(static_cast<std::size_t>(threads) + 1);
    for (int t = 0; t <= threads; ++t) joint_bound_[static_cast<std::size_t>(t)] = joint_split_.begin(n_joint_blocks, t);
    joint_runs_.reset(joint_bound_);
    own_runs_.reset(own_bound_);
  }
  int bits = 0;
  bool full_team = false;
#pragma omp parallel num_threads(threads) if (team.parallel()) reduction(| : bits)
  {
    const auto [th, team_size] = detail::thread_in_team();
    const int thread = static_cast<int>(th);
    // A team smaller than asked for runs everything on its first thread.
    const bool split = static_cast<int>(team_size) == threads;
    const bool stealing = split && team_size > 1;
    if (node_pass) {
      const auto [begin, end] = detail::chunk_indices(n_nodes, th, team_size, node_chunks);
      node_pass(begin, end);
#pragma omp barrier
    }
    const std::ptrdiff_t s_begin =
        split ? static_cast<std::ptrdiff_t>(shared_split_.begin(scatter.shared_count(), thread)) : (thread == 0 ? 0 : ns);
    const std::ptrdiff_t s_end =
        split ? static_cast<std::ptrdiff_t>(shared_split_.begin(scatter.shared_count(), thread + 1)) : ns;
    double busy_from = wall_seconds();
    for (std::ptrdiff_t s = s_begin; s < s_end; ++s) bits |= k.shared(static_cast<std::size_t>(s));
    shared_split_.set_busy(thread, wall_seconds() - busy_from);
    busy_from = wall_seconds();
    if (n_joint_blocks > 0) {
      if (stealing) {
        const std::size_t done = joint_runs_.run(thread, 1, [&](std::size_t b0, std::size_t b1) { k.joint_blocks(b0, b1); });
        joint_split_.set_busy(thread, StealingRuns::busy_for_own_run(wall_seconds() - busy_from,
                                                                     joint_bound_[th + 1] - joint_bound_[th], done));
      } else if (thread == 0) {
        k.joint_blocks(0, n_joint_blocks);
      }
    }
#pragma omp barrier
    busy_from = wall_seconds();
    std::size_t own_done = 0;
    if (stealing) own_done = own_runs_.run(thread, kOwnChunk, [&](std::size_t t0, std::size_t t1) { bits |= k.own(t0, t1); });
    else if (thread == 0) bits |= k.own(0, n_triangles);
#pragma omp for schedule(static) nowait
    for (std::ptrdiff_t g = 0; g < ng; ++g) k.gathered(static_cast<std::size_t>(g));
    // The gathered nodes' time counts as if spent on the own run: the loop is static.
    own_split_.set_busy(thread, stealing ? StealingRuns::busy_for_own_run(wall_seconds() - busy_from,
                                                                          own_bound_[th + 1] - own_bound_[th], own_done)
                                         : wall_seconds() - busy_from);
    if (thread == 0) full_team = split;
  }
  if (threads > 1 && full_team) {
    shared_split_.rebalance();
    joint_split_.rebalance();
    own_split_.rebalance();
  }
  return bits;
}

}  // namespace dsdem::exec
