#include "mesh/node_order.hpp"

#include <stdexcept>
#include <string>

namespace dsdem::mesh {

std::vector<Index> node_order_by_first_use(std::span<const std::array<Index, 3>> conn, std::size_t n_nodes) {
  std::vector<Index> new_id(n_nodes, kNoIndex);
  Index next = 0;
  for (const auto& c : conn)
    for (const Index i : c) {
      if (i < 0 || static_cast<std::size_t>(i) >= n_nodes)
        throw std::invalid_argument("node_order_by_first_use: node " + std::to_string(i) + " out of range (" +
                                    std::to_string(n_nodes) + " nodes)");
      if (new_id[static_cast<std::size_t>(i)] == kNoIndex) new_id[static_cast<std::size_t>(i)] = next++;
    }
  for (Index& id : new_id)
    if (id == kNoIndex) id = next++;
  return new_id;
}

double node_order_fingerprint(std::span<const Vec2> X) {
  double sum = 0.0;
  for (std::size_t i = 0; i < X.size(); ++i)
    sum += static_cast<double>(i % 1021 + 1) * (X[i].x() + 3.0 * X[i].y());
  return sum;
}

double node_order_fingerprint(std::span<const Vec3> X) {
  double sum = 0.0;
  for (std::size_t i = 0; i < X.size(); ++i)
    sum += static_cast<double>(i % 1021 + 1) * (X[i].x() + 3.0 * X[i].y() + 7.0 * X[i].z());
  return sum;
}

}  // namespace dsdem::mesh
