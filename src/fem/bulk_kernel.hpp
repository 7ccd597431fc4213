#pragma once
// What a bulk law's kernel is to the element loop (bulk_law.hpp lists them; the law's
// declaration, with its parameters, state and strength reduction, is in law/laws.cpp).
//
// A kernel is a struct with
//   name          the declared law it implements (law::material_laws())
//   Model         its constants, built once per material and shared read-only by threads;
//                 with the elastic constants as `elastic` (stiffness damping, plane-strain S0_zz)
//   State         trivially copyable doubles in the order of the declared state variables
//                 (none for a law without state)
//   kDissipation  the position in State of the accumulated dissipation, J/m^3 (the energy
//                 ledger's plastic work), or -1
//   make(params, elastic, plane_stress)   the Model from the declared parameters (declaration
//                 order and units); throws std::invalid_argument naming what is wrong
//   update(model, E, S0, S0_zz, start, end)   from the Green strain E (xx, yy, 2xy) at the
//                 step's end, the initial stress and the state at the step's start: the
//                 BulkResponse, and the state at the step's end into `end`
// and, for a law that also runs in 3D (the tetrahedron, tet4.hpp),
//   State3D, kDissipation3D   its state in 3D and the dissipation's position in it
//   update_3d(model, E, S0, start, end)   the same from the 3D Green strain (Voigt xx, yy,
//                 zz, 2yz, 2xz, 2xy): the BulkResponse3D
// A law without state (linear elastic) has the whole element's kernels of cst.hpp and
// tet4.hpp instead of update and update_3d.
#include <cstddef>

#include "model/types.hpp"

namespace dsdem::fem {

// One update of a bulk law at one material point, per unit reference volume.
struct BulkResponse {
  Vec3 S = Vec3::Zero();       // second Piola-Kirchhoff stress (xx, yy, xy), Pa
  double S_zz = 0.0;           // the out-of-plane stress of plane strain, Pa
  double strain_energy = 0.0;  // stored elastic energy, J/m^3
  double dissipation = 0.0;    // plastic work of this update, J/m^3, >= 0
};

// The same in 3D: no out-of-plane stress.
struct BulkResponse3D {
  Vec6 S = Vec6::Zero();       // second Piola-Kirchhoff stress, Voigt (xx, yy, zz, yz, xz, xy), Pa
  double strain_energy = 0.0;  // J/m^3
  double dissipation = 0.0;    // J/m^3, >= 0
};

// The most state variables a bulk law may declare (the element loop's fixed arrays).
inline constexpr std::size_t kMaxBulkState = 8;
inline constexpr std::size_t kMaxBulkState3D = 8;

}  // namespace dsdem::fem
