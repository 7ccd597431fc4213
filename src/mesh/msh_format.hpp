#pragma once
// Strict reader of Gmsh ASCII .msh files, formats 4.1 and 2.2 (docs/developer-guide.md §1), without
// libgmsh: Gmsh's own parser trusts its input and a damaged file could corrupt memory.
// parse_msh() checks every count, tag and reference and keeps the file's content;
// to_raw_mesh() orders it the way the Gmsh API returned it (nodes per entity, entities
// by (dim, tag)), so meshes and the solver's results do not change with the reader.
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mesh/raw_mesh.hpp"

namespace dsdem::mesh {

// Gmsh element type numbers dsdem uses.
constexpr int kMshLine2 = 1;
constexpr int kMshTriangle3 = 2;
constexpr int kMshQuad4 = 3;  // only with crossed: split in four triangles (to_raw_mesh)
constexpr int kMshTetrahedron4 = 4;
constexpr int kMshPoint = 15;

struct MshElementType {
  const char* name;  // as Gmsh names it, e.g. "Quadrilateral 4"
  int dim;
  int num_nodes;
};
// The type's name, dimension and node count, or nullptr when it is not a Gmsh type we know.
const MshElementType* msh_element_type(int type);

struct MshElement {
  std::int64_t tag = 0;
  int type = 0;
  std::size_t first_node = 0;  // into MshFile::element_nodes (file node indices)
  long line = 0;               // line of the file, for error messages
};

struct MshEntity {
  std::vector<int> physicals;                        // physical tags (> 0), without repeats
  std::vector<std::size_t> nodes;                    // file node indices it holds, in Gmsh's order
  std::map<int, std::vector<std::size_t>> elements;  // element type -> indices into MshFile::elements
};

struct MshFile {
  std::string path;
  int major_version = 0;  // 4 (4.1) or 2 (2.2)
  long last_line = 0;
  std::map<std::pair<int, int>, std::string> physical_names;  // (dim, tag) -> name
  std::map<std::pair<int, int>, MshEntity> entities;          // (dim, tag), Gmsh's order
  std::vector<std::int64_t> node_tags;                        // file order
  std::vector<std::array<double, 3>> node_xyz;                // m
  // The first node off the plane z = 0 (line 0: none), which a 2D mesh may not have.
  struct OffPlane {
    long line = 0;
    std::int64_t tag = 0;
    double z = 0.0;
  } first_off_plane;
  std::vector<MshElement> elements;                           // file order
  std::vector<std::size_t> element_nodes;
};

// Parses the text of an ASCII .msh 4.1 or 2.2 file. Throws std::runtime_error
// "PATH:LINE: what is wrong" for anything malformed; never allocates more than the
// text's size justifies.
MshFile parse_msh(std::string_view text, const std::string& path);

// Nodes, counter-clockwise triangles and physical groups in the order the Gmsh API gave
// them. With `crossed`, every 4-node quadrilateral becomes four triangles around a new
// node where its diagonals cross (docs/theory.md §2), in its surface's groups; the new
// nodes follow the file's, one per quadrilateral in element order. Throws
// std::runtime_error "PATH:LINE: ..." for unsupported element types (quadrilaterals
// without `crossed`), degenerate or folded elements, quadrilaterals that are not
// strictly convex and triangles outside every physical surface.
RawMesh to_raw_mesh(const MshFile& file, bool crossed = false);

// Whether the file holds a volume mesh: some volume entity holds elements. The mesh decides
// the model's dimension (docs/theory.md §14).
bool is_volume_mesh(const MshFile& file);

// Nodes, right-handed tetrahedra (positive volume) and physical groups of a volume mesh,
// in the order the Gmsh API gave them: physical volumes name materials and zones, physical
// surfaces boundaries (their triangles must be faces of the tetrahedra), physical points
// gauges. Throws std::runtime_error "PATH:LINE: ..." for elements other than 4-node
// tetrahedra in volumes, degenerate or folded tetrahedra, tetrahedra outside every
// physical volume, surface triangles that are no tetrahedron's face (loose surfaces).
RawMesh3 to_raw_mesh_3d(const MshFile& file);

}  // namespace dsdem::mesh
