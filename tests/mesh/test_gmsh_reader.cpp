// Gmsh input: .geo meshed by the gmsh CLI, .msh read by the strict parser (mesh/msh_format).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "mesh/gmsh_reader.hpp"
#include "mesh/mesh_test_util.hpp"

using namespace dsdem;
namespace fs = std::filesystem;

namespace {
std::string data(const std::string& name) { return test::mesh_data(name); }
fs::path temp_dir() { return test::mesh_temp_dir(); }
using test::error_of;
}  // namespace

TEST(GmshReader, MeshesGeoAndReadsGroups) {
  const std::string msh = (temp_dir() / "square.msh").string();
  mesh::mesh_geo(data("square.geo"), 0.2, msh);
  const RawMesh m = mesh::read_msh(msh);
  ASSERT_GT(m.triangles.size(), 20u);
  double area = 0;
  for (const auto& t : m.triangles) {
    const Vec2 a = m.nodes[t[1]] - m.nodes[t[0]], b = m.nodes[t[2]] - m.nodes[t[0]];
    const double a2 = a.x() * b.y() - a.y() * b.x();
    EXPECT_GT(a2, 0.0);  // counter-clockwise
    area += 0.5 * a2;
  }
  EXPECT_NEAR(area, 1.0, 1e-12);
  const auto* block = m.find("block");
  ASSERT_NE(block, nullptr);
  EXPECT_EQ(block->dim, 2);
  EXPECT_EQ(block->triangles.size(), m.triangles.size());
  const auto* sides = m.find("sides");
  ASSERT_NE(sides, nullptr);
  EXPECT_EQ(sides->dim, 1);
  double length = 0;
  for (const auto& e : sides->edges) length += (m.nodes[e[1]] - m.nodes[e[0]]).norm();
  EXPECT_NEAR(length, 2.0, 1e-12);
  for (Index n : sides->nodes) EXPECT_TRUE(std::abs(m.nodes[n].x()) < 1e-12 || std::abs(m.nodes[n].x() - 1) < 1e-12);
  const auto* centre = m.find("centre");
  ASSERT_NE(centre, nullptr);
  ASSERT_EQ(centre->nodes.size(), 1u);
  EXPECT_NEAR((m.nodes[centre->nodes[0]] - Vec2(0.5, 0.5)).norm(), 0.0, 1e-12);
}

TEST(GmshReader, MissingFileNamesThePath) {
  const std::string msg = error_of([] { mesh::read_msh("/nonexistent/x.msh"); });
  EXPECT_NE(msg.find("/nonexistent/x.msh"), std::string::npos) << msg;
}

TEST(GmshReader, GeoSyntaxErrorIsReportedWithGmshMessage) {
  const std::string msg = error_of([] { mesh::mesh_geo(data("broken.geo"), 0.1, (temp_dir() / "b.msh").string()); });
  EXPECT_NE(msg.find("broken.geo"), std::string::npos) << msg;
}

TEST(GmshReader, QuadrilateralsAreRefusedWithAHint) {
  const std::string msh = (temp_dir() / "quad.msh").string();
  mesh::mesh_geo(data("quad.geo"), 0.5, msh);
  const std::string msg = error_of([&] { mesh::read_msh(msh); });
  EXPECT_NE(msg.find("3-node triangles"), std::string::npos) << msg;
}

TEST(GmshReader, TriangleOutsideEveryPhysicalSurfaceIsAnError) {
  const std::string msh = (temp_dir() / "orphan.msh").string();
  mesh::mesh_geo(data("orphan.geo"), 0.5, msh);
  const std::string msg = error_of([&] { mesh::read_msh(msh); });
  EXPECT_NE(msg.find("no physical surface group"), std::string::npos) << msg;
}

TEST(GmshReader, FoldedSurfaceWithInvertedElementsIsAnError) {
  // Hand-written msh 4.1: two triangles of one surface with opposite orientation.
  const fs::path p = temp_dir() / "folded.msh";
  std::ofstream(p) << R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
1
2 1 "block"
$EndPhysicalNames
$Entities
0 0 1 0
1 0 0 0 2 1 0 1 1 0
$EndEntities
$Nodes
1 4 1 4
2 1 0 4
1
2
3
4
0 0 0
1 0 0
1 1 0
0 1 0
$EndNodes
$Elements
1 2 1 2
2 1 2 2
1 1 2 3
2 1 4 3
$EndElements
)";
  const std::string msg = error_of([&] { mesh::read_msh(p.string()); });
  EXPECT_NE(msg.find("inverted"), std::string::npos) << msg;
}

// A .geo of two boxes meshed into tetrahedra by `gmsh -3`: a volume mesh, read as such.
TEST(GmshReader, MeshesVolumesAndReadsThemAsA3DMesh) {
  const std::string msh = (temp_dir() / "cube.msh").string();
  mesh::mesh_geo(data("cube.geo"), 0.25, msh, false, 3);
  const auto any = mesh::read_msh_any(msh);
  ASSERT_TRUE(std::holds_alternative<RawMesh3>(any));
  const RawMesh3& m = std::get<RawMesh3>(any);
  ASSERT_GT(m.tetrahedra.size(), 100u);
  double volume = 0.0;
  for (const auto& t : m.tetrahedra) {
    const double v6 = (m.nodes[t[1]] - m.nodes[t[0]]).dot((m.nodes[t[2]] - m.nodes[t[0]]).cross(m.nodes[t[3]] - m.nodes[t[0]]));
    EXPECT_GT(v6, 0.0);
    volume += v6 / 6.0;
  }
  EXPECT_NEAR(volume, 2.0, 1e-12);
  const auto* rock = m.find("rock");
  const auto* soil = m.find("soil");
  ASSERT_NE(rock, nullptr);
  ASSERT_NE(soil, nullptr);
  EXPECT_EQ(rock->tetrahedra.size() + soil->tetrahedra.size(), m.tetrahedra.size());
  const auto* base = m.find("base");
  ASSERT_NE(base, nullptr);
  double area = 0.0;
  for (const auto& f : base->faces) area += 0.5 * (m.nodes[f[1]] - m.nodes[f[0]]).cross(m.nodes[f[2]] - m.nodes[f[0]]).norm();
  EXPECT_NEAR(area, 2.0, 1e-12);
  for (const Index n : base->nodes) EXPECT_NEAR(m.nodes[n].z(), 0.0, 1e-12);
  const auto* gauge = m.find("gauge");
  ASSERT_NE(gauge, nullptr);
  ASSERT_EQ(gauge->nodes.size(), 1u);
  EXPECT_LT((m.nodes[gauge->nodes[0]] - Vec3(1.0, 0.5, 1.0)).norm(), 1e-12);
  // The plane reader names what it was given.
  const std::string msg = error_of([&] { mesh::read_msh(msh); });
  EXPECT_NE(msg.find("the mesh holds volumes (tetrahedra): a 3D model"), std::string::npos) << msg;
}
