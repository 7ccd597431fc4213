#pragma once
// Fragments: pieces of the model connected through shared nodes (continuous mesh) or
// intact joints (docs/validation.md §2, the pieces of a broken beam). Union-find, O(N).
#include <vector>

#include "model/model.hpp"

namespace dsdem::solver {

// Number of fragments; `label` gets each triangle's fragment id (0..n-1, ordered by
// the lowest triangle index in the fragment, so labels are deterministic).
int count_fragments(const Model& model, std::vector<Index>& label);

}  // namespace dsdem::solver
