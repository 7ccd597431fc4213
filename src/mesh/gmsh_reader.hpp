#pragma once
// Gmsh input (docs/developer-guide.md §1): ASCII .msh 4.1 or 2.2 read by dsdem's own strict parser
// (mesh/msh_format); a .geo is first meshed by the gmsh command line with the element
// size the scenario gives.
#include <string>
#include <variant>

#include "mesh/raw_mesh.hpp"

namespace dsdem::mesh {

// Reads a Gmsh .msh file: nodes, 3-node triangles, 2-node lines and points with their
// physical groups, in the order the Gmsh API gave them. Triangles are made
// counter-clockwise. With `crossed`, every 4-node quadrilateral becomes four triangles
// around the crossing of its diagonals (to_raw_mesh). Throws std::runtime_error naming
// the file (and line) for malformed or unreadable files, higher-order or unsupported
// elements (quadrilaterals without `crossed`), triangles outside every physical surface,
// degenerate or inverted (folded) elements.
RawMesh read_msh(const std::string& path, bool crossed = false);

// Reads a Gmsh .msh file of either dimension: a volume mesh (some volume holds elements,
// docs/theory.md §14) as RawMesh3, else as read_msh. Throws as read_msh and to_raw_mesh_3d.
std::variant<RawMesh, RawMesh3> read_msh_any(const std::string& path, bool crossed = false);

// Meshes a .geo with `gmsh -2` at the given maximum element size (m) into out_msh.
// With `crossed`, an all-quadrilateral mesh for read_msh(..., true): Gmsh meshes
// triangles at twice every size (Mesh.MeshSizeFactor 2, so .geo-local sizes scale too)
// and splits each into three quadrilaterals (Mesh.SubdivisionAlgorithm 1), whose edges
// along the curves are then about element_size. Throws with gmsh's own message on failure.
// With dimension 3, `gmsh -3`: the geometry's volumes meshed into tetrahedra (1: the curves
// only, enough to list the geometry's entities).
void mesh_geo(const std::string& geo_path, double element_size, const std::string& out_msh, bool crossed = false,
              int dimension = 2);

}  // namespace dsdem::mesh
