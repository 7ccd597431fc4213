#pragma once
// Structured triangle meshes of a rectangle, for tests, benchmarks and quick examples
// without Gmsh. Groups: "domain" (surface), "left", "right", "bottom", "top" (curves).
#include "mesh/raw_mesh.hpp"

namespace dsdem::mesh {

enum class Diagonal { Right, Alternate, Cross };

// nx x ny cells over [x0, x0+lx] x [y0, y0+ly], each cell split in 2 triangles (Right,
// Alternate) or 4 around a centre node (Cross).
RawMesh rectangle_mesh(int nx, int ny, double lx, double ly, Diagonal diagonal = Diagonal::Alternate,
                       double x0 = 0.0, double y0 = 0.0, const std::string& surface_name = "domain");

// Appends `other` to `mesh` (nodes are not merged; groups with the same name merge).
void append_mesh(RawMesh& mesh, const RawMesh& other);

}  // namespace dsdem::mesh
