#pragma once
// Contact phase of the time step (docs/theory.md §1 step 5, §4): broad phase, narrow
// phase, contact law and shape-function mapping, adding the contact forces to the
// node forces. Called once per step; keeps its buffers and the tangential history
// between calls and allocates nothing once they have grown (warm-up).
//
// Determinism: candidate pairs are sorted (i < j), each pair's contacts are computed
// independently (in parallel with OpenMP, static contiguous chunks), and every node
// gets its contact forces in pair/feature order (one thread per node range), so the
// result does not depend on the thread count.
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <vector>

#include "contact/broad_phase.hpp"
#include "contact/buffer.hpp"
#include "contact/contact_history.hpp"
#include "contact/contact_types.hpp"
#include "contact/spheropolygon.hpp"
#include "exec/partitioned_region.hpp"

namespace dsdem::contact {

class ContactForces {
 public:
  explicit ContactForces(const ContactSettings& settings = {})
      : settings_(settings), scales_with_shapes_(settings.edge_scales == ContactSettings::EdgeScales::with_shapes) {}

  // Adds the contact forces to f (size = node count) and returns the step's counts
  // and energies. Pairs of triangles sharing a node (continuous mesh) or a body id
  // never interact. skip(i, j), i < j, is asked every step for every candidate pair
  // whose rounded boxes overlap and whose cores are not known to be apart (so a joint
  // that breaks lets its pair into contact at once); it must be cheap, thread-safe and
  // must not throw. conn, active and body are
  // read when the broad phase is rebuilt: call invalidate() after changing them.
  // skip_epoch >= 0 promises that skip's answers change only when skip_epoch changes
  // (the solver passes its count of broken joints: an intact joint's pair stays skipped
  // until some joint breaks): a pair skipped is then not asked again, nor its boxes
  // tested, until skip_epoch changes or the broad phase is rebuilt.
  template <class Skip>
  ContactStepStats compute(const ContactInput& in, const ContactParamTable& params, double dt,
                           Skip&& skip, std::vector<Vec2>& f, long skip_epoch = -1);

  ContactStepStats compute(const ContactInput& in, const ContactParamTable& params, double dt,
                           std::vector<Vec2>& f) {
    return compute(in, params, dt, [](Index, Index) { return false; }, f);
  }

  void set_parallel(bool on) { settings_.parallel = on; }
  // Fixes each thread's share of the pair loop's expected cost (one per thread, each > 0)
  // instead of tuning it from timing (balance_shares); empty: tune again. For tests: the
  // results are the same for any split.
  // With one partition (ContactSettings::one_partition) these are the shares of the
  // contact triangles' run each thread shapes, filters and examines.
  void pin_pair_split(std::vector<double> shares) {
    for (double s : shares)
      if (!(s > 0.0)) throw std::invalid_argument("pair split shares must be > 0");
    partition_.pin(shares);
    split_region_.pin_pairs(std::move(shares));
  }
  // Each thread's share of the pair loop at the last call (empty before the first
  // parallel one).
  std::span<const double> pair_split() const { return split_region_.pair_share(); }
  // Forces a broad-phase rebuild at the next call (e.g. after a remesh).
  void invalidate() { invalidated_ = true; }
  // Restart from a checkpoint: the stored tangential forces, the elastic-energy
  // reference, the skin and the last call's dashpot records (dashpot_records()) of the
  // interrupted run; the broad phase is rebuilt.
  void restore(const std::vector<ContactHistory::Entry>& entries, double last_elastic_energy, double skin,
               std::vector<DashpotRecord> dashpots = {});
  double last_elastic_energy() const { return last_elastic_energy_; }
  // The last call's contacts with a dashpot force, in key order: the second half of their
  // work is still to be booked (by the next call).
  std::vector<DashpotRecord> dashpot_records() const;
  // Forgets the tangential history and the elastic-energy reference.
  void reset_history() {
    history_.clear();
    last_elastic_energy_ = 0.0;
  }

  // The contacts of the last call, in key order.
  template <class Fn>
  void for_each_contact(Fn&& fn) const {
    for (int t = 0; t < used_threads_; ++t)
      for (const ContactRecord& c : buffers_[t]) fn(c);
  }
  const ContactHistory& history() const { return history_; }
  const BroadPhase& broad_phase() const { return broad_; }
  double skin() const { return skin_; }
  // OpenMP threads that ran the pair loop of the last call.
  int threads_used() const { return used_threads_; }
  // The threads' node ranges of the last call when it ran on one partition
  // (ContactSettings::one_partition): T + 1 ascending bounds, 0 first and the node count
  // last; thread t's triangles use mostly the nodes [bound[t], bound[t + 1]). Empty
  // otherwise. For the solver's node loops: a thread that kicks the nodes its contact
  // pairs read does not fetch them from the other core.
  std::span<const Index> node_split() const {
    return node_split_partitioned_ ? std::span<const Index>(node_bound_) : std::span<const Index>();
  }
  // The next call computes the edge data of every triangle in a candidate pair.
  bool edge_scales_with_shapes() const { return scales_with_shapes_; }
  // Spheropolygon of triangle t at the last call (contact triangles that are in some
  // candidate pair of the broad phase; the others are not updated).
  const Spheropolygon& spheropolygon(Index t) const { return sp_[t]; }

 private:
  // Checks sizes and sets the skin at the first call; true when the broad phase must be
  // built before anything else (first call, invalidate(), other sizes, stale).
  bool check_input(const ContactInput& in, std::size_t n_forces);
  // Builds the broad phase and updates the shapes of its pairs' triangles (motions restart).
  void build(const ContactInput& in);
  // Threads of the one-partition path this call (ContactSettings::one_partition); 1: not taken.
  int partition_threads() const;
  // One partition (see ContactSettings::one_partition), in one parallel region of nt
  // threads: shapes, then the filter and pair loop of each thread's pairs, then the
  // scatter. Returns false, having only updated the shapes and motions, when a node left
  // its box of the broad-phase build (the caller builds and takes the split path).
  template <class Skip>
  bool compute_partitioned(const ContactInput& in, const ContactParamTable& params, double dt, Skip& skip,
                           std::vector<Vec2>& f, int nt, Index& skipped);
  // The split path: the filter, the edge data and the pair loop each split on its own.
  template <class Skip>
  void compute_split(const ContactInput& in, const ContactParamTable& params, double dt, Skip& skip,
                     std::vector<Vec2>& f, Index& skipped);
  // The per-thread kernels of the two paths (exec::PartitionedRegion, exec::SplitRegion),
  // in contact_kernels.hpp.
  template <class Skip>
  struct PartitionKernels;
  template <class Skip>
  struct SplitKernels;
  // One partition's bounds of nt threads: tri_bound_ (their runs of triangles) and
  // node_bound_ (from the first node of each run; nn nodes).
  void set_partition_bounds(const ContactInput& in, std::size_t nn, int nt);
  // Shapes of the slots [s_begin, s_end) of shape_slots_, two at a time (the last one twice
  // when their count is odd); left = 1 when a node left its build box.
  void update_shape_run(const ContactInput& in, std::ptrdiff_t s_begin, std::ptrdiff_t s_end, bool rebuilt,
                        int& left);
  // The rebuild test of the active triangles in no pair: shared by the threads of the
  // enclosing parallel region (an orphaned worksharing loop, nowait; every thread of the
  // team must call it), or all by the calling thread (shared = false).
  void test_other_slots(const ContactInput& in, int& left, bool shared = true);
  // Appends to todo the pairs of [b, e) to examine (the filter, see compute_split) and,
  // given, their running expected costs to upto.
  // before_chunk(c, c_end) runs before the filter reads the pairs [c, c_end) (one chunk).
  template <class Skip, class BeforeChunk>
  void filter_pairs(std::size_t b, std::size_t e, Skip& skip, bool cache_skip, std::vector<Index>& todo,
                    std::vector<std::uint32_t>* upto, Index& skipped, BeforeChunk&& before_chunk);
  // One partition: the first triangle of thread u's run of T (a multiple of kSumBlock; 0 for
  // u = 0, past every triangle for u = T), from the tuned share of the shape slots.
  Index partition_begin(int u, int T) const;
  // Shapes, boxes and (unless rebuilt) motions of the triangles of shape_slots_, in one
  // parallel region with the rebuild test of the other active triangles (unless rebuilt);
  // returns true when a node of an active triangle has left its box of the broad-phase build.
  bool update_shapes(const ContactInput& in, bool rebuilt);
  // Thread count for this call; makes sure every thread has a buffer.
  int begin_pairs(std::size_t n_pairs);
  // Narrow phase + law of one pair whose rounded boxes overlap, appended to out; returns
  // the cores' clearance (narrow_phase) when they are apart, -(contact count) when they
  // touch, else 0.
  // check_apart: see narrow_phase().
  // f_now: the pair's forces go at once to the nodes below f_now.size(), while its records
  // are in cache (in record order, as scatter_forces() would add them): f itself on one
  // thread, the first node range on the first of several, empty on the others.
  double process_pair(Index i, Index j, const CoreEdgeScales& scales_i, const CoreEdgeScales& scales_j,
                      const ContactInput& in, const ContactParamTable& params, double dt, bool check_apart,
                      ContactHistory::Cursor& cursor, std::vector<ContactRecord>& out,
                      std::span<Vec2> f_now) const;
  struct BlockSums {
    double elastic_energy = 0.0, friction_dissipation = 0.0, damping_dissipation = 0.0;
  };
  // One thread's pair loop over one or more lists of pairs, in pair order.
  struct PairRun {
    int t = 0, T = 1;
    std::span<Vec2> f_now;  // see process_pair
    bool note = false;      // note_touching() for the scatter
    bool own_scales = false;  // the edge data per pair, not from edge_scales_
    ContactHistory::Cursor cursor;  // keys ascend within the run
    Index block = -1;
    BlockSums sums;
    Index active = 0, sliding = 0;
  };
  // Examines the pairs list[k] for k in [k_begin, k_end) into thread run.t's buffer, history
  // segment and block sums (skip_below_ updated).
  void examine_pairs(const std::vector<Index>& list, std::size_t k_begin, std::size_t k_end,
                     const ContactInput& in, const ContactParamTable& params, double dt, PairRun& run);
  // The run's last block sums and its counts.
  void end_pair_run(const PairRun& run);
  // The second half of the work of the last call's dashpot forces (docs/theory.md §1 steps 1
  // and 8, §7): velocity Verlet applies a force of step n half into v(n) and half into
  // v(n+1/2), so its exact (trapezoidal) work is 0.5 dt f . (v_rel(n-1/2) + v_rel(n+1/2)),
  // each at the contact's own shape functions. The first half is booked with the force
  // (ContactRecord::damping_dissipation); this books the second with in.v = v(n+1/2),
  // also for contacts that have ended. Thread t of T takes the last call's buffers t,
  // t + T, ... (before it clears its own), or thread 0 the restored records; the sums per
  // block of records (as block_sums_) keep them independent of the thread counts.
  void settle_previous(const ContactInput& in, double dt, int t, int T);
  // Makes sure nt threads have their buffers and lists.
  void ensure_thread_lists(int nt);
  // Serial: scale_tris_ = the triangles of the pairs in todo_[0..T), once each (flags in in_pair_).
  void collect_scale_triangles(int T);
  // Serial, in order: history and sums (the forces reached the nodes in the pair loop).
  ContactStepStats finish();
  // Node range of thread c of T in the scatter: [node_bound_[c], node_bound_[c + 1]).
  Index range_begin(int c) const { return node_bound_[static_cast<std::size_t>(c)]; }
  // node_bound_ = T equal node ranges of nn nodes.
  void equal_node_ranges(std::size_t nn, int T);
  // More than one thread: thread t notes its records [first, last) (one pair's) in the
  // lists of the node ranges that the pair's six nodes touch (thread 0 not in its own:
  // it added those forces in the pair loop).
  void note_touching(const ContactInput& in, const ContactPair& pr, int t, int T, std::size_t first, std::size_t last);
  // More than one thread: adds the forces of the records that touch node range c (of T)
  // to its nodes, in record order; the other nodes are left alone.
  void scatter_forces(const ContactInput& in, std::vector<Vec2>& f, int c, int T) const;

  ContactSettings settings_;
  double skin_ = 0.0;
  bool invalidated_ = true;
  std::size_t n_triangles_ = 0;
  BroadPhase broad_;
  ContactHistory history_;
  std::vector<Spheropolygon> sp_;
  // Of sp_[t].core; expand() per pair (memory per triangle). Computed each step either for
  // the triangles of the pairs examined only (scale_tris_, collected by a serial pass),
  // or, while most triangles of the candidate pairs are in pairs examined, with their
  // shapes in update_shapes() (scales_with_shapes_): then the serial pass and its
  // barrier would cost more than the extra scales. The same values either way.
  std::vector<CoreEdgeScales> edge_scales_;
  bool scales_with_shapes_ = false;  // decided at the end of each call for the next one
  std::vector<Aabb> box_;  // current boxes of the rounded shapes
  // Broad-phase slots (BroadPhase::active_triangles()) of the triangles in some candidate
  // pair (ascending), set at each broad-phase build: only their shapes are updated each
  // step. A contact zone's interior (one body, no pairs) is skipped.
  std::vector<Index> shape_slots_;
  // The other active triangles' slots (ascending), for their rebuild test in update_shapes().
  std::vector<Index> other_slots_;
  // Per triangle flags: kInPair (in some candidate pair of the build), and kScales
  // within a call for the triangles put into scale_tris_.
  static constexpr std::uint8_t kInPair = 2, kScales = 1;
  std::vector<std::uint8_t> in_pair_;
  std::vector<Index> scale_tris_;
  // A pair is examined when its rounded boxes overlap and it is not skipped; todo_[t]:
  // the indices of such pairs that thread t found in its chunk of the pair list this call.
  std::vector<ThreadVector<Index>> todo_;
  // More than one thread: running sums of the examined pairs' expected costs
  // (pair_weight), per list of todo_. The pair loop splits the pairs by these sums, not by
  // count: contacts are not spread evenly over the pair list.
  std::vector<ThreadVector<std::uint32_t>> todo_weight_;
  // Expected cost of examining a pair, from skip_below_ (its last check): a pair with n
  // contacts costs about 2 + 2 n times one found apart (from instruction counts of the
  // narrow phase per pair and of the law and mapping per contact).
  static std::uint32_t pair_weight(float skip_below) {
    return skip_below < 0.0f ? 2u + 2u * static_cast<std::uint32_t>(-skip_below) : 1u;
  }
  // Examined pairs, in pair order over todo_[0..T), whose running weight is <= w.
  std::size_t pairs_within_weight(std::uint64_t w, int T) const;
  // Pairs whose cores were found apart by some clearance are skipped until their cores
  // have moved that much (vertex neighbours of a discrete mesh that never touch are
  // common); so are pairs whose boxes were apart (the skin's extras), without loading
  // the boxes again.
  // motion_[t]: summed largest core-vertex
  // displacement of triangle t per step since the last build; skip_below_[p]: pair p is
  // skipped while motion_[i] + motion_[j] < it (0: check). Skipped pairs are exactly pairs
  // the narrow phase would find without contact, so results do not change. -n: the pair
  // had n contacts at its last check (its next check skips cores_clearance()); +inf:
  // skip() said yes in this skip_epoch_.
  std::vector<double> motion_;
  std::vector<float> skip_below_;
  long skip_epoch_ = -1;
  std::vector<ThreadVector<ContactRecord>> buffers_;  // one per thread
  // touching_[u T + c]: indices into buffers_[u] of the records with a node in range c,
  // ascending (more than one thread). Each thread reads only those in the scatter, not
  // every record.
  std::vector<ThreadVector<Index>> touching_;
  // More than one thread: the threads' regions (exec/), each with its shares tuned from
  // the threads' busy times: the shape update, the split path (filter and pair loop: see
  // compute_split) and one partition (each thread's run of shape_slots_, and so of the
  // pairs, tuned from its shapes, filter and pair loop together).
  exec::TunedRegion shape_region_;
  exec::SplitRegion split_region_;
  exec::PartitionedRegion partition_;
  // This call's node ranges of the threads (scatter_forces), T + 1 bounds: with one
  // partition, each starts at the first node of the thread's first triangle (nodes are
  // numbered by first use), so the nodes a thread's pairs touch are mostly in its range.
  std::vector<Index> node_bound_, tri_bound_;
  bool node_split_partitioned_ = false;  // node_bound_ came from the partition
  // The contact sums per block of pairs (triangle i / kSumBlock), in record order, by the
  // thread that made the records while they are in its cache; block_sums_[t]: thread t's
  // blocks in order, added in thread order by finish(). A serial sum over every record
  // would read each other thread's records from that core. Counts per thread (integers:
  // any order).
  static constexpr Index kSumBlock = 32;
  std::vector<ThreadVector<BlockSums>> block_sums_;
  // The last call's records whose dashpot work settle_previous() completes this call:
  // buffers_[0, late_sources_), or pending_ (restored from a checkpoint) when late_pending_;
  // late_blocks_[u]: the sums per block of source u, in record order. late_due_: this
  // call has not settled them yet.
  std::vector<ThreadVector<double>> late_blocks_;
  std::vector<DashpotRecord> pending_;
  int late_sources_ = 0;
  bool late_pending_ = false;
  bool late_due_ = false;
  struct alignas(64) ThreadCounts {
    Index active = 0, sliding = 0;
  };
  std::vector<ThreadCounts> thread_counts_;
  int used_threads_ = 0;
  bool cache_skip_ = false;  // this call's skip_epoch >= 0 (see compute())
  double last_elastic_energy_ = 0.0;
};

}  // namespace dsdem::contact

#include "contact/contact_kernels.hpp"  // the template members
