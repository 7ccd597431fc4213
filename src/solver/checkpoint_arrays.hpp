#pragma once
// Fixed-size vectors to and from a checkpoint's flat arrays of doubles, with the size check
// that says a file belongs to another model. Shared by the plane and the 3D solver.
#include <fmt/format.h>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/checkpoint.hpp"

namespace dsdem::solver {

inline void check_size(const std::string& name, std::size_t got, std::size_t want) {
  if (got != want)
    throw std::runtime_error(fmt::format("checkpoint '{}' has {} values, the model needs {}: it belongs to another model",
                                         name, got, want));
}

// Eigen fixed vectors (Vec2, Vec3, Vec6) flattened component by component.
template <class V>
std::vector<double> flatten_vectors(const std::vector<V>& v) {
  constexpr int n = V::RowsAtCompileTime;
  std::vector<double> out(v.size() * n);
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < n; ++k) out[i * n + static_cast<std::size_t>(k)] = v[i][k];
  return out;
}

// Reads `name` into v, whose size the model fixes.
template <class V>
void read_vectors(const io::CheckpointReader& in, const std::string& name, std::vector<V>& v) {
  constexpr int n = V::RowsAtCompileTime;
  const auto d = in.doubles(name);
  check_size(name, d.size(), n * v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < n; ++k) v[i][k] = d[i * n + static_cast<std::size_t>(k)];
}

}  // namespace dsdem::solver
