#pragma once
// The synthetic model of the solver-level tests and benchmarks, one copy for
// tests/solver (determinism, no allocation) and bench/ (the "box of breakable
// elements"): a discrete block (every triangle its own nodes, a cohesive joint on every
// interior edge, contact on) of nx x ny cells of side h, above a contact ground slab of
// nx x 2 cells, thrown at the ground so that joints break and contacts form.
#include <string>

#include "io/scenario.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"

namespace dsdem::test {

// Materials "rock" and "steel", joint defaults and contact of the solver tests; callers
// may change any of it before block_on_ground().
inline io::Scenario impact_scenario() {
  io::Scenario sc;
  sc.file = "(test)";
  Material rock;
  rock.name = "rock";
  rock.E = 21e9;
  rock.nu = 0.2;
  rock.rho = 2500;
  sc.materials["rock"] = rock;
  Material steel;
  steel.name = "steel";
  steel.E = 210e9;
  steel.nu = 0.3;
  steel.rho = 7850;
  sc.materials["steel"] = steel;
  sc.joints.present = true;
  sc.joints.defaults.params.values["ft"] = 2.5e6;
  sc.joints.defaults.params.values["c"] = 10e6;
  sc.joints.defaults.params.values["phi"] = 30;
  sc.joints.defaults.params.values["GI"] = 50;
  sc.joints.defaults.params.values["GII"] = 500;
  sc.contact.friction = 0.5;
  sc.contact.restitution = 0.5;
  sc.stages.push_back(io::StageSpec{});
  return sc;
}

struct BlockOnGround {
  int nx = 24, ny = 12;
  double h = 0.01;                   // cell size, m
  double gap = 0.02;                 // initial gap above the ground, in cells
  Vec2 velocity = Vec2(3.0, -20.0);  // initial velocity of the block, m/s
  std::string block_material = "rock";
  std::string ground_material = "rock";
};

// Groups "block" (discrete) and "ground" (contact zone; its boundary curves are
// "ground_bottom" etc.). sc: materials, joints and contact (impact_scenario()).
inline Model block_on_ground(const BlockOnGround& b, io::Scenario sc = impact_scenario()) {
  RawMesh raw = mesh::rectangle_mesh(b.nx, b.ny, b.nx * b.h, b.ny * b.h, mesh::Diagonal::Alternate, 0.0,
                                     b.gap * b.h, "block");
  RawMesh ground = mesh::rectangle_mesh(b.nx, 2, b.nx * b.h, 2 * b.h, mesh::Diagonal::Alternate, 0.0, -2 * b.h, "ground");
  for (auto& g : ground.groups)
    if (g.dim == 1) g.name = "ground_" + g.name;
  mesh::append_mesh(raw, ground);
  sc.regions.push_back(io::RegionSpec{"block", b.block_material, Zone::Discrete, {}, {}});
  sc.regions.push_back(io::RegionSpec{"ground", b.ground_material, Zone::ContactBedrock, {}, {}});
  Model model = mesh::build_model(sc, raw);
  for (Index t : model.groups[model.find_group("block")].triangles)
    for (Index n : model.triangles.conn[t]) model.nodes.v[n] = b.velocity;
  return model;
}

// The default block (joints on every interior edge, contact on, hitting the ground at
// 20 m/s, so joints break within a few hundred steps) with nx x ny cells.
inline Model impact_block(int nx, int ny) {
  BlockOnGround b;
  b.nx = nx;
  b.ny = ny;
  return block_on_ground(b);
}

}  // namespace dsdem::test
