// mesh.crossed: quadrilaterals split in four triangles around the crossing of their
// diagonals (docs/theory.md §2), from a .msh given directly or a .geo meshed by Gmsh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "app/cli_util.hpp"
#include "mesh/gmsh_reader.hpp"
#include "mesh/mesh_test_util.hpp"
#include "mesh/msh_format.hpp"

using namespace dsdem;
namespace fs = std::filesystem;

namespace {

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
double area2(const RawMesh& m, const std::array<Index, 3>& t) {
  return cross(m.nodes[t[1]] - m.nodes[t[0]], m.nodes[t[2]] - m.nodes[t[0]]);
}

// Where the diagonals a-c and b-d cross.
Vec2 crossing(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  return a + cross(b - a, d - b) / cross(c - a, d - b) * (c - a);
}

// One quadrilateral (nodes `quad`, file tags 1-4) in surface "block", its first edge in curve "base".
std::string one_quad_msh(const std::array<Vec2, 4>& p, const std::array<int, 4>& quad) {
  std::ostringstream s;
  s.precision(17);
  s << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 2 \"base\"\n2 1 \"block\"\n$EndPhysicalNames\n"
    << "$Entities\n0 1 1 0\n1 0 0 0 4 0 0 1 2 0\n1 0 0 0 4 2 0 1 1 0\n$EndEntities\n"
    << "$Nodes\n2 4 1 4\n1 1 0 2\n1\n2\n"
    << p[0].x() << " " << p[0].y() << " 0\n" << p[1].x() << " " << p[1].y() << " 0\n"
    << "2 1 0 2\n3\n4\n"
    << p[2].x() << " " << p[2].y() << " 0\n" << p[3].x() << " " << p[3].y() << " 0\n$EndNodes\n"
    << "$Elements\n2 2 1 2\n1 1 1 1\n1 1 2\n2 1 3 1\n2 " << quad[0] << " " << quad[1] << " " << quad[2] << " "
    << quad[3] << "\n$EndElements\n";
  return s.str();
}

RawMesh parse(const std::string& text, bool crossed) { return mesh::to_raw_mesh(mesh::parse_msh(text, "q.msh"), crossed); }

// A trapezoid: its diagonals cross at (2, 4/3), its corners' mean is (2, 1).
const std::array<Vec2, 4> kTrapezoid{Vec2(0, 0), Vec2(4, 0), Vec2(3, 2), Vec2(1, 2)};

void expect_trapezoid_split(const RawMesh& m) {
  ASSERT_EQ(m.nodes.size(), 5u);
  ASSERT_EQ(m.triangles.size(), 4u);
  const Index centre = 4;  // after the file's nodes
  EXPECT_NEAR((m.nodes[centre] - Vec2(2.0, 4.0 / 3.0)).norm(), 0.0, 1e-14);
  double area = 0.0;
  std::set<std::pair<Index, Index>> outer;
  for (const auto& t : m.triangles) {
    EXPECT_GT(area2(m, t), 0.0);  // counter-clockwise
    area += 0.5 * area2(m, t);
    EXPECT_EQ(std::count(t.begin(), t.end(), centre), 1);
    for (int j = 0; j < 3; ++j)
      if (t[j] != centre && t[(j + 1) % 3] != centre) outer.insert({t[j], t[(j + 1) % 3]});
  }
  EXPECT_NEAR(area, 6.0, 1e-12);  // (4 + 2) / 2 x 2
  // The outer edges are the quadrilateral's, counter-clockwise.
  EXPECT_EQ(outer, (std::set<std::pair<Index, Index>>{{0, 1}, {1, 2}, {2, 3}, {3, 0}}));
  const RawPhysicalGroup* block = m.find("block");
  ASSERT_NE(block, nullptr);
  EXPECT_EQ(block->triangles, (std::vector<Index>{0, 1, 2, 3}));
  for (Index g : m.triangle_surface_group) EXPECT_EQ(m.groups[static_cast<std::size_t>(g)].name, "block");
  const RawPhysicalGroup* base = m.find("base");
  ASSERT_NE(base, nullptr);
  EXPECT_EQ(base->edges, (std::vector<std::array<Index, 2>>{{0, 1}}));
}

// Every node past the file's is a quadrilateral's centre: in exactly 4 triangles, whose
// other corners make a quadrilateral with their diagonals crossing at it.
void expect_centres_at_crossings(const RawMesh& m, std::size_t file_nodes, std::size_t quads) {
  ASSERT_EQ(m.nodes.size(), file_nodes + quads);
  ASSERT_EQ(m.triangles.size(), 4 * quads);
  std::map<Index, std::vector<std::array<Index, 3>>> around;
  for (const auto& t : m.triangles)
    for (Index v : t)
      if (static_cast<std::size_t>(v) >= file_nodes) around[v].push_back(t);
  ASSERT_EQ(around.size(), quads);
  for (const auto& [c, tris] : around) {
    ASSERT_EQ(tris.size(), 4u) << "centre node " << c;
    // The triangles are (q_j, q_j+1, c) counter-clockwise: walk the ring.
    std::map<Index, Index> next;
    for (const auto& t : tris) {
      const auto k = std::find(t.begin(), t.end(), c) - t.begin();
      next[t[(k + 1) % 3]] = t[(k + 2) % 3];
    }
    ASSERT_EQ(next.size(), 4u);
    std::array<Index, 4> q{next.begin()->first, 0, 0, 0};
    for (int j = 1; j < 4; ++j) q[j] = next.at(q[j - 1]);
    EXPECT_EQ(next.at(q[3]), q[0]);
    const Vec2 x = crossing(m.nodes[q[0]], m.nodes[q[1]], m.nodes[q[2]], m.nodes[q[3]]);
    EXPECT_LT((m.nodes[c] - x).norm(), 1e-12 * (1.0 + x.norm())) << "centre node " << c;
  }
}

// The surface elements of a .msh by Gmsh type, and its node count.
std::map<int, std::size_t> surface_element_types(const mesh::MshFile& f) {
  std::map<int, std::size_t> n;
  for (const auto& [key, e] : f.entities)
    if (key.first == 2)
      for (const auto& [type, elems] : e.elements) n[type] += elems.size();
  return n;
}

std::size_t file_nodes(const mesh::MshFile& f) {
  std::size_t n = 0;
  for (const auto& [key, e] : f.entities) n += e.nodes.size();
  return n;
}

mesh::MshFile parse_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return mesh::parse_msh(s.str(), path);
}

// Edges of a curve group are boundary edges of the triangles: each an edge of one triangle.
void expect_curve_edges_on_triangles(const RawMesh& m, const std::string& group) {
  std::map<std::pair<Index, Index>, int> edges;
  for (const auto& t : m.triangles)
    for (int j = 0; j < 3; ++j) ++edges[std::minmax(t[j], t[(j + 1) % 3])];
  const RawPhysicalGroup* g = m.find(group);
  ASSERT_NE(g, nullptr) << group;
  ASSERT_FALSE(g->edges.empty()) << group;
  for (const auto& e : g->edges) EXPECT_EQ(edges[std::minmax(e[0], e[1])], 1) << group;
}

}  // namespace

TEST(CrossedMesh, TrapezoidSplitsInFourAtTheCrossingOfItsDiagonalsNotItsCentroid) {
  expect_trapezoid_split(parse(one_quad_msh(kTrapezoid, {1, 2, 3, 4}), true));
}

TEST(CrossedMesh, ClockwiseQuadrilateralGivesCounterClockwiseTriangles) {
  const RawMesh m = parse(one_quad_msh(kTrapezoid, {1, 4, 3, 2}), true);
  expect_trapezoid_split(m);
  EXPECT_EQ(m.triangles.front(), (std::array<Index, 3>{0, 1, 4}));  // the swap keeps the first corner first
}

TEST(CrossedMesh, QuadrilateralsWithoutCrossedAreRefusedNamingTheKey) {
  const std::string msg = test::error_of([] { parse(one_quad_msh(kTrapezoid, {1, 2, 3, 4}), false); });
  EXPECT_NE(msg.find("q.msh:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("3-node triangles"), std::string::npos) << msg;
  EXPECT_NE(msg.find("mesh.crossed: true"), std::string::npos) << msg;
}

TEST(CrossedMesh, NonConvexOrDegenerateQuadrilateralIsAnError) {
  // A dart: the corner (2, 0.5) points inwards, the diagonals do not cross inside.
  const std::array<Vec2, 4> dart{Vec2(0, 0), Vec2(4, 0), Vec2(2, 0.5), Vec2(2, 2)};
  std::string msg = test::error_of([&] { parse(one_quad_msh(dart, {1, 2, 3, 4}), true); });
  EXPECT_NE(msg.find("not strictly convex"), std::string::npos) << msg;
  // Three corners in a line: a triangle, not a quadrilateral.
  const std::array<Vec2, 4> flat{Vec2(0, 0), Vec2(2, 0), Vec2(4, 0), Vec2(2, 2)};
  msg = test::error_of([&] { parse(one_quad_msh(flat, {1, 2, 3, 4}), true); });
  EXPECT_NE(msg.find("not strictly convex"), std::string::npos) << msg;
  const std::array<Vec2, 4> line{Vec2(0, 0), Vec2(1, 0), Vec2(2, 0), Vec2(3, 0)};
  msg = test::error_of([&] { parse(one_quad_msh(line, {1, 2, 3, 4}), true); });
  EXPECT_NE(msg.find("degenerate"), std::string::npos) << msg;
}

TEST(CrossedMesh, TrianglesOfAMshAreKeptAsTheyAre) {
  const RawMesh plain = mesh::read_msh(test::mesh_data("square_msh22.msh"));
  const RawMesh crossed = mesh::read_msh(test::mesh_data("square_msh22.msh"), true);
  EXPECT_EQ(crossed.nodes, plain.nodes);
  EXPECT_EQ(crossed.triangles, plain.triangles);
}

TEST(CrossedMesh, GeoMeshedCrossedHasOnlyQuadrilateralsSplitInFourWithItsGroups) {
  const std::string plain_msh = (test::mesh_temp_dir() / "square_plain.msh").string();
  const std::string crossed_msh = (test::mesh_temp_dir() / "square_crossed.msh").string();
  mesh::mesh_geo(test::mesh_data("square.geo"), 0.2, plain_msh);
  mesh::mesh_geo(test::mesh_data("square.geo"), 0.2, crossed_msh, true);
  const mesh::MshFile f = parse_file(crossed_msh);
  const auto types = surface_element_types(f);
  ASSERT_EQ(types.size(), 1u);  // quadrilaterals only
  const std::size_t quads = types.at(mesh::kMshQuad4);

  const RawMesh plain = mesh::read_msh(plain_msh);
  const RawMesh m = mesh::read_msh(crossed_msh, true);
  expect_centres_at_crossings(m, file_nodes(f), quads);
  double area = 0.0;
  for (const auto& t : m.triangles) {
    EXPECT_GT(area2(m, t), 0.0);
    area += 0.5 * area2(m, t);
  }
  EXPECT_NEAR(area, 1.0, 1e-12);

  // The groups of the triangle mesh, with the same dimensions and tags.
  ASSERT_EQ(m.groups.size(), plain.groups.size());
  for (std::size_t g = 0; g < m.groups.size(); ++g) {
    EXPECT_EQ(m.groups[g].name, plain.groups[g].name);
    EXPECT_EQ(m.groups[g].dim, plain.groups[g].dim);
    EXPECT_EQ(m.groups[g].tag, plain.groups[g].tag);
  }
  EXPECT_EQ(m.find("block")->triangles.size(), m.triangles.size());
  for (const std::string curve : {"bottom", "top", "sides"}) expect_curve_edges_on_triangles(m, curve);
  double sides = 0.0;
  for (const auto& e : m.find("sides")->edges) sides += (m.nodes[e[1]] - m.nodes[e[0]]).norm();
  EXPECT_NEAR(sides, 2.0, 1e-12);
  for (Index n : m.find("top")->nodes) EXPECT_NEAR(m.nodes[n].y(), 1.0, 1e-12);
  const RawPhysicalGroup* centre = m.find("centre");
  ASSERT_EQ(centre->nodes.size(), 1u);
  EXPECT_NEAR((m.nodes[centre->nodes[0]] - Vec2(0.5, 0.5)).norm(), 0.0, 1e-12);

  // The size rule: the edges along the curves are about element_size (0.2 m), as in the
  // triangle mesh; the triangles are about 3 times as many or more on so coarse a mesh.
  const auto mean_curve_edge = [](const RawMesh& r) {
    double sum = 0.0;
    std::size_t n = 0;
    for (const auto& g : r.groups)
      for (const auto& e : g.edges) sum += (r.nodes[e[1]] - r.nodes[e[0]]).norm(), ++n;
    return sum / static_cast<double>(n);
  };
  EXPECT_NEAR(mean_curve_edge(m), 0.2, 0.04);
  EXPECT_NEAR(mean_curve_edge(plain), 0.2, 0.04);
  EXPECT_GE(m.triangles.size(), 3 * plain.triangles.size());

  // Gmsh's quadrilateral mesh without mesh.crossed: refused, naming the key.
  const std::string msg = test::error_of([&] { mesh::read_msh(crossed_msh); });
  EXPECT_NE(msg.find("mesh.crossed: true"), std::string::npos) << msg;
}

TEST(CrossedMesh, EntitiesInTwoSurfaceGroupsKeepBothAndOrphansAreRefused) {
  const std::string msh = (test::mesh_temp_dir() / "two_groups_crossed.msh").string();
  mesh::mesh_geo(test::mesh_data("two_groups.geo"), 0.5, msh, true);
  const RawMesh m = mesh::read_msh(msh, true);
  EXPECT_EQ(m.find("a")->triangles.size(), m.triangles.size());
  EXPECT_EQ(m.find("b")->triangles.size(), m.triangles.size());
  expect_curve_edges_on_triangles(m, "c1");
  expect_curve_edges_on_triangles(m, "c2");
  EXPECT_EQ(m.find("p")->nodes.size(), 1u);

  const std::string orphan = (test::mesh_temp_dir() / "orphan_crossed.msh").string();
  mesh::mesh_geo(test::mesh_data("orphan.geo"), 0.5, orphan, true);
  const std::string msg = test::error_of([&] { mesh::read_msh(orphan, true); });
  EXPECT_NE(msg.find("no physical surface group"), std::string::npos) << msg;
}

// The homogeneous slope's slope.geo (h = 0.5 m), crossed, passes dsdem check with its regions,
// boundaries and gauges; the check names the crossed mesh and its triangle count.
TEST(CrossedMesh, HomogeneousSlopeCrossedPassesCheck) {
  const std::string scenario = test::example("homogeneous_slope/scenario.yaml") + " --set mesh.file=slope.geo";
  const auto triangles = [](const std::string& out) {
    std::smatch m;
    return std::regex_search(out, m, std::regex(R"((\d+) nodes, (\d+) triangles)")) ? std::stol(m[2]) : -1L;
  };
  const auto plain = test::run_dsdem("check " + scenario);
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_EQ(plain.output.find("(crossed)"), std::string::npos) << plain.output;
  const auto c = test::run_dsdem("check " + scenario + " --set mesh.crossed=true");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("triangles (crossed)"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("scenario OK"), std::string::npos) << c.output;
  EXPECT_GE(triangles(c.output), 2.5 * static_cast<double>(triangles(plain.output))) << c.output;
  EXPECT_LE(triangles(c.output), 3.5 * static_cast<double>(triangles(plain.output))) << c.output;
}
