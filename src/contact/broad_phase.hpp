#pragma once
// Broad phase (docs/theory.md §4): candidate pairs of triangles whose bounding boxes,
// enlarged by half the skin on every side, overlap. Uniform cell grid built by a
// counting sort, O(N) time and memory; pairs in ascending (i, j), i < j. The list
// stays valid while every active triangle's current box lies inside its enlarged box of
// the build: then every pair whose current triangles' boxes overlap is still in it, and
// since the rounded shape lies inside its triangle, so is every contact. (A node moving
// less than half the skin always keeps that; the test needs no copy of the positions.)
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "contact/buffer.hpp"
#include "contact/positions.hpp"
#include "contact/spheropolygon.hpp"

namespace dsdem::contact {

// Below this many triangles the per-triangle loops of the contact phase run on one
// thread: a parallel region costs a few microseconds (threads spinning) to tens (asleep).
// 256, not 1024: the shape update of some hundreds of triangles already repays a split.
constexpr std::ptrdiff_t kMinParallelTriangles = 256;

struct ContactPair {
  Index i = 0;
  Index j = 0;  // i < j
};

class BroadPhase {
 public:
  // Builds the pair list over the triangles with active[t] != 0, from the current
  // node positions x. skip(i, j) -> true leaves the pair out (a callable inlined in
  // the pair loop; it must stay true until the next build, since the list is reused).
  template <class Skip>
  void build(const NodePositions& x, std::span<const std::array<Index, 3>> conn,
             std::span<const std::uint8_t> active, double skin, Skip&& skip);

  void build(const NodePositions& x, std::span<const std::array<Index, 3>> conn,
             std::span<const std::uint8_t> active, double skin) {
    build(x, conn, active, skin, [](Index, Index) { return false; });
  }

  // True when some active triangle of the last build has a node outside its enlarged
  // box of the build (or there was no build, or the node count changed). conn must be
  // the connectivity of the build. parallel: OpenMP over the triangles of large sets.
  // (ContactForces runs the same test within its shape update, from its own lists.)
  bool needs_rebuild(const NodePositions& x, std::span<const std::array<Index, 3>> conn,
                     bool parallel = false) const;

  // True when there was no build or the node count changed (a rebuild is due whatever
  // the positions).
  bool stale(std::size_t n_nodes) const { return builds_ == 0 || n_nodes != n_nodes_; }

  std::span<const ContactPair> pairs() const { return pairs_; }
  double skin() const { return skin_; }
  long builds() const { return builds_; }
  // The enlarged box of triangle active_triangles()[s] at the last build.
  std::span<const Index> active_triangles() const { return tris_; }
  std::span<const Aabb> boxes() const { return boxes_; }
  // Grid of the last build: cell size and cell count.
  double cell_size() const { return cell_size_; }
  long cell_count() const { return static_cast<long>(nx_) * ny_; }
  // An upper bound on the pair count of the last build's grid: the cells' k (k - 1) / 2.
  std::size_t pair_bound() const;

 private:
  // Boxes, grid, cell lists (non-template part, in the .cpp).
  void bin(const NodePositions& x, std::span<const std::array<Index, 3>> conn,
           std::span<const std::uint8_t> active, double skin);
  // Room for the first build's pairs (pair_bound) before its sweep. Grown by doubling, the
  // list's old and new blocks would both be resident at its last growth (peak memory).
  void reserve_first_pairs();
  static constexpr std::size_t kFirstPairsPerTriangleCap = 32;
  int cell_x(double v) const {
    return std::clamp(static_cast<int>((v - origin_.x()) * inv_h_), 0, nx_ - 1);
  }
  int cell_y(double v) const {
    return std::clamp(static_cast<int>((v - origin_.y()) * inv_h_), 0, ny_ - 1);
  }

  std::vector<Index> tris_;   // active triangles, ascending; "slot" s -> triangle
  std::vector<Aabb> boxes_;   // per slot, enlarged by skin/2
  std::vector<Index> cell_start_;  // CSR over cells (nx*ny + 1)
  std::vector<Index> cell_items_;  // slots, ascending within a cell
  std::vector<Index> fill_;        // scratch: write cursor per cell
  std::vector<ContactPair> pairs_;
  Vec2 origin_ = Vec2::Zero();
  double cell_size_ = 1.0, inv_h_ = 1.0, skin_ = 0.0;
  int nx_ = 1, ny_ = 1;
  std::size_t n_nodes_ = 0;
  long builds_ = 0;
};

inline bool BroadPhase::needs_rebuild(const NodePositions& x, std::span<const std::array<Index, 3>> conn,
                                      bool parallel) const {
  if (builds_ == 0 || x.size() != n_nodes_) return true;
  const std::ptrdiff_t ns = static_cast<std::ptrdiff_t>(tris_.size());
  // pos(i) is x[i] or X[i] + u[i], chosen once for the loop rather than per node.
  auto scan = [&](auto pos) {
    int out = 0;  // a flag, so any thread count gives the same answer
#pragma omp parallel for schedule(static) reduction(| : out) if (parallel && ns > kMinParallelTriangles)
    for (std::ptrdiff_t s = 0; s < ns; ++s) {
      if (out) continue;
      const auto& c = conn[tris_[s]];
      const Aabb& b = boxes_[s];
      for (int k = 0; k < 3; ++k)
        if (!contains(b, pos(c[k]))) out = 1;
    }
    return out != 0;
  };
  if (x.u.empty()) return scan([&x](Index i) { return Vec2(x.x[i]); });
  return scan([&x](Index i) { return Vec2(x.x[i] + x.u[i]); });
}

template <class Skip>
void BroadPhase::build(const NodePositions& x, std::span<const std::array<Index, 3>> conn,
                       std::span<const std::uint8_t> active, double skin, Skip&& skip) {
  bin(x, conn, active, skin);
  pairs_.clear();
  if (builds_ == 1) reserve_first_pairs();
  const Index ns = static_cast<Index>(tris_.size());
  for (Index s = 0; s < ns; ++s) {
    const Aabb& a = boxes_[s];
    const Index i = tris_[s];
    const std::size_t first = pairs_.size();
    const int cx0 = cell_x(a.lo.x()), cx1 = cell_x(a.hi.x());
    const int cy0 = cell_y(a.lo.y()), cy1 = cell_y(a.hi.y());
    for (int cy = cy0; cy <= cy1; ++cy) {
      for (int cx = cx0; cx <= cx1; ++cx) {
        const std::size_t c = static_cast<std::size_t>(cy) * nx_ + cx;
        const Index* begin = cell_items_.data() + cell_start_[c];
        const Index* end = cell_items_.data() + cell_start_[c + 1];
        for (const Index* it = std::upper_bound(begin, end, s); it != end; ++it) {
          const Aabb& b = boxes_[*it];
          if (!overlaps(a, b)) continue;
          // Report the pair only in the cell holding the low corner of the two boxes'
          // intersection, which both boxes cover: once, without a hash set.
          if (cell_x(std::max(a.lo.x(), b.lo.x())) != cx ||
              cell_y(std::max(a.lo.y(), b.lo.y())) != cy)
            continue;
          const Index j = tris_[*it];
          if (skip(i, j)) continue;
          pairs_.push_back({i, j});
        }
      }
    }
    std::sort(pairs_.begin() + first, pairs_.end(),
              [](const ContactPair& p, const ContactPair& q) { return p.j < q.j; });
  }
  reserve_with_headroom(pairs_, pairs_.size() + pairs_.size() / 8);  // spare for the next builds
}

}  // namespace dsdem::contact
