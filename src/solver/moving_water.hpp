#pragma once
// The solid's side of the moving water (docs/theory.md §11): which edges of the mesh the water
// can meet.
#include <span>
#include <vector>

#include "model/model.hpp"
#include "sph/solid_coupling.hpp"

namespace dsdem::solver {

// The exposed edges of the listed triangles, oriented for sph::SolidEdge (counter-clockwise
// along the triangle: the solid on the left): edges that no other triangle shares and that
// no joint glues (a discrete block's outline, a bedrock mesh's surface). In triangle order,
// corner k -> k + 1. Faces that joints broken later open are not included.
std::vector<sph::SolidEdge> exposed_edges(const Model& m, std::span<const Index> triangles);

}  // namespace dsdem::solver
