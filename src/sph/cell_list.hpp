#pragma once
// O(N) neighbour search for SPH (docs/theory.md §11): a uniform grid of cells as wide as the
// kernel's support, filled by a stable counting sort. The candidates of a point are the
// particles of the 3 x 3 cells around its own; cells are numbered row by row, so the three
// cells of one row are one contiguous range of the sorted order.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace dsdem::sph {

// The grid: origin, cell size and counts. cell_of clamps to the grid. A window of a larger
// grid (window_of) keeps that grid's origin and numbers its columns and rows from (ox, oy):
// every point inside it falls in the same cell as in the larger grid, bit for bit.
struct Grid {
  double x0 = 0.0, y0 = 0.0, inv_cell = 1.0;
  int nx = 1, ny = 1;
  int ox = 0, oy = 0;

  int column(double x) const;
  int row(double y) const;
  int cell_of(double x, double y) const { return row(y) * nx + column(x); }
  std::size_t cells() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
};

// A grid with cells of size `cell` over the box [xmin, xmax] x [ymin, ymax] (a small
// margin added), so that every point of the box has its own cell.
Grid grid_over(double xmin, double ymin, double xmax, double ymax, double cell);
// The window of `whole`'s cells that holds the box [xmin, xmax] x [ymin, ymax].
Grid window_of(const Grid& whole, double xmin, double ymin, double xmax, double ymax);

class CellList {
 public:
  // Bins the points (x[i], y[i]) into `grid`'s cells, in index order within a cell (the
  // same order for any thread count). Allocates only when the grid or the point count
  // grew past what it held before.
  // `reach`: cells searched on each side of a point's own, so that cells of size support /
  // reach hold every neighbour within the support in the (2 reach + 1)^2 block; smaller
  // cells, fewer candidates (reach 2: 25 cells of (s/2)^2 against 9 of s^2, 0.69 times).
  void build(const Grid& grid, std::span<const double> x, std::span<const double> y, int reach = 1);
  // The same for the points listed in `members` (ascending) only; cell(i) of any other
  // point is -1.
  void build(const Grid& grid, std::span<const double> x, std::span<const double> y,
             std::span<const std::int32_t> members, int reach);

  const Grid& grid() const { return grid_; }
  // The point indices sorted by cell.
  std::span<const std::int32_t> order() const { return order_; }
  // Point i's cell.
  std::int32_t cell(std::size_t i) const { return cell_[i]; }

  // The candidates of a point in cell c (of this grid): f(k0, k1) for up to 2 reach + 1
  // ranges [k0, k1) of order(), one per row of the block, bottom row first.
  template <class F>
  void for_each_range(int c, F&& f) const {
    for_each_range(c, reach_, f);
  }
  // The same with `reach` cells on each side instead of build()'s (a wider search).
  template <class F>
  void for_each_range(int c, int reach, F&& f) const {
    const int cx = c % grid_.nx, cy = c / grid_.nx;
    const int x_lo = cx > reach ? cx - reach : 0, x_hi = cx + reach < grid_.nx ? cx + reach : grid_.nx - 1;
    const int y_lo = cy > reach ? cy - reach : 0, y_hi = cy + reach < grid_.ny ? cy + reach : grid_.ny - 1;
    for (int row = y_lo; row <= y_hi; ++row) {
      const std::int32_t k0 = start_[static_cast<std::size_t>(row * grid_.nx + x_lo)];
      const std::int32_t k1 = start_[static_cast<std::size_t>(row * grid_.nx + x_hi + 1)];
      if (k1 > k0) f(k0, k1);
    }
  }

 private:
  // The exclusive prefix sums of the counts in start_ and the points with a cell (>= 0) in
  // index order.
  void fill_order(std::size_t n);

  Grid grid_;
  int reach_ = 1;
  std::vector<std::int32_t> start_;  // cells + 1: the first sorted index of each cell
  std::vector<std::int32_t> order_;
  std::vector<std::int32_t> cell_;
};

}  // namespace dsdem::sph
