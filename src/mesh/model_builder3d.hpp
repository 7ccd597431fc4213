#pragma once
// Builds a 3D Model3 from a volume mesh (docs/theory.md §14): materials per physical volume,
// reference geometry of the tetrahedra, lumped masses, groups on the model's nodes.
#include <map>
#include <string>

#include "mesh/raw_mesh.hpp"
#include "model/model3d.hpp"

namespace dsdem::mesh {

// A model whose physical volumes take their materials by name (`materials`: volume group
// name -> material). Throws std::invalid_argument naming a volume group without a material,
// a material whose law does not run in 3D, and a tetrahedron of zero or negative volume
// (its index and position).
Model3 build_model_3d(const RawMesh3& mesh, const std::map<std::string, Material>& materials);
// Every volume of one material (tests, benchmarks).
Model3 build_model_3d(const RawMesh3& mesh, const Material& material);

// Lumped masses rho V / 4 to each node of each tetrahedron (docs/theory.md §2).
void compute_lumped_masses(Model3& model);

}  // namespace dsdem::mesh
