#include "solver/fragments.hpp"

#include <numeric>

namespace dsdem::solver {

namespace {
Index find_root(std::vector<Index>& parent, Index i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}
void unite(std::vector<Index>& parent, Index a, Index b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a == b) return;
  if (a < b)
    parent[b] = a;
  else
    parent[a] = b;
}
}  // namespace

int count_fragments(const Model& model, std::vector<Index>& label) {
  const std::size_t nt = model.triangles.size();
  std::vector<Index> parent(nt);
  std::iota(parent.begin(), parent.end(), 0);
  // Triangles sharing a node are one piece.
  std::vector<Index> first_triangle(model.nodes.size(), kNoIndex);
  for (std::size_t t = 0; t < nt; ++t)
    for (Index n : model.triangles.conn[t]) {
      if (first_triangle[n] == kNoIndex)
        first_triangle[n] = static_cast<Index>(t);
      else
        unite(parent, first_triangle[n], static_cast<Index>(t));
    }
  const Joints& J = model.joints;
  for (std::size_t j = 0; j < J.size(); ++j)
    if (!J.broken[j]) unite(parent, J.tri_a[j], J.tri_b[j]);
  label.assign(nt, kNoIndex);
  std::vector<Index> root_label(nt, kNoIndex);
  int count = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    const Index r = find_root(parent, static_cast<Index>(t));
    if (root_label[r] == kNoIndex) root_label[r] = count++;
    label[t] = root_label[r];
  }
  return count;
}

}  // namespace dsdem::solver
