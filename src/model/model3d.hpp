#pragma once
// The 3D model as structures of arrays (docs/developer-guide.md §1): the same nodes as a
// plane model (NodeArrays<3>), linear tetrahedra for the continuum (docs/theory.md §14) and
// the physical groups of the volume mesh. Built by mesh/model_builder3d from a Gmsh
// volume mesh; advanced by solver/continuum3d.
#include <array>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "model/types.hpp"

namespace dsdem {

struct Tetrahedra {
  std::vector<std::array<Index, 4>> conn;  // right-handed: (X1-X0, X2-X0, X3-X0) has positive volume
  std::vector<Index> group;                // index into Model3::groups (a volume group)
  std::vector<Index> material;             // index into Model3::materials
  std::vector<Mat3> Dm_inv;    // inverse of the reference edge matrix [X1-X0, X2-X0, X3-X0]
  std::vector<double> volume0; // reference volume, m^3
  // Output of the current state (Solver3::update_stress fills them): Cauchy stress, Pa, and
  // Green strain with engineering shears, Voigt (xx, yy, zz, yz, xz, xy).
  std::vector<Vec6> stress;
  std::vector<Vec6> strain;
  // Initial (in-situ) stress kept from an earlier stage, Pa; empty = zero everywhere.
  std::vector<Vec6> stress0;

  std::size_t size() const { return conn.size(); }
  Vec6 initial_stress(std::size_t t) const { return stress0.empty() ? Vec6(Vec6::Zero()) : stress0[t]; }
};

// A physical group of the volume mesh on the model: its tetrahedra (volumes), its boundary
// triangles as model node triples (surfaces), its nodes (surfaces, curves, points).
struct Group3 {
  std::string name;
  int dim = 3;
  int gmsh_tag = -1;
  std::vector<Index> tetrahedra;
  std::vector<std::array<Index, 3>> faces;
  std::vector<Index> nodes;
};

struct Model3 {
  NodeArrays<3> nodes;
  Tetrahedra tetrahedra;
  std::vector<Group3> groups;
  std::vector<Material> materials;  // 3D Lame constants (never plane stress)

  Index find_group(const std::string& name) const {
    for (std::size_t i = 0; i < groups.size(); ++i)
      if (groups[i].name == name) return static_cast<Index>(i);
    return kNoIndex;
  }
};

}  // namespace dsdem
