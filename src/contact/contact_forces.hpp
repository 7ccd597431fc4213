#pragma once
// Contact phase of the time step (DESIGN.md §1 step 5, §4): broad phase, narrow
// phase, contact law and shape-function mapping, adding the contact forces to the
// node forces. Called once per step; keeps its buffers and the tangential history
// between calls and allocates nothing once they have grown (warm-up).
//
// Determinism: candidate pairs are sorted (i < j), each pair's contacts are computed
// independently (in parallel with OpenMP, static contiguous chunks), and every node
// gets its contact forces in pair/feature order (one thread per node range), so the
// result does not depend on the thread count.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <vector>

#include "contact/broad_phase.hpp"
#include "contact/buffer.hpp"
#include "contact/contact_history.hpp"
#include "contact/contact_law.hpp"
#include "contact/narrow_phase.hpp"
#include "contact/positions.hpp"
#include "contact/spheropolygon.hpp"
#include "exec/partitioned_region.hpp"

namespace dsdem::contact {

// Contact parameters per pair of groups (any per-triangle index: material, surface
// group, ...), symmetric, with a default for pairs not set. Restitution is turned
// into a damping ratio when an entry is set, not per contact.
class ContactParamTable {
 public:
  explicit ContactParamTable(const ContactProperties& default_props = {});
  void set_default(const ContactProperties& p);
  void set(Index g1, Index g2, const ContactProperties& p);  // g >= 0
  // Parameters of a pair; the default when either index is negative or was never set.
  const ContactLawParams& get(Index g1, Index g2) const {
    if (g1 < 0 || g2 < 0 || g1 >= n_ || g2 >= n_) return entries_[0];
    return entries_[table_[static_cast<std::size_t>(g1) * n_ + g2]];
  }

 private:
  Index n_ = 0;
  std::vector<ContactLawParams> entries_;  // [0] = default
  std::vector<Index> table_;               // n_ x n_ -> entry
};

struct ContactSettings {
  // Broad-phase skin, m: boxes are enlarged by skin/2 per side and the pair list is
  // rebuilt when a node has moved more than skin/2. <= 0: 0.5 * the mean inradius of
  // the contact triangles at the first call.
  double skin = 0.0;
  // Below this many candidate pairs the pair loop runs on one thread.
  std::size_t min_pairs_per_parallel_run = 128;
  // Below this many pairs examined in a step (after the parallel filter), the first thread
  // alone computes their edge data, contacts and forces: a split costs three barriers,
  // which a few dozen pairs do not repay.
  std::size_t min_examined_pairs_to_split = 64;
  // false: every loop on one thread (the solver turns OpenMP off for small models; a
  // parallel region there costs more than it saves, and far more on a loaded machine).
  bool parallel = true;
  // Where the cores' edge data are computed (ContactForces::edge_scales_): automatic
  // chooses each step; the others force one way (tests: the results are the same).
  enum class EdgeScales { automatic, with_shapes, examined_only };
  EdgeScales edge_scales = EdgeScales::automatic;
  // Several threads: one partition of the contact triangles per step (ContactForces::
  // compute_partitioned): each thread updates the shapes of a contiguous run of them,
  // then filters and examines the pairs whose triangle i is in its run, with no barrier
  // between its filter and its pair loop. false: the shapes, the filter and the pair loop
  // are split each on its own (tests: the results are the same).
  bool one_partition = true;
};

// The model arrays the contact phase reads (sizes: nodes for x, v, mass, u; triangles
// for conn, active, rounding_radius, group, body).
struct ContactInput {
  std::span<const Vec2> x;       // current node positions, m (reference positions when u is given)
  std::span<const Vec2> v;       // node velocities, m/s (the half-step ones in Verlet)
  std::span<const double> mass;  // lumped node masses, kg (per unit thickness)
  std::span<const std::array<Index, 3>> conn;
  std::span<const std::uint8_t> active;      // != 0: the triangle takes part (zones A, C)
  std::span<const double> rounding_radius;   // per triangle, m (see rounding_radius())
  std::span<const Index> group;              // per triangle, index into ContactParamTable
  // Optional, per triangle: two triangles with the same body id >= 0 never interact
  // (e.g. 0 for every zone-C triangle: one continuous mesh that cannot separate), and
  // such pairs are left out of the broad phase. Empty: only the shared-node rule.
  std::span<const Index> body = {};
  // Optional node displacements, m: the current positions are then x + u (NodePositions).
  std::span<const Vec2> u = {};
  NodePositions positions() const { return {x, u}; }
};

// One contact of the last call. The constructor leaves the values unset: the contact
// phase writes every field, so a zero-fill would be wasted work on every record.
struct ContactRecord {
  ContactRecord() {}  // user-provided: emplace_back() does not zero-fill either
  // What scatter_forces() reads comes first and together (key, force, Ni, Nj: 80 B, two
  // cache lines, not three): on two threads each thread reads every record.
  ContactKey key;  // triangles i < j and feature (see ContactGeometry)
  ContactKind kind;
  std::uint8_t other;
  bool sliding;
  Vec2 force;                    // total force on i (on j: -force)
  Vec3 Ni;                       // shape functions of i and j at the point
  Vec3 Nj;
  double overlap;                // m
  double fn;                     // normal force on i, N/m
  Vec2 normal;                   // from j to i
  Vec2 point;                    // contact point, m
  Vec2 ft;                       // tangential force on i, N/m
  double elastic_energy;         // J/m
  double friction_dissipation;   // J/m this step
  // The dashpot's part of fn (ContactLawResult::dashpot_force), N/m, and the half of its
  // work booked at this step; the other half is booked at the next call (settle_previous).
  double damping_dissipation;    // J/m
  double dashpot_force;
};
static_assert(sizeof(ContactRecord) <= 176, "keep the contact record compact (memory per contact)");

// What a contact's dashpot force needs for the second half of its work (a checkpoint keeps
// these between a run and its restart; see ContactForces::settle_previous).
struct DashpotRecord {
  ContactKey key;
  Vec3 Ni, Nj;
  Vec2 normal;
  double dashpot_force = 0.0;
};


struct ContactStepStats {
  Index active_contacts = 0;
  Index sliding_contacts = 0;
  Index candidate_pairs = 0;
  // Candidates known to be apart (not examined): their cores or boxes were apart by more
  // than they have moved since.
  Index skipped_pairs = 0;
  Index examined_pairs = 0;  // candidates sent to the narrow phase
  bool rebuilt = false;                  // the broad phase was rebuilt this call
  double elastic_energy = 0.0;           // stored in all contacts now, J/m
  double elastic_energy_increment = 0.0; // change since the previous call, J/m
  double friction_dissipation = 0.0;     // Coulomb sliding this step, J/m
  // Normal dashpots' work this step, J/m: half of this call's forces' (at the half-step
  // velocity they were computed with) and half of the last call's (at this call's).
  double damping_dissipation = 0.0;
};

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
               std::vector<DashpotRecord> dashpots = {}) {
    pending_ = std::move(dashpots);
    if (late_blocks_.empty()) late_blocks_.resize(1);
    reserve_with_headroom(late_blocks_[0], pending_.size() + 4);
    history_.clear();
    history_.begin_step();
    for (const auto& e : entries) history_.record(e.key, e.ft);
    history_.end_step();
    last_elastic_energy_ = last_elastic_energy;
    if (skin > 0.0) settings_.skin = skin;
    invalidated_ = true;
  }
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
  // The second half of the work of the last call's dashpot forces (DESIGN.md §1 steps 1
  // and 8, §6): velocity Verlet applies a force of step n half into v(n) and half into
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

template <class Skip>
bool ContactForces::compute_partitioned(const ContactInput& in, const ContactParamTable& params, double dt,
                                        Skip& skip, std::vector<Vec2>& f, int nt, Index& skipped) {
  ensure_thread_lists(nt);
  partition_.prepare(nt);
  history_.begin_step(nt);
  const std::size_t nn = f.size();
  // The nt parts: triangles [tri_bound_[u], tri_bound_[u + 1]) and their first nodes.
  tri_bound_.resize(static_cast<std::size_t>(nt) + 1);
  node_bound_.resize(static_cast<std::size_t>(nt) + 1);
  for (int u = 0; u <= nt; ++u) {
    const Index tri = partition_begin(u, nt);
    tri_bound_[static_cast<std::size_t>(u)] = tri;
    Index node = static_cast<Index>(nn);
    if (u == 0) node = 0;
    else if (tri < static_cast<Index>(in.conn.size()))
      node = std::min({in.conn[tri][0], in.conn[tri][1], in.conn[tri][2]});
    node_bound_[static_cast<std::size_t>(u)] = u > 0 ? std::max(node, node_bound_[static_cast<std::size_t>(u) - 1]) : 0;
  }
  node_split_partitioned_ = true;
  // The kernels of one partition (exec::PartitionedRegion): thread t of T holds the
  // triangles [from, to) (T = 1: all), their shapes, and the pairs whose triangle i they hold.
  struct Kernels {
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
  Kernels k{*this, in, params, dt, skip, f, broad_.pairs(), broad_.active_triangles()};
  const exec::PartitionedRegion::Result r = partition_.run(nt, k);
  skipped += static_cast<Index>(r.count);
  used_threads_ = r.threads;
  late_due_ = false;
  if (used_threads_ == 1) equal_node_ranges(nn, 1);
  return !r.stopped;
}

template <class Skip>
void ContactForces::compute_split(const ContactInput& in, const ContactParamTable& params, double dt, Skip& skip,
                                  std::vector<Vec2>& f, Index& skipped) {
  const std::size_t np = broad_.pairs().size();
  const int nt = begin_pairs(np);
  // Each thread writes its contacts' history to a segment of its own, and its blocks' sums.
  history_.begin_step(nt);
  equal_node_ranges(f.size(), nt);
  // The kernels of the split path (exec::SplitRegion).
  struct Kernels {
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
  Kernels k{*this, in, params, dt, skip, f, broad_.pairs(), cache_skip_, late_due_};
  const exec::SplitRegion::Result r = split_region_.run(nt, np, k);
  skipped += static_cast<Index>(r.count);
  used_threads_ = r.threads;
  late_due_ = false;
}

}  // namespace dsdem::contact
