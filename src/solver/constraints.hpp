#pragma once
// Prescribed motions of nodes (fixed, roller, velocity or displacement histories),
// built per stage from the scenario's boundary conditions.
#include <memory>
#include <vector>

#include "boundary/boundary_setup.hpp"
#include "io/scenario.hpp"
#include "model/model.hpp"
#include "model/model3d.hpp"

namespace dsdem::solver {

struct PrescribedDof {
  Index node = kNoIndex;
  int dir = 0;  // 0 = x, 1 = y
  enum Kind : std::uint8_t { Fixed, Velocity, Displacement } kind = Fixed;
  // Shared by the dofs of one boundary condition; owned here so no caller's lifetime matters.
  std::shared_ptr<const io::TimeHistory> history;
  double u_start = 0.0;    // displacement at the start of the stage (displacement histories are relative)
  double t_start = 0.0;    // stage start time: histories run on stage time
  double reaction_prev = 0.0;  // reaction force at the previous step, N (for the work it does)
  double u_prev = 0.0;         // the dof's displacement before this step's drift, m (solver scratch)
};

// Later conditions in the list override earlier ones on shared nodes; "free" releases. For a
// plane Model or a 3D Model3 (fixed holds every direction, x, y and z histories by the
// model's dimension).
template <class M>
std::vector<PrescribedDof> build_constraints(const M& model, const std::vector<io::BoundarySpec>& boundaries,
                                             double t_start);

// Viscous-spring boundary nodes for a new stage (docs/theory.md §6, stage 2): their springs
// start from the displacement u, and a node supported in the previous stage keeps that
// support's reaction as a constant load.
template <int D>
void attach_boundary_nodes(std::vector<boundary::BoundaryNodeD<D>>& nodes, const std::vector<VecD<D>>& u,
                           const std::vector<PrescribedDof>& previous_constraints) {
  for (auto& bn : nodes) {
    bn.u_ref = u[static_cast<std::size_t>(bn.node)];
    bn.static_force.setZero();
    for (const auto& d : previous_constraints)
      if (d.node == bn.node) bn.static_force[d.dir] += d.reaction_prev;
  }
}

// Prescribed velocity and acceleration of a dof at time t.
double prescribed_velocity(const PrescribedDof& d, double t);
double prescribed_acceleration(const PrescribedDof& d, double t);

}  // namespace dsdem::solver
