#pragma once
// The template parts of ContactForces (contact_forces.hpp, which includes this file at
// its end): the step (compute), the pair filter, and the two ways the step runs on the
// threads, each as per-thread kernels handed to the execution layer (exec/): one
// partition of the contact triangles (PartitionKernels) or the split path (SplitKernels).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "contact/contact_forces.hpp"

namespace dsdem::contact {

// x as a float no larger than x (a skip threshold must not grow by the rounding).
inline float below(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

template <class Skip>
ContactStepStats ContactForces::compute(const ContactInput& in, const ContactParamTable& params,
                                        double dt, Skip&& skip, std::vector<Vec2>& f, long skip_epoch) {
  bool rebuilt = check_input(in, f.size());
  const int partition = rebuilt ? 1 : partition_threads();
  if (rebuilt) {
    build(in);
  } else if (partition < 2 && update_shapes(in, false)) {
    build(in);
    rebuilt = true;
  }
  constexpr float kSkipped = std::numeric_limits<float>::infinity();  // skip_below_: skip() said yes
  if (skip_epoch != skip_epoch_) {  // answers may have changed: ask again (a build has)
    if (!rebuilt)
      for (float& sb : skip_below_)
        if (sb == kSkipped) sb = 0.0f;
    skip_epoch_ = skip_epoch;
  }
  cache_skip_ = skip_epoch >= 0;
  late_pending_ = !pending_.empty();
  late_sources_ = late_pending_ ? 1 : used_threads_;
  late_due_ = true;
  Index skipped = 0;
  if (partition < 2 || !compute_partitioned(in, params, dt, skip, f, partition, skipped)) {
    if (partition >= 2) {  // a node left its box: the shapes are up to date, build on them
      build(in);
      rebuilt = true;
    }
    compute_split(in, params, dt, skip, f, skipped);
  }
  std::size_t examined = 0;
  for (int u = 0; u < used_threads_; ++u) examined += todo_[u].size();
  // Edge data with the shapes next call once the examined pairs are at least half the
  // shape slots (most of those triangles then need them; see edge_scales_).
  using Mode = ContactSettings::EdgeScales;
  scales_with_shapes_ = settings_.edge_scales == Mode::automatic ? 2 * examined >= shape_slots_.size()
                                                                 : settings_.edge_scales == Mode::with_shapes;
  ContactStepStats st = finish();
  st.rebuilt = rebuilt;
  st.candidate_pairs = static_cast<Index>(broad_.pairs().size());
  st.skipped_pairs = skipped;
  st.examined_pairs = static_cast<Index>(examined);
  return st;
}

template <class Skip, class BeforeChunk>
void ContactForces::filter_pairs(std::size_t b, std::size_t e, Skip& skip, bool cache_skip,
                                 std::vector<Index>& todo, std::vector<std::uint32_t>* upto, Index& skipped,
                                 BeforeChunk&& before_chunk) {
  constexpr float kSkipped = std::numeric_limits<float>::infinity();
  const std::span<const ContactPair> pairs = broad_.pairs();
  std::uint32_t weight = 0;
  // In chunks of the run: 1a. without branches, the pairs neither known to be apart (no
  // need to load their boxes) nor skipped by skip() in this epoch. Which pairs those are
  // follows no predictable pattern, so as branches this test would be mispredicted often.
  // A chunk on the stack, not a list of every pair (memory per element).
  constexpr std::size_t kChunk = 256;
  Index open[kChunk];
  for (std::size_t c = b; c < e; c += kChunk) {
    const std::size_t c_end = std::min(e, c + kChunk);
    before_chunk(c, c_end);
    std::size_t n_open = 0;
    for (std::size_t p = c; p < c_end; ++p) {
      const ContactPair pr = pairs[p];
      const float sb = skip_below_[p];
      const double moved = motion_[pr.i] + motion_[pr.j];
      const bool asked = sb == kSkipped, apart = moved < sb;
      open[n_open] = static_cast<Index>(p);
      n_open += static_cast<std::size_t>(!(asked | apart));
      skipped += static_cast<Index>(apart & !asked);
    }
    // 1b. Their boxes and the caller's skip(), in pair order.
    for (std::size_t o = 0; o < n_open; ++o) {
      const std::size_t p = static_cast<std::size_t>(open[o]);
      const ContactPair pr = pairs[p];
      const float sb = skip_below_[p];
      const double moved = motion_[pr.i] + motion_[pr.j];
      const Aabb& bi = box_[pr.i];
      const Aabb& bj = box_[pr.j];
      if (!overlaps(bi, bj)) {  // the skin's extras: apart while they move less than the gap
        skip_below_[p] = below(moved + 0.5 * box_gap(bi, bj));
        continue;
      }
      if (skip(pr.i, pr.j)) {
        if (cache_skip) skip_below_[p] = kSkipped;
        continue;
      }
      todo.push_back(static_cast<Index>(p));
      if (upto) upto->push_back(weight += pair_weight(sb));
    }
  }
}

// The kernels of one partition (exec::PartitionedRegion): thread t of T holds the
// triangles [from, to) (T = 1: all), their shapes, and the pairs whose triangle i they hold.
template <class Skip>
struct ContactForces::PartitionKernels {
  ContactForces& cf;
  const ContactInput& in;
  const ContactParamTable& params;
  const double dt;
  Skip& skip;
  std::vector<Vec2>& f;
  const std::span<const ContactPair> pairs;
  const std::span<const Index> tris;

  Index from(int t, int T) const { return T == 1 ? 0 : cf.tri_bound_[static_cast<std::size_t>(t)]; }
  Index to(int t, int T) const {
    return T == 1 ? std::numeric_limits<Index>::max() : cf.tri_bound_[static_cast<std::size_t>(t) + 1];
  }
  std::ptrdiff_t slot_at(Index tri) const {
    return std::lower_bound(cf.shape_slots_.begin(), cf.shape_slots_.end(), tri,
                            [&](Index slot, Index x) { return tris[static_cast<std::size_t>(slot)] < x; }) -
           cf.shape_slots_.begin();
  }
  std::size_t pair_at(Index tri) const {
    return static_cast<std::size_t>(
        std::lower_bound(pairs.begin(), pairs.end(), tri, [](const ContactPair& p, Index x) { return p.i < x; }) -
        pairs.begin());
  }
  // 1. The shapes of this thread's triangles; the first thread also tests the others
  // (in no pair) for a rebuild: the other threads' shapes are then done before the
  // first thread's filter reaches pairs that need them (once the bodies have moved,
  // many of its pairs reach the other thread's triangles). true: a node left its box.
  bool first(int t, int T) {
    int left = 0;
    cf.update_shape_run(in, slot_at(from(t, T)), slot_at(to(t, T)), false, left);
    if (t == 0) cf.test_other_slots(in, left, false);
    return left != 0;
  }
  // 2. The pairs whose triangle i is this thread's, filtered. A pair's triangle j > i is
  // this thread's or a later one's: the later threads' shapes are waited for before the
  // first chunk of pairs that reaches their triangles (j >= to), so no thread waits at a
  // barrier for the others' shapes.
  long second(int t, int T, exec::PartitionedRegion::Later& later) {
    Index skipped = 0;
    const Index end = to(t, T);
    std::vector<Index>& todo = cf.todo_[t];
    todo.clear();
    cf.filter_pairs(pair_at(from(t, T)), pair_at(end), skip, cf.cache_skip_, todo, nullptr, skipped,
                    [&](std::size_t c, std::size_t c_end) {
                      if (later.seen()) return;
                      Index j_max = 0;
                      for (std::size_t p = c; p < c_end; ++p) j_max = std::max(j_max, pairs[p].j);
                      if (j_max >= end) later.wait();
                    });
    return skipped;
  }
  // 3. The pairs examined, unless a node left its box (the first thread, which adds
  // forces to nodes at once that a rebuild could not take back, is told).
  void third(int t, int T, bool left) {
    cf.settle_previous(in, dt, t, T);
    cf.buffers_[t].clear();
    cf.block_sums_[t].clear();
    for (int c = 0; c < T; ++c) cf.touching_[t * T + c].clear();
    PairRun run;
    run.t = t;
    run.T = T;
    run.note = T > 1;
    run.own_scales = !cf.scales_with_shapes_;
    run.f_now = T == 1   ? std::span<Vec2>(f)
                : t == 0 ? std::span<Vec2>(f).first(static_cast<std::size_t>(cf.range_begin(1)))
                         : std::span<Vec2>();
    if (!left) cf.examine_pairs(cf.todo_[t], 0, cf.todo_[t].size(), in, params, dt, run);
    cf.end_pair_run(run);
  }
  // 4. The forces to each thread's node range, in record order (see compute_split).
  void gather(int t, int T) { cf.scatter_forces(in, f, t, T); }
};

template <class Skip>
bool ContactForces::compute_partitioned(const ContactInput& in, const ContactParamTable& params, double dt,
                                        Skip& skip, std::vector<Vec2>& f, int nt, Index& skipped) {
  ensure_thread_lists(nt);
  partition_.prepare(nt);
  history_.begin_step(nt);
  const std::size_t nn = f.size();
  set_partition_bounds(in, nn, nt);
  PartitionKernels<Skip> k{*this, in, params, dt, skip, f, broad_.pairs(), broad_.active_triangles()};
  const exec::PartitionedRegion::Result r = partition_.run(nt, k);
  skipped += static_cast<Index>(r.count);
  used_threads_ = r.threads;
  late_due_ = false;
  if (used_threads_ == 1) equal_node_ranges(nn, 1);
  return !r.stopped;
}

// The kernels of the split path (exec::SplitRegion).
template <class Skip>
struct ContactForces::SplitKernels {
  ContactForces& cf;
  const ContactInput& in;
  const ContactParamTable& params;
  const double dt;
  Skip& skip;
  std::vector<Vec2>& f;
  const std::span<const ContactPair> candidates;
  const bool cache_skip, settle;

  std::size_t examined(int T) const {
    std::size_t n = 0;
    for (int u = 0; u < T; ++u) n += cf.todo_[u].size();
    return n;
  }
  // 1. The pairs to examine, in pair order per contiguous chunk: rounded boxes overlap,
  // not known to be apart (see skip_below_), not skipped by the caller.
  long filter(int t, int T, std::size_t b, std::size_t e) {
    Index skipped = 0;
    std::vector<Index>& todo = cf.todo_[t];
    std::vector<std::uint32_t>& upto = cf.todo_weight_[t];
    todo.clear();
    upto.clear();
    cf.filter_pairs(b, e, skip, cache_skip, todo, T > 1 ? &upto : nullptr, skipped, [](std::size_t, std::size_t) {});
    return skipped;
  }
  // Few pairs: the first thread alone from here.
  bool split(int T) const { return examined(T) >= cf.settings_.min_examined_pairs_to_split; }
  // 2. Edge data of the triangles in those pairs only (once each), unless
  // update_shapes() did it for all.
  bool scales() const { return !cf.scales_with_shapes_; }
  void collect(int T) { cf.collect_scale_triangles(T); }
  std::size_t items() const { return cf.scale_tris_.size(); }
  void item(std::size_t s) {
    const Index tri = cf.scale_tris_[s];
    cf.edge_scales_[tri] = core_edge_scales(cf.sp_[tri].core);
    cf.in_pair_[tri] &= ~kScales;
  }
  void prepare(int t, int T, bool) {
    if (settle) cf.settle_previous(in, dt, t, T);
    cf.buffers_[t].clear();
    cf.block_sums_[t].clear();
    if (T > 1)
      for (int c = 0; c < T; ++c) cf.touching_[t * T + c].clear();
  }
  // 3. Narrow phase and law. The pairs to examine, in pair order (todo_[0], todo_[1],
  // ...), are split into T contiguous runs of equal expected cost (todo_weight_),
  // whatever share of them each thread's filter found. Concatenating the buffers in
  // thread order still gives pair order.
  void pairs(int t, int T, bool split, std::span<const double> cum) {
    // Forces added at once, while the records are in cache: by one thread (or the first
    // alone, few pairs), to every node; by the first of several, to the nodes of its range
    // (no earlier pair touches them).
    PairRun run;
    run.t = t;
    run.T = T;
    run.note = split;
    run.f_now = t != 0 ? std::span<Vec2>()
                : split ? std::span<Vec2>(f).first(static_cast<std::size_t>(cf.range_begin(1)))
                        : std::span<Vec2>(f);
    const std::size_t n_examined = examined(T);
    std::size_t first = 0, count = t == 0 ? n_examined : 0;  // split: set below
    if (split) {
      std::uint64_t total = 0;
      for (int u = 0; u < T; ++u) total += cf.todo_weight_[u].empty() ? 0 : cf.todo_weight_[u].back();
      // Thread t's run: the running weights in (total cum[t], total cum[t + 1]].
      auto bound = [&](int u) {
        if (u >= T) return total;
        if (cum.empty()) return total * static_cast<std::uint64_t>(u) / static_cast<std::uint64_t>(T);
        return std::min(total, static_cast<std::uint64_t>(static_cast<double>(total) * cum[u]));
      };
      // Runs start at the first pair of a sum block (pairs whose triangle i is in one run of
      // kSumBlock indices), so no block is split between threads.
      auto pair_at = [&](std::size_t c) -> const ContactPair& {
        int u = 0;
        while (c >= cf.todo_[u].size()) c -= cf.todo_[u++].size();
        return candidates[cf.todo_[u][c]];
      };
      auto at_block = [&](std::size_t c) {
        while (c > 0 && c < n_examined && pair_at(c).i / kSumBlock == pair_at(c - 1).i / kSumBlock) ++c;
        return c;
      };
      first = at_block(cf.pairs_within_weight(bound(t), T));
      const std::size_t end = t + 1 == T ? n_examined : at_block(cf.pairs_within_weight(bound(t + 1), T));
      count = end > first ? end - first : 0;
    }
    for (int u = 0; u < T && count > 0; ++u) {
      const std::vector<Index>& list = cf.todo_[u];
      if (first >= list.size()) {
        first -= list.size();
        continue;
      }
      const std::size_t end = std::min(list.size(), first + count);
      cf.examine_pairs(list, first, end, in, params, dt, run);
      count -= end - first;
      first = 0;
    }
    cf.end_pair_run(run);
  }
  // 4. The forces to the nodes (one thread, or few pairs: done in step 3): thread t adds
  // the forces of the records that touch its node range to those nodes (thread 0's own
  // ones: done in step 3), in record order, so each node gets the same sum, in the same
  // order, for any thread count. The last thread's gather is the longest by construction
  // (it adds every record on its nodes, the first thread only the others' records).
  void gather(int t, int T) { cf.scatter_forces(in, f, t, T); }
};

template <class Skip>
void ContactForces::compute_split(const ContactInput& in, const ContactParamTable& params, double dt, Skip& skip,
                                  std::vector<Vec2>& f, Index& skipped) {
  const std::size_t np = broad_.pairs().size();
  const int nt = begin_pairs(np);
  // Each thread writes its contacts' history to a segment of its own, and its blocks' sums.
  history_.begin_step(nt);
  equal_node_ranges(f.size(), nt);
  SplitKernels<Skip> k{*this, in, params, dt, skip, f, broad_.pairs(), cache_skip_, late_due_};
  const exec::SplitRegion::Result r = split_region_.run(nt, np, k);
  skipped += static_cast<Index>(r.count);
  used_threads_ = r.threads;
  late_due_ = false;
}

}  // namespace dsdem::contact
