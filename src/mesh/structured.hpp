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

namespace dsdem::mesh {

// A structured tetrahedral mesh of a box, for tests, benchmarks and quick examples without
// Gmsh: nx x ny x nz cells over [x0, x0+lx] x [y0, y0+ly] x [z0, z0+lz], each cell split
// into six tetrahedra around its diagonal from the lowest to the highest corner (Kuhn's
// split: neighbouring cells share their faces' diagonals, so the mesh is conforming).
// Groups: "domain" (volume), "xmin", "xmax", "ymin", "ymax", "zmin", "zmax" (surfaces).
RawMesh3 box_mesh(int nx, int ny, int nz, double lx, double ly, double lz, const Vec3& origin = Vec3::Zero());

}  // namespace dsdem::mesh
