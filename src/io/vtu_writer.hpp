#pragma once
// VTK XML unstructured-grid (.vtu) output for ParaView (docs/user-guide.md): the triangles of
// the model at the current configuration, crack segments, and point clouds such as
// contact forces. Every file is written atomically (io/atomic_file.hpp).
//
// Array names follow the `<quantity>_<unit>` convention of io/atomic_file.hpp
// (name_with_unit): "displacement_m", "stress_Pa", "damage", "group_id".
//
// Extra data: the caller passes any number of extra point or cell fields as a FieldSet
// of non-owning views, so a new physics module (joint damage, plastic strain, ...) adds
// output without touching this writer. The views must stay valid during the call only.
#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "model/model.hpp"
#include "model/model3d.hpp"

namespace dsdem::io {

enum class VtuEncoding : std::uint8_t {
  AppendedRaw,   // raw binary appended block, zlib-compressed: a third smaller than base64, but
                 // meshio (the Python tools, users' scripts) misreads some such files: it
                 // renames each array's offset as it decodes and can then find the wrong array
  InlineBase64,  // base64 inside each DataArray, zlib-compressed: every reader (default)
  Ascii,         // human-readable numbers, for tests and debugging only (large, slow)
};

struct VtuOptions {
  VtuEncoding encoding = VtuEncoding::InlineBase64;
  // Simulated time, s. When finite it is stored as the FieldData array "TimeValue"
  // (ParaView's convention) so a lone file still knows its time; a PVD index supersedes it.
  double time_s = std::numeric_limits<double>::quiet_NaN();
};

// Values of one field, entity-major: values[i * components + c]. Integer views are
// written as Int32 (ids, codes, states), double views as Float64.
using FieldValues = std::variant<std::span<const double>, std::span<const std::int32_t>>;

// One named output field, a view of the caller's data (nothing is copied until the
// writer builds the file).
//   components == 1: scalar.
//   components == 2: a 2D vector (x, y). It is written with 3 components, z = 0, so
//                    ParaView treats it as a vector (glyphs, Warp By Vector, magnitude).
//   components >= 3: written as is (e.g. the Voigt stress xx, yy, xy).
// For a pair of scalars that is not a vector (e.g. two principal values) use two fields.
struct Field {
  std::string quantity;                      // snake_case, e.g. "damage"
  std::string unit;                          // SI unit token, "" if dimensionless or an id
  int components = 1;
  FieldValues values;
  std::vector<std::string> component_names;  // optional: empty, or one per component

  std::string array_name() const;            // name_with_unit(quantity, unit)
};
using FieldSet = std::vector<Field>;

// Convenience constructors of views.
Field scalar_field(std::string quantity, std::string unit, std::span<const double> values);
Field scalar_field(std::string quantity, std::string unit, std::span<const std::int32_t> values);
Field vector_field(std::string quantity, std::string unit, std::span<const Vec2> values);
Field vector_field(std::string quantity, std::string unit, std::span<const Vec3> values);

// The triangles of the model at the current configuration.
//   Points: x = X + u (z = 0), one per node, in node order.
//   Cells: VTK_TRIANGLE, one per triangle, in triangle order (so ParaView's cell ids
//          are the solver's element ids).
//   Point data: displacement_m, velocity_m_per_s, acceleration_m_per_s2 (3 components,
//          z = 0). Points are already displaced: use displacement to colour, not to warp.
//   Cell data: stress_Pa (xx, yy, xy), von_mises_stress_Pa, max_principal_stress_Pa,
//          min_principal_stress_Pa (in-plane, tension positive), strain (Green-Lagrange
//          xx, yy, engineering gamma_xy), group_id, material_id, zone (0 = A discrete,
//          1 = B bedrock, 2 = C contact bedrock); and one scalar per state variable the
//          material laws declare (Triangles::state), named after it with its unit
//          ("plastic_strain_xx", "plastic_dissipation_J_per_m3").
//   Von Mises uses sigma_zz = 0 in plane stress and sigma_zz = nu (sigma_xx + sigma_yy)
//   in plane strain (exact for small-strain linear elasticity, an estimate otherwise).
// Extra fields must have nodes.size() (point) or triangles.size() (cell) entries and
// names distinct from the built-in ones. Throws std::invalid_argument on a size or name
// mismatch or a node/material index out of range, std::runtime_error (naming the path
// and the OS error) if the file cannot be written; the target is then left untouched.
void write_triangles_vtu(const std::filesystem::path& path, const Nodes& nodes,
                         const Triangles& triangles, std::span<const Material> materials,
                         const FieldSet& extra_point_fields = {},
                         const FieldSet& extra_cell_fields = {}, const VtuOptions& options = {});

// The tetrahedra of a 3D model at the current configuration (docs/theory.md §14), as
// write_triangles_vtu: points x = X + u, one VTK_TETRA per tetrahedron in order; point data
// displacement_m, velocity_m_per_s, acceleration_m_per_s2; cell data stress_Pa (xx, yy, zz,
// yz, xz, xy), von_mises_stress_Pa, max_ and min_principal_stress_Pa (tension positive),
// strain (Green-Lagrange with engineering shears), group_id, material_id. The stress and
// strain must be filled (Solver3::update_stress). Throws as write_triangles_vtu.
void write_tetrahedra_vtu(const std::filesystem::path& path, const NodeArrays<3>& nodes,
                          const Tetrahedra& tetrahedra, std::span<const Material> materials,
                          const FieldSet& extra_point_fields = {}, const FieldSet& extra_cell_fields = {},
                          const VtuOptions& options = {});

// Line segments, one VTK_LINE cell each with its own two points (segments share no
// points, so a broken joint's faces can be drawn apart). For cracks the caller passes,
// per joint, the segment between its end points (or between the midpoints of its two
// faces) and cell fields such as state, damage, opening_m, slip_m, mode, time_broken_s.
void write_segments_vtu(const std::filesystem::path& path,
                        std::span<const std::array<Vec2, 2>> segments,
                        const FieldSet& cell_fields = {}, const VtuOptions& options = {});

// Points, one VTK_VERTEX cell each, with point fields (e.g. contact points with
// contact_force_N_per_m as a vector field).
void write_points_vtu(const std::filesystem::path& path, std::span<const Vec2> points,
                      const FieldSet& point_fields = {}, const VtuOptions& options = {});

}  // namespace dsdem::io
