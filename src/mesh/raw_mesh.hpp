#pragma once
// A mesh as read from Gmsh, before joints are inserted: nodes, linear triangles and
// the physical groups they belong to. Pure data; no solver state.
#include <string>
#include <vector>

#include "model/types.hpp"

namespace dsdem {

struct RawPhysicalGroup {
  std::string name;
  int dim = 2;  // 2 surface, 1 curve, 0 point
  int tag = -1;
  std::vector<Index> triangles;               // dim 2: indices into RawMesh::triangles
  std::vector<std::array<Index, 2>> edges;    // dim 1: mesh node pairs of its line elements
  std::vector<Index> nodes;                   // dim 1 and 0: mesh nodes on it
};

struct RawMesh {
  std::string source;                          // file it came from (for error messages)
  std::string msh_file;                        // the .msh read (meshed from source when that is a .geo)
  std::vector<Vec2> nodes;                     // m
  std::vector<std::array<Index, 3>> triangles; // counter-clockwise after read
  std::vector<Index> triangle_surface_group;   // index into groups of its (first) surface group, or kNoIndex
  std::vector<RawPhysicalGroup> groups;

  const RawPhysicalGroup* find(const std::string& name) const {
    for (const auto& g : groups)
      if (g.name == name) return &g;
    return nullptr;
  }
};

// A volume mesh as read from Gmsh (mesh/msh_format.hpp, to_raw_mesh_3d): nodes, linear
// tetrahedra and the physical groups they belong to.
struct RawPhysicalGroup3 {
  std::string name;
  int dim = 3;  // 3 volume, 2 surface, 1 curve, 0 point
  int tag = -1;
  std::vector<Index> tetrahedra;             // dim 3: indices into RawMesh3::tetrahedra
  std::vector<std::array<Index, 3>> faces;   // dim 2: mesh nodes of its triangles
  std::vector<Index> nodes;                  // dim 2, 1 and 0: mesh nodes on it, sorted
};

struct RawMesh3 {
  std::string source;
  std::string msh_file;
  std::vector<Vec3> nodes;                      // m
  std::vector<std::array<Index, 4>> tetrahedra; // right-handed (positive volume) after read
  std::vector<Index> tetrahedron_volume_group;  // index into groups of its (first) volume group
  std::vector<RawPhysicalGroup3> groups;

  const RawPhysicalGroup3* find(const std::string& name) const {
    for (const auto& g : groups)
      if (g.name == name) return &g;
    return nullptr;
  }
};

}  // namespace dsdem
