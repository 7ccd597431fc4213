#pragma once
// The discrete bar of the fracture tests and the time-step tests: a
// bar of triangles and cohesive joints whose mid-section, a named curve, is 1 % weaker,
// as in a notched specimen, so the crack has a place to start.
#include <vector>

#include "io/scenario.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"

namespace dsdem::test {

// One discrete region "bar" of rock (E, nu 0.2, rho 2500) with joints ft, c = 4 ft,
// phi 30 deg, GI 120 N/m, GII 1500 N/m and the penalty rule p = 50.
inline io::Scenario discrete_bar_scenario(double E, double ft) {
  io::Scenario sc;
  sc.file = "(test)";
  Material m;
  m.name = "rock";
  m.E = E;
  m.nu = 0.2;
  m.rho = 2500;
  sc.materials["rock"] = m;
  sc.regions.push_back(io::RegionSpec{"bar", "rock", Zone::Discrete, {}, {}});
  sc.joints.present = true;
  sc.joints.defaults.params.values["ft"] = ft;
  sc.joints.defaults.params.values["c"] = 4 * ft;
  sc.joints.defaults.params.values["phi"] = 30;
  sc.joints.defaults.params.values["GI"] = 120;
  sc.joints.defaults.params.values["GII"] = 1500;
  sc.joints.defaults.params.values["penalty"] = 50;
  sc.stages.push_back(io::StageSpec{});
  return sc;
}

// A bar L x H of nx x ny cells, joints with the given penalty and friction 0.3 once
// broken; the joints of the mid-section (curve "mid", x = L/2) have 0.99 ft and, when
// section_penalty > 0, that penalty instead.
inline Model notched_bar(double L, double H, int nx, int ny, double E, double ft, double penalty,
                         double section_penalty = 0.0) {
  RawMesh raw = mesh::rectangle_mesh(nx, ny, L, H, mesh::Diagonal::Alternate, 0, 0, "bar");
  RawPhysicalGroup notch;
  notch.name = "mid";
  notch.dim = 1;
  for (int i = 0; i < ny; ++i)
    notch.edges.push_back({static_cast<Index>(i * (nx + 1) + nx / 2), static_cast<Index>((i + 1) * (nx + 1) + nx / 2)});
  raw.groups.push_back(notch);
  io::Scenario sc = discrete_bar_scenario(E, ft);
  io::JointSpec weak;
  weak.params.values["ft"] = 0.99 * ft;
  if (section_penalty > 0.0) weak.params.values["penalty"] = section_penalty;
  sc.joints.curves["mid"] = weak;
  sc.joints.defaults.params.values["penalty"] = penalty;
  sc.contact.friction = 0.3;
  return mesh::build_model(sc, raw);
}

// Left end fixed, right end pulled at 0.02 m/s after a gentle ramp (fills `right`).
inline std::vector<io::BoundarySpec> pull_bar(io::BoundarySpec& right) {
  io::BoundarySpec left;
  left.group = "left";
  left.type = io::BoundaryType::Fixed;
  right.group = "right";
  right.type = io::BoundaryType::Velocity;
  right.x = io::TimeHistory{{0.0, 2e-4}, {0.0, 0.02}};
  right.y = io::TimeHistory{{0.0}, {0.0}};
  return {left, right};
}

}  // namespace dsdem::test
