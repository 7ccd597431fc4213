// Volume meshes (to_raw_mesh_3d): tetrahedra made right-handed, physical volumes, surfaces
// and points, and every malformed volume mesh refused with file and line.
#include <gtest/gtest.h>

#include <string>

#include "mesh/msh_format.hpp"
#include "mesh/structured.hpp"

using namespace dsdem;

namespace {

// Two tetrahedra sharing the face (2, 3, 4), a base triangle on the first and a gauge point.
const std::string kVolume = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
0 3 "gauge"
2 2 "base"
3 1 "rock"
$EndPhysicalNames
$Nodes
5
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 1 1 1
$EndNodes
$Elements
4
1 15 2 3 1 4
2 2 2 2 1 1 2 3
3 4 2 1 1 1 2 3 4
4 4 2 1 1 2 3 4 5
$EndElements
)";

std::string with(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

RawMesh3 read(const std::string& text) { return mesh::to_raw_mesh_3d(mesh::parse_msh(text, "v.msh")); }

std::string error_of(const std::string& text) {
  try {
    read(text);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

double volume(const RawMesh3& m, std::size_t t) {
  const auto& c = m.tetrahedra[t];
  return (m.nodes[c[1]] - m.nodes[c[0]]).dot((m.nodes[c[2]] - m.nodes[c[0]]).cross(m.nodes[c[3]] - m.nodes[c[0]])) / 6.0;
}

}  // namespace

TEST(MshVolume, ReadsTetrahedraAndTheirGroups) {
  const auto file = mesh::parse_msh(kVolume, "v.msh");
  EXPECT_TRUE(mesh::is_volume_mesh(file));
  const RawMesh3 m = mesh::to_raw_mesh_3d(file);
  ASSERT_EQ(m.nodes.size(), 5u);
  ASSERT_EQ(m.tetrahedra.size(), 2u);
  EXPECT_NEAR(volume(m, 0), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(volume(m, 1), 2.0 / 6.0, 1e-15);
  const RawPhysicalGroup3* rock = m.find("rock");
  ASSERT_NE(rock, nullptr);
  EXPECT_EQ(rock->dim, 3);
  EXPECT_EQ(rock->tetrahedra.size(), 2u);
  EXPECT_EQ(m.tetrahedron_volume_group[0], m.tetrahedron_volume_group[1]);
  const RawPhysicalGroup3* base = m.find("base");
  ASSERT_NE(base, nullptr);
  EXPECT_EQ(base->dim, 2);
  ASSERT_EQ(base->faces.size(), 1u);
  EXPECT_EQ(base->nodes.size(), 3u);
  const RawPhysicalGroup3* gauge = m.find("gauge");
  ASSERT_NE(gauge, nullptr);
  ASSERT_EQ(gauge->nodes.size(), 1u);
  EXPECT_EQ(m.nodes[gauge->nodes[0]], Vec3(0, 0, 1));
}

TEST(MshVolume, LeftHandedTetrahedraAreMadeRightHanded) {
  const RawMesh3 m = read(with(with(kVolume, "3 4 2 1 1 1 2 3 4", "3 4 2 1 1 1 3 2 4"), "4 4 2 1 1 2 3 4 5",
                               "4 4 2 1 1 3 2 4 5"));
  EXPECT_NEAR(volume(m, 0), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(volume(m, 1), 2.0 / 6.0, 1e-15);
}

TEST(MshVolume, MalformedVolumeMeshesAreRefusedWithTheirLine) {
  auto expect_error = [](const std::string& text, const std::string& where, const std::string& what) {
    const std::string msg = error_of(text);
    EXPECT_EQ(msg.rfind(where, 0), 0u) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  };
  // One of two tetrahedra of a volume given left-handed: the volume is folded.
  expect_error(with(kVolume, "4 4 2 1 1 2 3 4 5", "4 4 2 1 1 3 2 4 5"), "v.msh:23:",
               "volume 1 has inverted elements: 1 of its 2 tetrahedra are left-handed");
  // Four nodes in one plane.
  expect_error(with(kVolume, "4 4 2 1 1 2 3 4 5", "4 4 2 1 1 1 2 3 2"), "v.msh:23:", "is degenerate (zero volume)");
  // A surface triangle that is no tetrahedron's face: a loose surface beside the volume.
  expect_error(with(kVolume, "2 2 2 2 1 1 2 3", "2 2 2 2 1 1 2 5"), "v.msh:21:", "is no tetrahedron's face");
  // Quadratic tetrahedra.
  expect_error(with(kVolume, "4 4 2 1 1 2 3 4 5", "4 11 2 1 1 2 3 4 5 1 1 1 1 1 1"), "v.msh:23:",
               "holds 'Tetrahedron 10' elements");
  // A tetrahedron in an elementary volume without a physical volume.
  expect_error(with(kVolume, "4 4 2 1 1 2 3 4 5", "4 4 2 0 2 2 3 4 5"), "v.msh:23:",
               "belongs to no physical volume group");
}

TEST(MshVolume, PlaneMeshesAreNotVolumeMeshes) {
  const std::string plane = with(with(kVolume, "3 4 2 1 1 1 2 3 4\n4 4 2 1 1 2 3 4 5\n", ""), "$Elements\n4\n",
                                 "$Elements\n2\n");
  EXPECT_FALSE(mesh::is_volume_mesh(mesh::parse_msh(plane, "v.msh")));
}

TEST(BoxMesh, KuhnSplitFillsTheBoxWithRightHandedTetrahedra) {
  const RawMesh3 m = mesh::box_mesh(3, 2, 4, 3.0, 1.0, 2.0, Vec3(1.0, -1.0, 0.5));
  ASSERT_EQ(m.tetrahedra.size(), 6u * 3 * 2 * 4);
  double total = 0.0;
  for (std::size_t t = 0; t < m.tetrahedra.size(); ++t) {
    EXPECT_GT(volume(m, t), 0.0);
    total += volume(m, t);
  }
  EXPECT_NEAR(total, 6.0, 1e-12);
  // Each boundary face is a face of exactly one tetrahedron: the faces' triangles are the
  // tetrahedra's (a conforming split), 2 per cell face.
  const RawPhysicalGroup3* zmax = m.find("zmax");
  ASSERT_NE(zmax, nullptr);
  EXPECT_EQ(zmax->faces.size(), 2u * 3 * 2);
  EXPECT_EQ(zmax->nodes.size(), 4u * 3);
  for (const auto& f : zmax->faces) {
    int owners = 0;
    for (const auto& t : m.tetrahedra) {
      int shared = 0;
      for (Index v : f) shared += (v == t[0] || v == t[1] || v == t[2] || v == t[3]) ? 1 : 0;
      owners += shared == 3 ? 1 : 0;
    }
    EXPECT_EQ(owners, 1);
  }
}
