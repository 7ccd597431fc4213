#include "contact/contact_forces.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "contact/buffer.hpp"
#include "contact/dashpot_mass.hpp"
#include "contact/shape_map.hpp"
#include "contact/shapes_x2.hpp"

namespace dsdem::contact {


ContactParamTable::ContactParamTable(const ContactProperties& default_props) {
  entries_.push_back(law_params(default_props));
}

void ContactParamTable::set_default(const ContactProperties& p) { entries_[0] = law_params(p); }

void ContactParamTable::set(Index g1, Index g2, const ContactProperties& p) {
  if (g1 < 0 || g2 < 0) throw std::invalid_argument("contact parameter groups must be >= 0");
  const Index n = std::max({n_, g1 + 1, g2 + 1});
  if (n > n_) {  // grow the table, keeping what was set
    std::vector<Index> t(static_cast<std::size_t>(n) * n, 0);
    for (Index a = 0; a < n_; ++a)
      for (Index b = 0; b < n_; ++b)
        t[static_cast<std::size_t>(a) * n + b] = table_[static_cast<std::size_t>(a) * n_ + b];
    table_.swap(t);
    n_ = n;
  }
  entries_.push_back(law_params(p));
  const Index e = static_cast<Index>(entries_.size() - 1);
  table_[static_cast<std::size_t>(g1) * n_ + g2] = e;
  table_[static_cast<std::size_t>(g2) * n_ + g1] = e;
}

namespace {

// The second halves of the dashpot work of records (see settle_previous), summed per
// block of key.i / block_size in record order into blocks (one entry per block with a
// dashpot force). A record without one adds nothing (+0) and is passed over.
template <class Record>
void settle_records(std::span<const Record> records, const ContactInput& in, double dt, Index block_size,
                    std::vector<double>& blocks) {
  blocks.clear();
  Index block = -1;
  double sum = 0.0;
  for (const Record& r : records) {
    if (r.dashpot_force == 0.0) continue;
    if (r.key.i / block_size != block) {
      if (block >= 0) blocks.push_back(sum);
      sum = 0.0;
      block = r.key.i / block_size;
    }
    const Vec2 v_rel =
        point_velocity(r.Ni, in.conn[r.key.i], in.v) - point_velocity(r.Nj, in.conn[r.key.j], in.v);
    sum += -0.5 * dt * r.dashpot_force * r.normal.dot(v_rel);
  }
  if (block >= 0) blocks.push_back(sum);
}

bool shares_node(const std::array<Index, 3>& a, const std::array<Index, 3>& b) {
  for (Index p : a)
    for (Index q : b)
      if (p == q) return true;
  return false;
}

void check_size(std::size_t got, std::size_t want, const char* what) {
  if (got != want) {
    throw std::invalid_argument(std::string("contact input: ") + what + " has " +
                                std::to_string(got) + " entries, expected " +
                                std::to_string(want));
  }
}

}  // namespace

bool ContactForces::check_input(const ContactInput& in, std::size_t n_forces) {
  const std::size_t nn = in.x.size();
  const std::size_t nt = in.conn.size();
  const NodePositions x = in.positions();
  if (!in.u.empty()) check_size(in.u.size(), nn, "u");
  check_size(n_forces, nn, "f");
  check_size(in.v.size(), nn, "v");
  check_size(in.mass.size(), nn, "mass");
  check_size(in.active.size(), nt, "active");
  check_size(in.rounding_radius.size(), nt, "rounding_radius");
  check_size(in.group.size(), nt, "group");
  if (!in.body.empty()) check_size(in.body.size(), nt, "body");

  if (!(skin_ > 0.0)) {
    skin_ = settings_.skin;
    if (!(skin_ > 0.0)) {  // auto: half the mean inradius of the contact triangles
      double sum = 0.0;
      std::size_t n = 0;
      for (std::size_t t = 0; t < nt; ++t) {
        if (!in.active[t]) continue;
        const auto& c = in.conn[t];
        sum += incircle(x[c[0]], x[c[1]], x[c[2]]).radius;
        ++n;
      }
      skin_ = n > 0 && sum > 0.0 ? 0.5 * sum / static_cast<double>(n) : 1.0;
    }
  }

  sp_.resize(nt);
  edge_scales_.resize(nt);
  box_.resize(nt);
  // Without a pending build, the shape update also runs the broad phase's rebuild test,
  // of its triangles (their nodes are loaded anyway) and of the others: a build then
  // redoes the shapes of the new pair list (the same values: same inputs).
  return invalidated_ || nt != n_triangles_ || broad_.stale(x.size());
}

void ContactForces::build(const ContactInput& in) {
  const std::size_t nt = in.conn.size();
  const NodePositions x = in.positions();
  const auto conn = in.conn;
  const auto body = in.body;
  if (body.empty()) {
    broad_.build(x, in.conn, in.active, skin_,
                 [conn](Index i, Index j) { return shares_node(conn[i], conn[j]); });
  } else {
    broad_.build(x, in.conn, in.active, skin_, [conn, body](Index i, Index j) {
      return (body[i] >= 0 && body[i] == body[j]) || shares_node(conn[i], conn[j]);
    });
  }
  invalidated_ = false;
  n_triangles_ = nt;
  in_pair_.assign(nt, 0);
  for (const ContactPair& p : broad_.pairs()) in_pair_[p.i] = in_pair_[p.j] = kInPair;
  shape_slots_.clear();
  other_slots_.clear();
  if (shape_slots_.capacity() < nt) shape_slots_.reserve(nt);  // once: rebuilds happen in the time loop
  if (other_slots_.capacity() < nt) other_slots_.reserve(nt);
  if (scale_tris_.capacity() < nt) scale_tris_.reserve(nt);
  const std::span<const Index> tris = broad_.active_triangles();
  for (std::size_t slot = 0; slot < tris.size(); ++slot)
    (in_pair_[tris[slot]] ? shape_slots_ : other_slots_).push_back(static_cast<Index>(slot));
  // New pairs: every one checked at its first step; motions counted from the build.
  reserve_with_headroom(skip_below_, broad_.pairs().size());
  skip_below_.assign(broad_.pairs().size(), 0.0f);
  motion_.assign(nt, 0.0);
  update_shapes(in, true);
}

void ContactForces::restore(const std::vector<ContactHistory::Entry>& entries, double last_elastic_energy,
                            double skin, std::vector<DashpotRecord> dashpots) {
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

void ContactForces::set_partition_bounds(const ContactInput& in, std::size_t nn, int nt) {
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
}

int ContactForces::partition_threads() const {
  if (settings_.parallel && settings_.one_partition && broad_.pairs().size() >= settings_.min_pairs_per_parallel_run &&
      static_cast<std::ptrdiff_t>(shape_slots_.size() + other_slots_.size()) > kMinParallelTriangles)
    return exec::max_threads();
  return 1;
}

void ContactForces::equal_node_ranges(std::size_t nn, int T) {
  node_bound_.resize(static_cast<std::size_t>(T) + 1);
  for (int c = 0; c <= T; ++c) node_bound_[static_cast<std::size_t>(c)] = static_cast<Index>(nn * c / T);
  node_split_partitioned_ = false;
}

Index ContactForces::partition_begin(int u, int T) const {
  if (u <= 0) return 0;
  const std::size_t n = shape_slots_.size();
  const std::size_t s = u >= T ? n : partition_.begin(n, u);
  if (s >= n) return std::numeric_limits<Index>::max();
  const Index tri = broad_.active_triangles()[static_cast<std::size_t>(shape_slots_[s])];
  return tri - tri % kSumBlock;  // no sum block split between threads
}

bool ContactForces::update_shapes(const ContactInput& in, bool rebuilt) {
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(shape_slots_.size());
  const std::ptrdiff_t n_others = rebuilt ? 0 : static_cast<std::ptrdiff_t>(other_slots_.size());
  const bool parallel = settings_.parallel && n + n_others > kMinParallelTriangles;
  // Each thread a contiguous run of slot pairs, tuned from the threads' busy times.
  const auto np2 = static_cast<std::size_t>((n + 1) / 2);
  const int threads = parallel ? exec::max_threads() : 1;
  const int left = shape_region_.run(threads, np2, [&](std::size_t q_begin, std::size_t q_end) {
    int run_left = 0;  // a flag, so any thread count gives the same answer
    const auto s_begin = 2 * static_cast<std::ptrdiff_t>(q_begin);
    update_shape_run(in, s_begin, std::min(2 * static_cast<std::ptrdiff_t>(q_end), n), rebuilt, run_left);
    if (!rebuilt) test_other_slots(in, run_left);
    return run_left;
  });
  return left != 0;
}

void ContactForces::update_shape_run(const ContactInput& in, std::ptrdiff_t s_begin, std::ptrdiff_t s_end,
                                     bool rebuilt, int& left) {
  const NodePositions x = in.positions();
  const std::span<const Index> tris = broad_.active_triangles();
  const std::span<const Aabb> build_box = broad_.boxes();
  // Two triangles at a time, the last one twice when the count is odd; each lane equals the
  // scalar functions bit for bit (shapes_x2.hpp), so any pairing gives the same shapes.
  for (std::ptrdiff_t s = s_begin; s < s_end; s += 2) {
    const std::ptrdiff_t s_of[2] = {s, std::min(s + 1, s_end - 1)};
    std::array<Vec2, 3> p[2];
    Index t_of[2];
    for (int lane = 0; lane < 2; ++lane) {
      const Index slot = shape_slots_[s_of[lane]];
      const Index t = tris[slot];
      t_of[lane] = t;
      const auto& c = in.conn[t];
      p[lane] = {x[c[0]], x[c[1]], x[c[2]]};
      // The broad phase's rebuild test (BroadPhase::needs_rebuild) for this triangle.
      for (const Vec2& v : p[lane])
        if (!contains(build_box[slot], v)) left = 1;
    }
    Spheropolygon shape[2];
    CoreEdgeScales scales[2];
#if defined(DSDEM_SHAPES_X2)
    make_shapes_x2(p[0], p[1], in.rounding_radius[t_of[0]], in.rounding_radius[t_of[1]], shape[0], shape[1],
                   scales_with_shapes_ ? &scales[0] : nullptr, &scales[1]);
#else
    for (int lane = 0; lane < 2; ++lane) {
      shape[lane] = make_spheropolygon(p[lane][0], p[lane][1], p[lane][2], in.rounding_radius[t_of[lane]]);
      if (scales_with_shapes_) scales[lane] = core_edge_scales(shape[lane].core);
    }
#endif
    for (int lane = 0; lane < (s_of[1] == s_of[0] ? 1 : 2); ++lane) {
      const Index t = t_of[lane];
      // The largest core-vertex displacement since the last step bounds how much any gap
      // measured between this core and another can have shrunk (triangle inequality). At
      // a build the motions restart from these shapes (some were not updated before).
      if (!rebuilt) {
        double d2 = 0.0;
        for (int k = 0; k < 3; ++k) d2 = std::max(d2, (shape[lane].core[k] - sp_[t].core[k]).squaredNorm());
        motion_[t] += std::sqrt(d2);
      }
      sp_[t] = shape[lane];
      box_[t] = bounding_box(shape[lane]);
      if (scales_with_shapes_) edge_scales_[t] = scales[lane];
    }
  }
}

void ContactForces::test_other_slots(const ContactInput& in, int& left, bool shared) {
  // The rebuild test for the active triangles in no pair (no shape to update), from their
  // list: shared, each thread tests an equal share. (A split of all the active slots would
  // be uneven: discrete triangles, numbered first, are nearly all in pairs.)
  const NodePositions x = in.positions();
  const std::span<const Index> tris = broad_.active_triangles();
  const std::span<const Aabb> build_box = broad_.boxes();
  const std::size_t n_others = other_slots_.size();
  auto test = [&](std::size_t s) {
    const Index slot = other_slots_[s];
    const auto& c = in.conn[tris[slot]];
    for (int k = 0; k < 3; ++k)
      if (!contains(build_box[slot], x[c[k]])) left = 1;
  };
  if (!shared) {
    for (std::size_t s = 0; s < n_others && !left; ++s) test(s);
    return;
  }
  exec::shared_for_nowait(n_others, [&](std::size_t s) {
    if (!left) test(s);
  });
}

int ContactForces::begin_pairs(std::size_t n_pairs) {
  const int nt = settings_.parallel && n_pairs >= settings_.min_pairs_per_parallel_run ? exec::max_threads() : 1;
  ensure_thread_lists(nt);
  return nt;
}

void ContactForces::settle_previous(const ContactInput& in, double dt, int t, int T) {
  if (late_pending_) {
    if (t == 0) settle_records(std::span<const DashpotRecord>(pending_), in, dt, kSumBlock, late_blocks_[0]);
    return;
  }
  for (int u = t; u < late_sources_; u += T)
    settle_records(std::span<const ContactRecord>(buffers_[u]), in, dt, kSumBlock, late_blocks_[u]);
}

std::vector<DashpotRecord> ContactForces::dashpot_records() const {
  if (!pending_.empty()) return pending_;
  std::vector<DashpotRecord> out;
  for_each_contact([&out](const ContactRecord& c) {
    if (c.dashpot_force != 0.0) out.push_back({c.key, c.Ni, c.Nj, c.normal, c.dashpot_force});
  });
  return out;
}

void ContactForces::ensure_thread_lists(int nt) {
  const auto n = static_cast<std::size_t>(nt);
  if (buffers_.size() < n) buffers_.resize(n);
  if (late_blocks_.size() < n) late_blocks_.resize(n);
  if (todo_.size() < n) todo_.resize(n);
  if (todo_weight_.size() < n) todo_weight_.resize(n);
  if (touching_.size() < n * n) touching_.resize(n * n);
  if (thread_counts_.size() < n) thread_counts_.resize(n);
  if (block_sums_.size() < n) block_sums_.resize(n);
}

void ContactForces::collect_scale_triangles(int T) {
  scale_tris_.clear();
  const std::span<const ContactPair> pairs = broad_.pairs();
  for (int t = 0; t < T; ++t) {
    for (const Index p : todo_[t]) {
      for (const Index tri : {pairs[p].i, pairs[p].j}) {
        if (in_pair_[tri] & kScales) continue;
        in_pair_[tri] |= kScales;
        scale_tris_.push_back(tri);
      }
    }
  }
}

double ContactForces::process_pair(Index i, Index j, const CoreEdgeScales& scales_i, const CoreEdgeScales& scales_j,
                                   const ContactInput& in, const ContactParamTable& params, double dt,
                                   bool check_apart, ContactHistory::Cursor& cursor,
                                   std::vector<ContactRecord>& out, std::span<Vec2> f_now) const {
  std::array<ContactGeometry, kMaxContactsPerPair> geo;
  double clearance = 0.0;
  const int n = narrow_phase(sp_[i], scales_i, sp_[j], scales_j, geo, &clearance, check_apart);
  if (n == 0) return clearance;
  const NodePositions x = in.positions();
  const auto& ci = in.conn[i];
  const auto& cj = in.conn[j];
  const ContactLawParams& p = params.get(in.group[i], in.group[j]);
  // Per pair, for all its contacts (the same operations as per contact).
  const BarycentricFrame frame_i = barycentric_frame(x[ci[0]], x[ci[1]], x[ci[2]]);
  const BarycentricFrame frame_j = barycentric_frame(x[cj[0]], x[cj[1]], x[cj[2]]);
  const PairDashpotMass dashpot = pair_dashpot_mass(ci, cj, in.mass, dt, p.damping_ratio, p.kn);
  for (int k = 0; k < n; ++k) {
    const ContactGeometry& g = geo[k];
    ContactRecord& r = out.emplace_back();  // filled in place: no copy of the record
    r.key = {i, j, g.feature};
    r.kind = g.kind;
    r.other = g.other;
    r.overlap = g.overlap;
    r.normal = g.normal;
    r.point = g.point;
    r.Ni = barycentric(g.point, frame_i);
    r.Nj = barycentric(g.point, frame_j);
    const Vec2 v_rel = point_velocity(r.Ni, ci, in.v) - point_velocity(r.Nj, cj, in.v);
    // Dashpot mass: the two triangles' reduced mass, capped for the point's own mass.
    const double m_eff = contact_dashpot_mass(dashpot, r.Ni, ci, r.Nj, cj, in.mass);
    const ContactLawResult law =
        contact_law(g.overlap, g.normal, v_rel, dt, history_.previous(r.key, cursor), m_eff, p);
    r.sliding = law.sliding;
    r.fn = law.fn;
    r.ft = law.ft;
    r.force = law.force;
    r.elastic_energy = law.elastic_energy;
    r.friction_dissipation = law.friction_dissipation;
    r.dashpot_force = law.dashpot_force;
    r.damping_dissipation = 0.5 * law.damping_dissipation;  // the first half (settle_previous)
    if (f_now.size() == in.x.size()) {
      add_point_force(r.Ni, ci, r.force, f_now);
      add_point_force(r.Nj, cj, -r.force, f_now);
    } else if (!f_now.empty()) {  // add_point_force() on the nodes below f_now.size() only
      const Index end = static_cast<Index>(f_now.size());
      const Vec2 minus = -r.force;
      for (int k = 0; k < 3; ++k)
        if (ci[k] < end) f_now[ci[k]] += r.Ni[k] * r.force;
      for (int k = 0; k < 3; ++k)
        if (cj[k] < end) f_now[cj[k]] += r.Nj[k] * minus;
    }
  }
  return -static_cast<double>(n);
}

void ContactForces::examine_pairs(const std::vector<Index>& list, std::size_t k_begin, std::size_t k_end,
                                  const ContactInput& in, const ContactParamTable& params, double dt,
                                  PairRun& run) {
  const std::span<const ContactPair> pairs = broad_.pairs();
  std::vector<ContactRecord>& out = buffers_[run.t];
  std::vector<ContactHistory::Entry>& history_out = history_.segment(run.t);
  for (std::size_t k = k_begin; k < k_end; ++k) {
    const Index p = list[k];
    const ContactPair pr = pairs[p];
    const double moved = motion_[pr.i] + motion_[pr.j];
    const std::size_t before = out.size();
    double res;
    if (run.own_scales) {  // the same values as edge_scales_ would hold (same shapes)
      const CoreEdgeScales si = core_edge_scales(sp_[pr.i].core), sj = core_edge_scales(sp_[pr.j].core);
      res = process_pair(pr.i, pr.j, si, sj, in, params, dt, skip_below_[p] >= 0.0f, run.cursor, out, run.f_now);
    } else {
      res = process_pair(pr.i, pr.j, edge_scales_[pr.i], edge_scales_[pr.j], in, params, dt, skip_below_[p] >= 0.0f,
                         run.cursor, out, run.f_now);
    }
    // Sums of the records of each block (pairs whose triangle i / kSumBlock is the same),
    // in record order; finish() adds the blocks in order. Only blocks with records count,
    // so the sums depend on the records alone: the same for any split, thread count or
    // pair list (pairs skipped while apart, a rebuilt broad phase).
    if (out.size() > before && pr.i / kSumBlock != run.block) {
      if (run.block >= 0) block_sums_[run.t].push_back(run.sums);
      run.sums = BlockSums{};
      run.block = pr.i / kSumBlock;
    }
    for (std::size_t r = before; r < out.size(); ++r) {
      const ContactRecord& rec = out[r];
      history_out.push_back({rec.key, rec.ft});
      run.sums.elastic_energy += rec.elastic_energy;
      run.sums.friction_dissipation += rec.friction_dissipation;
      run.sums.damping_dissipation += rec.damping_dissipation;
      run.sliding += rec.sliding ? 1 : 0;
    }
    run.active += static_cast<Index>(out.size() - before);
    if (run.note && out.size() > before) note_touching(in, pr, run.t, run.T, before, out.size());
    // Half the clearance: margin for the float and for the sums' rounding.
    skip_below_[p] = res > 0.0 ? below(moved + 0.5 * res) : static_cast<float>(res);
  }
}

void ContactForces::end_pair_run(const PairRun& run) {
  if (run.block >= 0) block_sums_[run.t].push_back(run.sums);
  thread_counts_[run.t] = {run.active, run.sliding};
}

std::size_t ContactForces::pairs_within_weight(std::uint64_t w, int T) const {
  std::size_t before = 0;
  for (int u = 0; u < T; ++u) {
    const std::vector<std::uint32_t>& upto = todo_weight_[u];
    const std::uint64_t in_list = upto.empty() ? 0 : upto.back();
    if (w < in_list) return before + static_cast<std::size_t>(std::upper_bound(upto.begin(), upto.end(), w) - upto.begin());
    w -= in_list;
    before += upto.size();
  }
  return before;
}

void ContactForces::note_touching(const ContactInput& in, const ContactPair& pr, int t, int T, std::size_t first,
                                  std::size_t last) {
  const auto& ci = in.conn[pr.i];
  const auto& cj = in.conn[pr.j];
  for (int c = t == 0 ? 1 : 0; c < T; ++c) {
    const Index lo = range_begin(c), hi = range_begin(c + 1);
    bool touches = false;
    for (int k = 0; k < 3; ++k) touches |= (ci[k] >= lo && ci[k] < hi) || (cj[k] >= lo && cj[k] < hi);
    if (!touches) continue;
    std::vector<Index>& list = touching_[t * T + c];
    for (std::size_t r = first; r < last; ++r) list.push_back(static_cast<Index>(r));
  }
}

void ContactForces::scatter_forces(const ContactInput& in, std::vector<Vec2>& f, int c, int T) const {
  const Index lo = range_begin(c), hi = range_begin(c + 1);
  // add_point_force() restricted to [lo, hi): the same products, added in the same order.
  auto add = [&f, lo, hi](const Vec3& N, const std::array<Index, 3>& nodes, const Vec2& F) {
    for (int k = 0; k < 3; ++k)
      if (nodes[k] >= lo && nodes[k] < hi) f[nodes[k]] += N[k] * F;
  };
  for (int u = 0; u < T; ++u) {
    const std::vector<ContactRecord>& records = buffers_[u];
    for (const Index r : touching_[u * T + c]) {
      const ContactRecord& rec = records[r];
      add(rec.Ni, in.conn[rec.key.i], rec.force);
      add(rec.Nj, in.conn[rec.key.j], -rec.force);
    }
  }
}

ContactStepStats ContactForces::finish() {
  ContactStepStats st;
  // The blocks' sums in block order (see block_sums_), the threads' counts.
  for (int t = 0; t < used_threads_; ++t)
    for (const BlockSums& b : block_sums_[t]) {
      st.elastic_energy += b.elastic_energy;
      st.friction_dissipation += b.friction_dissipation;
      st.damping_dissipation += b.damping_dissipation;
    }
  // The last call's dashpots' second halves, after this call's first halves.
  double late = 0.0;
  for (int u = 0; u < late_sources_; ++u)
    for (const double b : late_blocks_[u]) late += b;
  st.damping_dissipation += late;
  if (late_pending_) std::vector<DashpotRecord>().swap(pending_);  // settled: not needed again
  for (int t = 0; t < used_threads_; ++t) {
    st.active_contacts += thread_counts_[t].active;
    st.sliding_contacts += thread_counts_[t].sliding;
  }
  // Spare room so that a slowly growing contact count does not reallocate every step. Each
  // thread's lists get room for the whole step's count, not only for its own: the split
  // between the threads follows their measured speed (TunedSplit) and may give any thread
  // more than it ever had, which must not allocate in the time loop (docs/developer-guide.md §3). On one
  // thread it is the same room as before.
  std::size_t records = 0, examined = 0, blocks = 0;
  for (int t = 0; t < used_threads_; ++t) {
    records += buffers_[t].size();
    examined += todo_[t].size();
    blocks += block_sums_[t].size();
  }
  const auto room = [](std::size_t n) { return n + n / 8; };
  history_.reserve_headroom(room(records));
  history_.end_step();
  for (int t = 0; t < used_threads_; ++t) {
    reserve_with_headroom(buffers_[t], room(records));
    reserve_with_headroom(block_sums_[t], room(blocks) + 4);
    reserve_with_headroom(late_blocks_[t], room(blocks) + 4);  // settle_previous() of buffer t next call
    if (used_threads_ > 1) {
      reserve_with_headroom(todo_[t], room(examined));
      reserve_with_headroom(todo_weight_[t], room(examined));
      for (int c = 0; c < used_threads_; ++c) reserve_with_headroom(touching_[t * used_threads_ + c], room(records));
    }
  }
  st.elastic_energy_increment = st.elastic_energy - last_elastic_energy_;
  last_elastic_energy_ = st.elastic_energy;
  return st;
}

}  // namespace dsdem::contact
