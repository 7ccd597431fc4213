#pragma once
// Gmsh input (DESIGN.md §9): ASCII .msh 4.1 or 2.2 read by dsdem's own strict parser
// (mesh/msh_format); a .geo is first meshed by the gmsh command line with the element
// size the scenario gives.
#include <string>

#include "mesh/raw_mesh.hpp"

namespace dsdem::mesh {

// Reads a Gmsh .msh file: nodes, 3-node triangles, 2-node lines and points with their
// physical groups, in the order the Gmsh API gave them. Triangles are made
// counter-clockwise. Throws std::runtime_error naming the file (and line) for malformed
// or unreadable files, higher-order or unsupported elements, triangles outside every
// physical surface, degenerate or inverted (folded) elements.
RawMesh read_msh(const std::string& path);

// Meshes a .geo with `gmsh -2` at the given maximum element size (m) into out_msh.
// Throws with gmsh's own message on failure.
void mesh_geo(const std::string& geo_path, double element_size, const std::string& out_msh);

}  // namespace dsdem::mesh
