#pragma once
// Builds the solver's Model from a Gmsh mesh and a validated scenario: materials per
// surface group, zones, lumped masses, reference geometry. Errors that need the mesh
// (groups it lacks, inverted elements) name the scenario's file, line and key.
#include "io/scenario.hpp"
#include "mesh/joint_insertion.hpp"
#include "mesh/raw_mesh.hpp"
#include "model/model.hpp"

namespace dsdem::mesh {

// Loads (and for a .geo, meshes into work_dir) the scenario's mesh; its triangles are
// renumbered along a Hilbert curve unless mesh.triangle_order is file (triangle_order.hpp).
RawMesh load_mesh(const io::Scenario& scenario, const std::string& work_dir);

// Throws io::ScenarioError listing every mismatch between scenario and mesh.
Model build_model(const io::Scenario& scenario, const RawMesh& mesh);

// Joint property table (one per discrete group, the interface, each named curve) and
// insertion options from the scenario's joints section.
void build_joint_properties(const io::Scenario& sc, const RawMesh& mesh,
                            const std::vector<const io::RegionSpec*>& region_of_group,
                            const std::map<std::string, Index>& material_index, Model& model,
                            dsdem::JointInsertionOptions& opt, std::vector<std::string>& errors);

// Spheropolygons of zones A and C, continuous bodies, pair parameters (docs/theory.md §4).
void setup_contact(const io::Scenario& sc, Model& model, std::vector<std::string>& errors);

// Lumped masses rho * A * t / 3 to each node (docs/theory.md §2).
void compute_lumped_masses(Model& model);

// Each material's law index from its model name, and Triangles::state: one zeroed column
// per state variable that the laws of the materials in use declare (law/registry.hpp),
// none for a purely elastic model; the same for Joints::law_state from the joint laws.
// Throws law::UnknownLaw for an unregistered model.
void setup_law_state(Model& model);

}  // namespace dsdem::mesh

namespace dsdem::mesh {
// A model of one material from a raw mesh, without a scenario (tests, benchmarks).
Model build_model(const RawMesh& mesh, const Material& material, Zone zone = Zone::Bedrock);
}  // namespace dsdem::mesh
