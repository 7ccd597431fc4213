#pragma once
// Node numbering for locality (docs/developer-guide.md §1): nodes numbered in the order the
// triangles first use them, so that the nodes of nearby triangle indices are nearby in
// memory and every contiguous share of the triangles (a thread's) works on a contiguous
// share of the nodes. Gmsh numbers a mesh's corner and curve nodes first and its surface
// nodes after, and joint insertion appends the split copies: a triangle's three nodes
// could lie thousands of entries apart, and a thread would read node data last written
// by another core.
//
// Only the numbering changes: each node's force is still summed in element, joint and
// contact-pair order (they are numbered by triangle and joint), so the motion is the same
// bit for bit; sums over all nodes (the energies) add in another order.
#include <array>
#include <span>
#include <vector>

#include "model/types.hpp"

namespace dsdem::mesh {

// new_id[old]: nodes in order of first use by conn (triangle by triangle, corner by
// corner), then the nodes no triangle uses, in their old order. A permutation of
// 0 .. n_nodes - 1. Throws std::invalid_argument for a node index out of range.
std::vector<Index> node_order_by_first_use(std::span<const std::array<Index, 3>> conn, std::size_t n_nodes);

// Applies new_id to a list of node indices in place.
inline void renumber(std::span<Index> nodes, const std::vector<Index>& new_id) {
  for (Index& i : nodes) i = new_id[static_cast<std::size_t>(i)];
}

// A number that changes when the same positions come in another order (or move): the
// reference positions weighted by position in the list. A checkpoint records it, so one
// written with another numbering (dsdem before this one numbered nodes as the mesh did)
// is refused instead of continuing with its node arrays in the wrong order.
double node_order_fingerprint(std::span<const Vec2> X);
double node_order_fingerprint(std::span<const Vec3> X);  // of a 3D model's nodes

}  // namespace dsdem::mesh
