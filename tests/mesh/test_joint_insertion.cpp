// Joint insertion (docs/theory.md §3, paper Fig. 3) on small hand-built meshes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "mesh/joint_insertion.hpp"

using namespace dsdem;

namespace {

// nx x ny unit squares, nodes i + (nx+1) j, each square split by its (i,j)-(i+1,j+1)
// diagonal into (n00, n10, n11) and (n00, n11, n01), both counter-clockwise.
// Triangles 2*(i + nx*j) and 2*(i + nx*j) + 1.
RawMesh grid(int nx, int ny) {
  RawMesh m;
  m.source = "grid.msh";
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.nodes.emplace_back(i, j);
  auto id = [&](int i, int j) { return Index(i + (nx + 1) * j); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  m.triangle_surface_group.assign(m.triangles.size(), kNoIndex);
  return m;
}

Index add_surface(RawMesh& m, const std::string& name, const std::vector<Index>& tris) {
  RawPhysicalGroup g;
  g.name = name;
  g.dim = 2;
  g.tag = static_cast<int>(m.groups.size()) + 1;
  g.triangles = tris;
  m.groups.push_back(g);
  const Index gi = static_cast<Index>(m.groups.size()) - 1;
  for (Index t : tris) m.triangle_surface_group[t] = gi;
  return gi;
}

Index add_curve(RawMesh& m, const std::string& name, const std::vector<std::array<Index, 2>>& edges) {
  RawPhysicalGroup g;
  g.name = name;
  g.dim = 1;
  g.tag = static_cast<int>(m.groups.size()) + 1;
  g.edges = edges;
  for (const auto& e : edges) {
    g.nodes.push_back(e[0]);
    g.nodes.push_back(e[1]);
  }
  m.groups.push_back(g);
  return static_cast<Index>(m.groups.size()) - 1;
}

// Invariants every insertion must satisfy, checked against the input mesh.
void check_invariants(const RawMesh& mesh, const JointInsertionResult& r) {
  ASSERT_EQ(r.nodes.size(), r.origin.size());
  ASSERT_EQ(r.triangles.size(), mesh.triangles.size());
  for (std::size_t n = 0; n < r.nodes.size(); ++n)
    EXPECT_EQ(r.nodes[n], mesh.nodes[r.origin[n]]);
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(r.origin[r.triangles[t][k]], mesh.triangles[t][k]);
  // Copies CSR lists each model node exactly once, under its origin.
  ASSERT_EQ(r.copies_offset.size(), mesh.nodes.size() + 1);
  EXPECT_EQ(r.copies.size(), r.nodes.size());
  for (std::size_t v = 0; v < mesh.nodes.size(); ++v)
    for (Index k = r.copies_offset[v]; k < r.copies_offset[v + 1]; ++k)
      EXPECT_EQ(r.origin[r.copies[k]], Index(v));
  const Joints& J = r.joints;
  for (std::size_t j = 0; j < J.size(); ++j) {
    const auto& nd = J.nodes[j];
    // Faces coincide in the reference configuration.
    EXPECT_EQ(r.nodes[nd[0]], r.nodes[nd[2]]);
    EXPECT_EQ(r.nodes[nd[1]], r.nodes[nd[3]]);
    EXPECT_NEAR(J.length0[j], (r.nodes[nd[1]] - r.nodes[nd[0]]).norm(), 1e-15);
    // a0 -> a1 counter-clockwise in tri_a; b1 -> b0 counter-clockwise in tri_b.
    const auto& ca = r.triangles[J.tri_a[j]];
    const auto& cb = r.triangles[J.tri_b[j]];
    bool a_ok = false, b_ok = false;
    for (int k = 0; k < 3; ++k) {
      a_ok = a_ok || (ca[k] == nd[0] && ca[(k + 1) % 3] == nd[1]);
      b_ok = b_ok || (cb[k] == nd[3] && cb[(k + 1) % 3] == nd[2]);
    }
    EXPECT_TRUE(a_ok) << "joint " << j;
    EXPECT_TRUE(b_ok) << "joint " << j;
    EXPECT_LT(J.tri_a[j], J.tri_b[j]);
    // Not both sides continuous: at least one face has nodes of its own.
    EXPECT_TRUE(nd[0] != nd[2] || nd[1] != nd[3]);
  }
}

}  // namespace

TEST(JointInsertion, SlideOnBedrockWithBrokenCrackAndWeakInterlayer) {
  // 2 x 2 squares: bottom row bedrock (continuous), top row slide (breakable).
  RawMesh m = grid(2, 2);
  const Index bedrock = add_surface(m, "bedrock", {0, 1, 2, 3});
  const Index slide = add_surface(m, "slide", {4, 5, 6, 7});
  const Index crack = add_curve(m, "crack", {{4, 7}});                   // x = 1 inside the slide
  const Index interlayer = add_curve(m, "interlayer", {{3, 4}, {4, 5}});  // y = 1 interface
  const Index old_crack = add_curve(m, "old_crack", {{1, 4}});           // x = 1 inside bedrock
  JointInsertionOptions o;
  o.breakable.assign(m.groups.size(), false);
  o.breakable[slide] = true;
  o.group_property.assign(m.groups.size(), kNoIndex);
  o.group_property[slide] = 1;
  o.curve_property[interlayer] = 2;
  o.broken_curves.insert(crack);
  o.broken_curves.insert(old_crack);  // continuous on both sides: no joint, reported

  const JointInsertionResult r = insert_joints(m, o);
  check_invariants(m, r);
  // 3 nodes per slide triangle + the 6 mesh nodes of the bedrock (rows y = 0, 1).
  EXPECT_EQ(r.nodes.size(), 3u * 4u + 6u);
  // Bedrock triangles share their nodes among themselves.
  std::set<Index> bedrock_nodes, slide_nodes;
  for (Index t : {0, 1, 2, 3}) bedrock_nodes.insert(r.triangles[t].begin(), r.triangles[t].end());
  for (Index t : {4, 5, 6, 7}) slide_nodes.insert(r.triangles[t].begin(), r.triangles[t].end());
  EXPECT_EQ(bedrock_nodes.size(), 6u);
  EXPECT_EQ(slide_nodes.size(), 12u);
  for (Index n : slide_nodes) EXPECT_EQ(bedrock_nodes.count(n), 0u);
  // Mesh node 4 (centre): one bedrock copy + slide triangles 4, 6, 7.
  EXPECT_EQ(r.copies_offset[5] - r.copies_offset[4], 4);

  // Joints: 2 slide diagonals + the slide's vertical edge + 2 interface edges.
  ASSERT_EQ(r.joints.size(), 5u);
  // Ordered by mesh edge: (3,4) (3,7) (4,5) (4,7) (4,8).
  const std::vector<std::array<Index, 2>> edges = {{3, 4}, {3, 7}, {4, 5}, {4, 7}, {4, 8}};
  for (std::size_t j = 0; j < 5; ++j) {
    const Index o0 = r.origin[r.joints.nodes[j][0]], o1 = r.origin[r.joints.nodes[j][1]];
    EXPECT_EQ(std::min(o0, o1), edges[j][0]) << j;
    EXPECT_EQ(std::max(o0, o1), edges[j][1]) << j;
  }
  // Interface joints: bedrock copy shared with the bedrock triangles, interlayer property.
  for (std::size_t j : {0u, 2u}) {
    EXPECT_EQ(r.joints.property[j], 2);
    EXPECT_EQ(r.joints.curve_group[j], interlayer);
    EXPECT_FALSE(r.joints.broken[j]);
    const Index tri_bedrock = r.joints.tri_a[j];
    EXPECT_EQ(m.triangle_surface_group[tri_bedrock], bedrock);
    EXPECT_EQ(m.triangle_surface_group[r.joints.tri_b[j]], slide);
    EXPECT_TRUE(bedrock_nodes.count(r.joints.nodes[j][0]) && bedrock_nodes.count(r.joints.nodes[j][1]));
  }
  // The crack starts broken; the diagonals take the slide's property.
  EXPECT_TRUE(r.joints.broken[3]);
  EXPECT_EQ(r.joints.break_mode(3), BreakMode::Initial);
  ASSERT_NE(r.joints.find_break(3), nullptr);
  EXPECT_EQ(r.joints.find_break(3)->time, 0.0);
  EXPECT_EQ(r.joints.damage(3), 1.0);
  EXPECT_EQ(r.joints.curve_group[3], crack);
  EXPECT_EQ(r.joints.find_break(3)->position, Vec2(1.0, 1.5));
  for (std::size_t j : {1u, 4u}) {
    EXPECT_EQ(r.joints.property[j], 1);
    EXPECT_EQ(r.joints.curve_group[j], kNoIndex);
    EXPECT_FALSE(r.joints.broken[j]);
    EXPECT_NEAR(r.joints.length0[j], std::sqrt(2.0), 1e-15);
    EXPECT_EQ(r.joints.find_break(j), nullptr);
    EXPECT_TRUE(std::isnan(r.joints.break_times()[j]));
  }
  ASSERT_EQ(r.curve_edges_without_joint.size(), 1u);
  EXPECT_EQ(r.curve_edges_without_joint[0], (std::array<Index, 2>{1, 4}));
}

TEST(JointInsertion, AllBreakableAndAllContinuous) {
  RawMesh m = grid(2, 2);
  const Index all = add_surface(m, "all", {0, 1, 2, 3, 4, 5, 6, 7});
  JointInsertionOptions o;
  o.breakable = {true};
  JointInsertionResult r = insert_joints(m, o);
  check_invariants(m, r);
  EXPECT_EQ(r.nodes.size(), 24u);
  EXPECT_EQ(r.joints.size(), 8u);  // 16 edges, 8 on the boundary
  for (std::size_t j = 0; j < r.joints.size(); ++j) EXPECT_EQ(r.joints.property[j], 0);

  o.breakable[all] = false;
  r = insert_joints(m, o);
  check_invariants(m, r);
  EXPECT_EQ(r.nodes.size(), 9u);
  EXPECT_EQ(r.joints.size(), 0u);
  EXPECT_EQ(r.triangles, m.triangles);  // untouched: one copy per mesh node, same order
}

TEST(JointInsertion, JointArraysReservedNotGrownByDoubling) {
  // Reserved for one joint per two edge sides (memory): every array's capacity
  // stays within 3 n_triangles / 2, where growing one joint at a time would have doubled
  // it to 2048 for these 1 160 joints (and kept 40 % more on the 10^6-element box).
  RawMesh m = grid(20, 20);
  std::vector<Index> all(m.triangles.size());
  for (std::size_t t = 0; t < all.size(); ++t) all[t] = static_cast<Index>(t);
  add_surface(m, "all", all);
  JointInsertionOptions o;
  o.breakable = {true};
  const JointInsertionResult r = insert_joints(m, o);
  check_invariants(m, r);
  const Joints& J = r.joints;
  ASSERT_EQ(J.size(), 1160u);  // (3 x 800 edge sides - 80 on the boundary) / 2
  const std::size_t bound = 3 * m.triangles.size() / 2;
  for (const std::size_t capacity :
       {J.nodes.capacity(), J.tri_a.capacity(), J.tri_b.capacity(), J.property.capacity(), J.curve_group.capacity(),
        J.length0.capacity(), J.state.capacity(), J.end_mode.capacity(), J.broken.capacity(),
        J.stiffness_scale.capacity()})
    EXPECT_LE(capacity, bound);
}

TEST(JointInsertion, CountsMatchBruteForceOnAPatchworkOfGroups) {
  // 6 x 5 squares, four surface groups in a patchwork (two breakable), one curve
  // crossing everything: counts against an independent O(T^2) enumeration.
  const int nx = 6, ny = 5;
  RawMesh m = grid(nx, ny);
  std::vector<std::vector<Index>> tris(4);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int g = (i / 2 + j / 2) % 4;
      tris[g].push_back(2 * (i + nx * j));
      tris[g].push_back(2 * (i + nx * j) + 1);
    }
  for (int g = 0; g < 4; ++g) add_surface(m, "g" + std::to_string(g), tris[g]);
  std::vector<std::array<Index, 2>> mid;  // vertical line x = 3
  for (int j = 0; j < ny; ++j) mid.push_back({Index(3 + (nx + 1) * j), Index(3 + (nx + 1) * (j + 1))});
  const Index curve = add_curve(m, "mid", mid);
  JointInsertionOptions o;
  o.breakable = {true, false, true, false, false};
  o.group_property = {5, kNoIndex, 6, kNoIndex, kNoIndex};
  o.interface_property = 9;
  o.broken_curves = {curve};
  const JointInsertionResult r = insert_joints(m, o);
  check_invariants(m, r);

  auto brk = [&](Index t) { return o.breakable[m.triangle_surface_group[t]]; };
  std::size_t n_brk = 0;
  std::set<Index> continuous_nodes;
  for (Index t = 0; t < Index(m.triangles.size()); ++t) {
    if (brk(t)) ++n_brk;
    else continuous_nodes.insert(m.triangles[t].begin(), m.triangles[t].end());
  }
  std::size_t interior = 0, interface = 0, interface_continuous = 0, on_curve = 0;
  std::set<std::array<Index, 2>> curve_edges(mid.begin(), mid.end());
  for (Index s = 0; s < Index(m.triangles.size()); ++s)
    for (Index t = s + 1; t < Index(m.triangles.size()); ++t) {
      std::vector<Index> shared;
      for (Index a : m.triangles[s])
        for (Index b : m.triangles[t])
          if (a == b) shared.push_back(a);
      if (shared.size() != 2) continue;
      const bool same = m.triangle_surface_group[s] == m.triangle_surface_group[t];
      if (!brk(s) && !brk(t)) {
        if (curve_edges.count({std::min(shared[0], shared[1]), std::max(shared[0], shared[1])}))
          ++interface_continuous;
        continue;
      }
      (same ? interior : interface)++;
      if (curve_edges.count({std::min(shared[0], shared[1]), std::max(shared[0], shared[1])}))
        ++on_curve;
    }
  EXPECT_EQ(r.nodes.size(), 3 * n_brk + continuous_nodes.size());
  EXPECT_EQ(r.joints.size(), interior + interface);
  std::size_t n_interface = 0, n_broken = 0;
  for (std::size_t j = 0; j < r.joints.size(); ++j) {
    const Index ga = m.triangle_surface_group[r.joints.tri_a[j]];
    const Index gb = m.triangle_surface_group[r.joints.tri_b[j]];
    if (ga != gb) {
      ++n_interface;
      EXPECT_EQ(r.joints.property[j], 9);
    } else {
      EXPECT_EQ(r.joints.property[j], ga == 0 ? 5 : 6);
    }
    if (r.joints.broken[j]) {
      ++n_broken;
      EXPECT_EQ(r.joints.curve_group[j], curve);
    }
  }
  EXPECT_EQ(n_interface, interface);
  EXPECT_EQ(n_broken, on_curve);
  EXPECT_GT(on_curve, 0u);  // the patchwork exercises every case
  EXPECT_GT(interface, 0u);
  EXPECT_GT(interface_continuous, 0u);
  EXPECT_EQ(r.curve_edges_without_joint.size(), interface_continuous);
  // Deterministic: a second run gives identical arrays.
  const JointInsertionResult r2 = insert_joints(m, o);
  EXPECT_EQ(r2.nodes, r.nodes);
  EXPECT_EQ(r2.triangles, r.triangles);
  EXPECT_EQ(r2.joints.nodes, r.joints.nodes);
  EXPECT_EQ(r2.joints.property, r.joints.property);
}

TEST(JointInsertion, RejectsBadInput) {
  RawMesh m = grid(1, 1);
  const Index g = add_surface(m, "s", {0, 1});
  JointInsertionOptions o;
  o.breakable = {true, true};  // wrong size
  EXPECT_THROW(insert_joints(m, o), std::runtime_error);
  o.breakable = {true};
  o.curve_property[g] = 1;  // not a curve group
  EXPECT_THROW(insert_joints(m, o), std::runtime_error);
  o.curve_property.clear();
  std::swap(m.triangles[0][1], m.triangles[0][2]);  // clockwise
  try {
    insert_joints(m, o);
    ADD_FAILURE() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("grid.msh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("counter-clockwise"), std::string::npos) << e.what();
  }
}
