#include "sph/cell_list.hpp"

#include <algorithm>
#include <cmath>

namespace dsdem::sph {

int Grid::column(double x) const {
  const int c = static_cast<int>(std::floor((x - x0) * inv_cell)) - ox;
  return std::clamp(c, 0, nx - 1);
}
int Grid::row(double y) const {
  const int c = static_cast<int>(std::floor((y - y0) * inv_cell)) - oy;
  return std::clamp(c, 0, ny - 1);
}

Grid grid_over(double xmin, double ymin, double xmax, double ymax, double cell) {
  // Half a cell of margin on each side, so that rounding never clamps a point.
  Grid g;
  g.x0 = xmin - 0.5 * cell;
  g.y0 = ymin - 0.5 * cell;
  g.inv_cell = 1.0 / cell;
  g.nx = std::max(1, static_cast<int>(std::ceil((xmax - xmin) / cell)) + 1);
  g.ny = std::max(1, static_cast<int>(std::ceil((ymax - ymin) / cell)) + 1);
  return g;
}

Grid window_of(const Grid& whole, double xmin, double ymin, double xmax, double ymax) {
  Grid g = whole;
  const int c0 = whole.column(xmin), c1 = whole.column(xmax), r0 = whole.row(ymin), r1 = whole.row(ymax);
  g.ox = whole.ox + c0;
  g.oy = whole.oy + r0;
  g.nx = c1 - c0 + 1;
  g.ny = r1 - r0 + 1;
  return g;
}

void CellList::build(const Grid& grid, std::span<const double> x, std::span<const double> y, int reach) {
  grid_ = grid;
  reach_ = reach;
  const std::size_t n = x.size(), cells = grid.cells();
  start_.assign(cells + 1, 0);
  order_.resize(n);
  cell_.resize(n);
  // Counting sort: counts per cell, exclusive prefix sums, then the points in index order.
  for (std::size_t i = 0; i < n; ++i) {
    const int c = grid.cell_of(x[i], y[i]);
    cell_[i] = c;
    ++start_[static_cast<std::size_t>(c) + 1];
  }
  fill_order(n);
}

void CellList::build(const Grid& grid, std::span<const double> x, std::span<const double> y,
                     std::span<const std::int32_t> members, int reach) {
  grid_ = grid;
  reach_ = reach;
  start_.assign(grid.cells() + 1, 0);
  order_.reserve(x.size());  // room for every point: a growing membership never reallocates
  order_.resize(members.size());
  cell_.assign(x.size(), -1);
  for (const std::int32_t m : members) {
    const auto i = static_cast<std::size_t>(m);
    const int c = grid.cell_of(x[i], y[i]);
    cell_[i] = c;
    ++start_[static_cast<std::size_t>(c) + 1];
  }
  fill_order(x.size());
}

void CellList::fill_order(std::size_t n) {
  const std::size_t cells = grid_.cells();
  for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  // Fill from the cell starts; start_[c] is advanced, then shifted back below.
  for (std::size_t i = 0; i < n; ++i) {
    if (cell_[i] < 0) continue;
    order_[static_cast<std::size_t>(start_[static_cast<std::size_t>(cell_[i])]++)] = static_cast<std::int32_t>(i);
  }
  for (std::size_t c = cells; c > 0; --c) start_[c] = start_[c - 1];
  start_[0] = 0;
}

}  // namespace dsdem::sph
