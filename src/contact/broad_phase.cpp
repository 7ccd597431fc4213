#include "contact/broad_phase.hpp"

#include <cmath>

#include "contact/buffer.hpp"
#include <limits>

namespace dsdem::contact {

void BroadPhase::bin(const NodePositions& x, std::span<const std::array<Index, 3>> conn,
                     std::span<const std::uint8_t> active, double skin) {
  ++builds_;
  skin_ = skin;
  n_nodes_ = x.size();
  const double half = 0.5 * skin;

  // Active triangles and their enlarged boxes (also what the rebuild test checks).
  tris_.clear();
  boxes_.clear();
  reserve_with_headroom(tris_, conn.size());
  reserve_with_headroom(boxes_, conn.size());
  Vec2 dlo = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 dhi = -dlo;
  double extent_sum = 0.0;
  for (std::size_t t = 0; t < conn.size(); ++t) {
    if (!active[t]) continue;
    const auto& c = conn[t];
    const Vec2 p0 = x[c[0]], p1 = x[c[1]], p2 = x[c[2]];
    Aabb b;
    b.lo = p0.cwiseMin(p1).cwiseMin(p2).array() - half;
    b.hi = p0.cwiseMax(p1).cwiseMax(p2).array() + half;
    tris_.push_back(static_cast<Index>(t));
    boxes_.push_back(b);
    dlo = dlo.cwiseMin(b.lo);
    dhi = dhi.cwiseMax(b.hi);
    extent_sum += (b.hi - b.lo).maxCoeff();
  }

  const std::size_t ns = tris_.size();
  if (ns == 0) {
    nx_ = ny_ = 1;
    origin_.setZero();
    cell_size_ = inv_h_ = 1.0;
    reserve_with_headroom(cell_start_, 2);
    cell_start_.assign(2, 0);
    cell_items_.clear();
    return;
  }

  // Cell about the mean box size, but never more than ~6N cells (sparse or elongated
  // sets), so memory and the sweep stay O(N).
  const double W = dhi.x() - dlo.x();
  const double H = dhi.y() - dlo.y();
  const double n = static_cast<double>(ns);
  double h = extent_sum / n;
  h = std::max(h, std::sqrt(W * H / (2.0 * n)));
  h = std::max(h, std::max(W, H) / (2.0 * n));
  if (!(h > 0.0)) h = 1.0;
  cell_size_ = h;
  inv_h_ = 1.0 / h;
  origin_ = dlo;
  nx_ = static_cast<int>(W * inv_h_) + 1;
  ny_ = static_cast<int>(H * inv_h_) + 1;
  const std::size_t ncells = static_cast<std::size_t>(nx_) * ny_;

  // Counting sort of the slots into every cell their box covers.
  reserve_with_headroom(cell_start_, ncells + 1);
  reserve_with_headroom(fill_, ncells);
  cell_start_.assign(ncells + 1, 0);
  for (std::size_t s = 0; s < ns; ++s) {
    const Aabb& b = boxes_[s];
    const int cx0 = cell_x(b.lo.x()), cx1 = cell_x(b.hi.x());
    const int cy0 = cell_y(b.lo.y()), cy1 = cell_y(b.hi.y());
    for (int cy = cy0; cy <= cy1; ++cy)
      for (int cx = cx0; cx <= cx1; ++cx) ++cell_start_[static_cast<std::size_t>(cy) * nx_ + cx + 1];
  }
  for (std::size_t c = 0; c < ncells; ++c) cell_start_[c + 1] += cell_start_[c];
  fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
  reserve_with_headroom(cell_items_, static_cast<std::size_t>(cell_start_[ncells]));
  cell_items_.resize(static_cast<std::size_t>(cell_start_[ncells]));
  for (std::size_t s = 0; s < ns; ++s) {
    const Aabb& b = boxes_[s];
    const int cx0 = cell_x(b.lo.x()), cx1 = cell_x(b.hi.x());
    const int cy0 = cell_y(b.lo.y()), cy1 = cell_y(b.hi.y());
    for (int cy = cy0; cy <= cy1; ++cy)
      for (int cx = cx0; cx <= cx1; ++cx)
        cell_items_[fill_[static_cast<std::size_t>(cy) * nx_ + cx]++] = static_cast<Index>(s);
  }
}

std::size_t BroadPhase::pair_bound() const {
  // Every pair is reported in one cell that holds both its slots.
  const std::size_t ncells = static_cast<std::size_t>(nx_) * ny_;
  std::size_t bound = 0;
  for (std::size_t c = 0; c < ncells && c + 1 < cell_start_.size(); ++c) {
    const auto k = static_cast<std::size_t>(cell_start_[c + 1] - cell_start_[c]);
    if (k > 1) bound += k * (k - 1) / 2;
  }
  return bound;
}

void BroadPhase::reserve_first_pairs() {
  // Only the touched pages of a large block become resident, so the overestimate costs
  // address space, not memory; capped for degenerate grids.
  const std::size_t room = std::min(pair_bound(), kFirstPairsPerTriangleCap * tris_.size());
  if (pairs_.capacity() < room) pairs_.reserve(room);
}

}  // namespace dsdem::contact
