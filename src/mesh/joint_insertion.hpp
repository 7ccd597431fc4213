#pragma once
// Joint insertion (paper step 2, Fig. 3; docs/theory.md §3): split a mesh into discrete
// triangles glued by 4-node zero-thickness joints where it may break.
//
// Rules:
//  * a triangle is breakable when its surface group (RawMesh::triangle_surface_group)
//    is flagged breakable; triangles without a surface group are continuous;
//  * every breakable triangle gets three nodes of its own; continuous triangles share
//    one copy of each mesh node among themselves;
//  * every mesh edge shared by two triangles of which at least one is breakable gets a
//    joint: interior edges of breakable groups, edges between two breakable groups and
//    edges between a breakable and a continuous group (the slide is bonded to the
//    bedrock until that bond fails);
//  * a joint on a named mesh curve (RawPhysicalGroup dim 1, its edges) takes that
//    curve's property or starts broken. Edges of named curves between two continuous
//    triangles stay continuous and are listed in curve_edges_without_joint.
// Output order is deterministic: nodes by mesh node, then (for the copies of one mesh
// node) the continuous copy first and breakable copies by triangle index; joints by
// their mesh edge (lower node id, then higher).
#include <map>
#include <set>
#include <vector>

#include "model/joints.hpp"
#include "mesh/raw_mesh.hpp"

namespace dsdem {

struct JointInsertionOptions {
  // Per RawMesh::groups entry (only surface groups are read); empty = nothing breaks.
  std::vector<bool> breakable;
  // Property of joints inside breakable group g: group_property[g] when given and not
  // kNoIndex, else default_property. group_property is empty or sized like groups.
  Index default_property = 0;
  std::vector<Index> group_property;
  // Joints between two different surface groups: interface_property when not kNoIndex,
  // else the property of the breakable side (of the lower group index if both are).
  Index interface_property = kNoIndex;
  // Named curves (indices of dim-1 groups): their joints' property, or broken at start.
  // When an edge lies on several curves the lowest group index wins.
  std::map<Index, Index> curve_property;
  std::set<Index> broken_curves;
};

struct JointInsertionResult {
  std::vector<Vec2> nodes;                     // reference positions of the model nodes, m
  std::vector<Index> origin;                   // mesh node each model node was split from
  std::vector<std::array<Index, 3>> triangles; // same order as RawMesh::triangles, CCW
  Joints joints;                               // properties assigned, histories zero
  // Copies of each mesh node (CSR): copies[copies_offset[n] .. copies_offset[n+1]).
  // Mesh nodes used by no triangle get no copy.
  std::vector<Index> copies_offset;
  std::vector<Index> copies;
  std::vector<std::array<Index, 2>> curve_edges_without_joint;  // mesh node pairs (low, high)
};

// Throws std::runtime_error (message starts with mesh.source) on: a triangle that is
// not counter-clockwise or references a missing node, an edge shared by more than two
// triangles or by two triangles with the same orientation, option vectors of the wrong
// size, or curve overrides naming something that is not a curve group.
JointInsertionResult insert_joints(const RawMesh& mesh, const JointInsertionOptions& options);

}  // namespace dsdem
