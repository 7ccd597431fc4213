#pragma once
// Builds a 3D Model3 from a volume mesh (docs/theory.md §14): materials per physical volume,
// reference geometry of the tetrahedra, lumped masses, groups on the model's nodes.
#include <map>
#include <optional>
#include <string>

#include "io/scenario.hpp"
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

// The scenario's mesh when it is a volume mesh (docs/theory.md §14): a .msh whose volumes
// hold elements, or a .geo with volumes, meshed into tetrahedra (gmsh -3) in work_dir;
// std::nullopt for a plane mesh (read by load_mesh). Throws io::ScenarioError at mesh.file.
std::optional<RawMesh3> load_volume_mesh(const io::Scenario& scenario, const std::string& work_dir);

// The model of a volume mesh and a scenario: each region names a physical volume and its
// material. Throws io::ScenarioError (file, line and key) for a region whose group is not a
// volume of the mesh, a volume without a region, or a material whose law does not run in 3D.
Model3 build_model_3d(const io::Scenario& scenario, const RawMesh3& mesh);

// Lumped masses rho V / 4 to each node of each tetrahedron (docs/theory.md §2).
void compute_lumped_masses(Model3& model);

}  // namespace dsdem::mesh
