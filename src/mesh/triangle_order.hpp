#pragma once
// Triangle numbering for locality (docs/developer-guide.md §1): triangles numbered along a
// Hilbert curve through their centroids, so that triangles near in space are near in
// number. Gmsh numbers a surface's triangles in the order its mesher made them, not by
// place: a thread's contact pairs would then often reach a triangle in another thread's
// run and read data the other core had just written. Nodes then follow the triangles
// (node_order.hpp).
//
// Unlike the node numbering, this one changes the order of the sums (element, joint and
// contact forces are added in triangle order), so a run differs from one on the file's
// numbering by rounding, which a breaking slope amplifies (docs/dr2.md §4). The scenario
// key mesh.triangle_order: file keeps the mesh file's order.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "mesh/raw_mesh.hpp"
#include "model/types.hpp"

namespace dsdem::mesh {

// Distance along the Hilbert curve of cell (x, y) on a 2^order x 2^order grid
// (x, y < 2^order, 1 <= order <= 31). Neighbouring distances are neighbouring cells.
std::uint64_t hilbert_index(std::uint32_t x, std::uint32_t y, int order);

// order[k] = the old index of the triangle placed at k: triangles sorted by the Hilbert
// distance of their centroid's cell on a 2^16 grid over the nodes' bounding square, ties
// (one cell) in their old order. A permutation of 0 .. triangles.size() - 1; the identity
// for fewer than two triangles or a mesh of zero extent.
std::vector<Index> spatial_triangle_order(std::span<const Vec2> nodes, std::span<const std::array<Index, 3>> triangles);

// Renumbers the mesh's triangles: triangle k becomes old triangle order[k], with its
// surface group; each group's triangle list is mapped to the new numbers and sorted.
// Throws std::invalid_argument if order is not a permutation of the triangles.
void apply_triangle_order(RawMesh& mesh, std::span<const Index> order);

}  // namespace dsdem::mesh
