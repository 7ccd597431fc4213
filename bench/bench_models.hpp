#pragma once
// Models for the whole-run benchmarks, built in code from structured meshes.
//  - box_model: the "synthetic box of breakable elements": a discrete block (every
//    triangle its own nodes, a cohesive joint on every interior edge, contact on) that
//    falls onto a contact ground slab, so joints break and contacts form.
//  - disc_model: a synthetic stand-in for examples/brazilian_disc (same radius, mesh
//    size, materials, joints and plates): a discrete disc cut from a structured mesh,
//    squeezed between two contact plates, the top one driven at 0.01 m/s.
#include <cmath>
#include <string>
#include <vector>

#include "common/block_on_ground.hpp"  // tests/common: shared with the solver tests
#include "io/scenario.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

namespace dsdem::bench {

inline void add_body(RawMesh& raw, RawMesh m, const std::string& name) {
  for (auto& g : m.groups)
    if (g.dim == 1) g.name = name + "_" + g.name;
  if (raw.nodes.empty()) {
    raw = std::move(m);
  } else {
    mesh::append_mesh(raw, m);
  }
}

// The solver tests' materials (rock, steel) with the paper's rock joints (§1.3.1) and
// contact stiffness 1 x E of the rock.
inline io::Scenario rock_scenario() {
  io::Scenario sc = test::impact_scenario();
  sc.file = "(bench)";
  sc.joints.defaults.params.values["c"] = 20e6;
  sc.joints.defaults.params.values["phi"] = 45;
  sc.joints.defaults.params.values["GI"] = 120;
  sc.joints.defaults.params.values["GII"] = 1500;
  sc.contact.kn = 21e9;
  return sc;
}

// The "synthetic box of breakable elements": tests/common/block_on_ground.hpp with
// nx x ny cells (2 nx ny discrete triangles) of side h on a steel ground, starting
// 0.001 h above it moving down at v0.
inline Model box_model(int nx, int ny, double h = 0.01, double v0 = 20.0) {
  test::BlockOnGround b;
  b.nx = nx;
  b.ny = ny;
  b.h = h;
  b.gap = 0.001;
  b.velocity = Vec2(0.0, -v0);
  b.ground_material = "steel";
  return test::block_on_ground(b, rock_scenario());
}

inline std::vector<solver::PrescribedDof> box_constraints(const Model& model) {
  io::BoundarySpec fixed;
  fixed.group = "ground";
  fixed.type = io::BoundaryType::Fixed;
  return solver::build_constraints(model, {fixed}, 0.0);
}

// Keeps the triangles of m whose centroid lies within radius R of (cx, cy).
inline RawMesh cut_disc(const RawMesh& m, double cx, double cy, double R) {
  RawMesh out;
  out.source = "disc";
  std::vector<Index> remap(m.nodes.size(), kNoIndex);
  RawPhysicalGroup g;
  g.name = "disc";
  g.dim = 2;
  for (const auto& t : m.triangles) {
    const Vec2 c = (m.nodes[t[0]] + m.nodes[t[1]] + m.nodes[t[2]]) / 3.0;
    if (std::hypot(c.x() - cx, c.y() - cy) > R) continue;
    std::array<Index, 3> nt;
    for (int k = 0; k < 3; ++k) {
      if (remap[t[k]] == kNoIndex) {
        remap[t[k]] = static_cast<Index>(out.nodes.size());
        out.nodes.push_back(m.nodes[t[k]]);
      }
      nt[k] = remap[t[k]];
    }
    g.triangles.push_back(static_cast<Index>(out.triangles.size()));
    out.triangles.push_back(nt);
    out.triangle_surface_group.push_back(0);
  }
  out.groups.push_back(g);
  return out;
}

// Brazilian disc, R = 0.1 m, element size h (examples/brazilian_disc: 0.0087 m, 3.7 mm
// on the diameter; h = 0.005 gives a similar element count).
inline Model disc_model(double h = 0.005) {
  const double R = 0.1;
  const int n = static_cast<int>(std::ceil(2 * R / h));
  RawMesh raw = cut_disc(mesh::rectangle_mesh(n, n, n * h, n * h, mesh::Diagonal::Alternate, -0.5 * n * h, -0.5 * n * h, "d"),
                         0.0, 0.0, R);
  const double gap = 0.0;
  add_body(raw, mesh::rectangle_mesh(20, 2, 0.2, 0.02, mesh::Diagonal::Alternate, -0.1, R + gap, "top_plate"), "top_plate");
  add_body(raw, mesh::rectangle_mesh(20, 2, 0.2, 0.02, mesh::Diagonal::Alternate, -0.1, -R - gap - 0.02, "bottom_plate"),
           "bottom_plate");
  io::Scenario sc = rock_scenario();
  sc.regions.push_back(io::RegionSpec{"disc", "rock", Zone::Discrete, {}, {}});
  sc.regions.push_back(io::RegionSpec{"top_plate", "steel", Zone::ContactBedrock, {}, {}});
  sc.regions.push_back(io::RegionSpec{"bottom_plate", "steel", Zone::ContactBedrock, {}, {}});
  return mesh::build_model(sc, raw);
}

// Bottom plate fixed, top plate driven down at 'speed' (no ramp: benchmarks run only
// a few thousand steps, so a fast plate makes contacts and breaks early).
inline std::vector<solver::PrescribedDof> disc_constraints(const Model& model, double speed = 1.0) {
  io::BoundarySpec bottom;
  bottom.group = "bottom_plate";
  bottom.type = io::BoundaryType::Fixed;
  io::BoundarySpec top;
  top.group = "top_plate";
  top.type = io::BoundaryType::Velocity;
  top.x = io::TimeHistory{{0.0}, {0.0}};
  top.y = io::TimeHistory{{0.0}, {-speed}};
  return solver::build_constraints(model, {bottom, top}, 0.0);
}

// A solver ready to step: constraints, gravity, dt = 0.3 x stable.
inline void prepare(solver::Solver& s, std::vector<solver::PrescribedDof> dofs, Vec2 gravity) {
  s.set_constraints(std::move(dofs));
  const double dt = 0.3 * solver::stable_time_step(s.model(), 0.0).dt;
  s.set_settings({gravity, 0.0, 0.0, dt, true});
  s.set_stress_on_demand(true);  // as `dsdem run` steps: stress and strain for output only
  s.initialise();
}

}  // namespace dsdem::bench
