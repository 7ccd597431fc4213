#include "io/vtu_writer.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace dsdem::io {
namespace fs = std::filesystem;

// The views below reinterpret arrays of Eigen fixed-size vectors as arrays of doubles.
static_assert(sizeof(Vec2) == 2 * sizeof(double), "Vec2 must be two packed doubles");
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
static_assert(sizeof(Vec6) == 6 * sizeof(double), "Vec6 must be six packed doubles");
static_assert(sizeof(Index) == sizeof(std::int32_t));

namespace {

template <class V>
std::span<const double> flat_doubles(std::span<const V> v) {
  constexpr std::size_t k = sizeof(V) / sizeof(double);
  if (v.empty()) return {};
  return {v.data()->data(), k * v.size()};
}

std::size_t value_count(const FieldValues& values) {
  return std::visit([](auto s) { return s.size(); }, values);
}

// Checks one field against the number of entities it describes and against the names
// already used in the same attribute block (ParaView would silently show only one).
void check_field(const Field& f, std::size_t entities, std::string_view block,
                 std::vector<std::string>& used_names) {
  const std::string name = f.array_name();
  if (f.quantity.empty())
    throw std::invalid_argument(fmt::format("VTU {} field with an empty name", block));
  if (f.components < 1)
    throw std::invalid_argument(
        fmt::format("VTU {} field '{}': {} components", block, name, f.components));
  if (!f.component_names.empty() && f.component_names.size() != std::size_t(f.components))
    throw std::invalid_argument(fmt::format("VTU {} field '{}': {} component names for {} components",
                                            block, name, f.component_names.size(), f.components));
  const std::size_t expected = entities * std::size_t(f.components);
  if (value_count(f.values) != expected)
    throw std::invalid_argument(fmt::format(
        "VTU {} field '{}': {} values, expected {} ({} entities x {} components)", block, name,
        value_count(f.values), expected, entities, f.components));
  if (std::find(used_names.begin(), used_names.end(), name) != used_names.end())
    throw std::invalid_argument(fmt::format("VTU {} field '{}' given twice", block, name));
  used_names.push_back(name);
}

// Copies one field into a new VTK array (Float64 or Int32), padding 2D vectors to 3D.
vtkSmartPointer<vtkDataArray> make_array(const Field& f, std::size_t entities) {
  const int in_comp = f.components;
  const int out_comp = in_comp == 2 ? 3 : in_comp;
  return std::visit(
      [&](auto values) -> vtkSmartPointer<vtkDataArray> {
        using T = std::remove_const_t<typename decltype(values)::element_type>;
        using Array = std::conditional_t<std::is_same_v<T, double>, vtkDoubleArray, vtkIntArray>;
        auto array = vtkSmartPointer<Array>::New();
        array->SetName(f.array_name().c_str());
        array->SetNumberOfComponents(out_comp);
        array->SetNumberOfTuples(static_cast<vtkIdType>(entities));
        auto* dst = array->GetPointer(0);
        for (std::size_t i = 0; i < entities; ++i) {
          for (int c = 0; c < in_comp; ++c) dst[i * out_comp + c] = values[i * in_comp + c];
          if (out_comp != in_comp) dst[i * out_comp + 2] = T(0);
        }
        for (std::size_t c = 0; c < f.component_names.size(); ++c)
          array->SetComponentName(static_cast<vtkIdType>(c), f.component_names[c].c_str());
        if (out_comp != in_comp && !f.component_names.empty()) array->SetComponentName(2, "z");
        return array;
      },
      f.values);
}

void add_fields(vtkDataSetAttributes* attributes, const FieldSet& fields, std::size_t entities,
                std::string_view block, std::vector<std::string>& used_names) {
  for (const Field& f : fields) check_field(f, entities, block, used_names);
  for (const Field& f : fields) attributes->AddArray(make_array(f, entities));
}

// A grid whose points are `xy` (`dim` doubles per point: 2, z = 0, or 3) and whose cells
// all have the same type and `nodes_per_cell` point ids taken in order from `connectivity`.
vtkSmartPointer<vtkUnstructuredGrid> make_grid(std::span<const double> xy, int cell_type,
                                               int nodes_per_cell,
                                               std::span<const vtkIdType> connectivity, int dim = 2) {
  const std::size_t d = static_cast<std::size_t>(dim);
  const std::size_t n_points = xy.size() / d;
  vtkNew<vtkDoubleArray> coords;
  coords->SetNumberOfComponents(3);
  coords->SetNumberOfTuples(static_cast<vtkIdType>(n_points));
  double* p = coords->GetPointer(0);
  for (std::size_t i = 0; i < n_points; ++i) {
    p[3 * i] = xy[d * i];
    p[3 * i + 1] = xy[d * i + 1];
    p[3 * i + 2] = d == 3 ? xy[d * i + 2] : 0.0;
  }
  vtkNew<vtkPoints> points;
  points->SetData(coords);

  const std::size_t n_cells = connectivity.size() / std::size_t(nodes_per_cell);
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(static_cast<vtkIdType>(n_cells + 1));
  for (std::size_t c = 0; c <= n_cells; ++c)
    offsets->SetValue(static_cast<vtkIdType>(c), static_cast<vtkIdType>(c * nodes_per_cell));
  vtkNew<vtkIdTypeArray> conn;
  conn->SetNumberOfTuples(static_cast<vtkIdType>(connectivity.size()));
  std::copy(connectivity.begin(), connectivity.end(), conn->GetPointer(0));
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, conn);

  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(cell_type, cells);
  return grid;
}

void add_time(vtkUnstructuredGrid* grid, double time_s) {
  if (!std::isfinite(time_s)) return;
  vtkNew<vtkDoubleArray> time;
  time->SetName("TimeValue");
  time->SetNumberOfTuples(1);
  time->SetValue(0, time_s);
  grid->GetFieldData()->AddArray(time);
}

// Encodes the grid in memory with VTK, then hands the bytes to the atomic writer: VTK
// writing straight to `path` could leave a truncated file behind.
void write_grid(const fs::path& path, vtkUnstructuredGrid* grid, const VtuOptions& options) {
  add_time(grid, options.time_s);
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetInputData(grid);
  writer->SetWriteToOutputString(true);
  // 64-bit block headers: a large mesh must not overflow a 4 GiB array size.
  writer->SetHeaderTypeToUInt64();
  switch (options.encoding) {
    case VtuEncoding::AppendedRaw:
      writer->SetDataModeToAppended();
      writer->EncodeAppendedDataOff();
      writer->SetCompressorTypeToZLib();
      break;
    case VtuEncoding::InlineBase64:
      writer->SetDataModeToBinary();
      writer->SetCompressorTypeToZLib();
      break;
    case VtuEncoding::Ascii:
      writer->SetDataModeToAscii();
      writer->SetCompressorTypeToNone();
      break;
  }
  if (writer->Write() != 1 || writer->GetErrorCode() != 0)
    throw std::runtime_error(fmt::format("cannot write '{}': VTK failed to encode the grid",
                                         path.string()));
  write_file_atomically(path, writer->GetOutputString());
}

// In-plane principal stresses (tension positive) and von Mises of one Voigt stress.
struct StressInvariants {
  double max_principal, min_principal, von_mises;
};

StressInvariants stress_invariants(const Vec3& s, double sigma_zz) {
  const double centre = 0.5 * (s[0] + s[1]);
  const double radius = std::hypot(0.5 * (s[0] - s[1]), s[2]);
  const double dxy = s[0] - s[1], dyz = s[1] - sigma_zz, dzx = sigma_zz - s[0];
  const double vm = std::sqrt(0.5 * (dxy * dxy + dyz * dyz + dzx * dzx) + 3.0 * s[2] * s[2]);
  return {centre + radius, centre - radius, vm};
}

// A unit as written in declarations ("J/m^3", "m/s^2") as an array-name token
// ("J_per_m3", "m_per_s2"), the convention of the built-in fields.
std::string unit_token(const std::string& unit) {
  std::string out;
  for (const char ch : unit) {
    if (ch == '/') out += "_per_";
    else if (ch != '^' && ch != ' ') out += ch;
  }
  return out;
}

void check_triangles(const Nodes& nodes, const Triangles& t, std::size_t n_materials) {
  const std::size_t n = t.size();
  if (t.group.size() != n || t.material.size() != n || t.zone.size() != n ||
      t.stress.size() != n || t.strain.size() != n)
    throw std::invalid_argument("VTU: triangle arrays of different lengths");
  if (nodes.u.size() != nodes.size() || nodes.v.size() != nodes.size() ||
      nodes.a.size() != nodes.size())
    throw std::invalid_argument("VTU: node arrays of different lengths");
  const auto n_nodes = static_cast<Index>(nodes.size());
  for (std::size_t e = 0; e < n; ++e) {
    for (Index i : t.conn[e])
      if (i < 0 || i >= n_nodes)
        throw std::invalid_argument(
            fmt::format("VTU: triangle {} refers to node {} of {}", e, i, n_nodes));
    if (t.material[e] < 0 || std::size_t(t.material[e]) >= n_materials)
      throw std::invalid_argument(fmt::format("VTU: triangle {} has material {} of {}", e,
                                              t.material[e], n_materials));
  }
}

}  // namespace

std::string Field::array_name() const { return name_with_unit(quantity, unit); }

Field scalar_field(std::string quantity, std::string unit, std::span<const double> values) {
  return Field{std::move(quantity), std::move(unit), 1, values, {}};
}

Field scalar_field(std::string quantity, std::string unit, std::span<const std::int32_t> values) {
  return Field{std::move(quantity), std::move(unit), 1, values, {}};
}

Field vector_field(std::string quantity, std::string unit, std::span<const Vec2> values) {
  return Field{std::move(quantity), std::move(unit), 2, flat_doubles(values), {}};
}

Field vector_field(std::string quantity, std::string unit, std::span<const Vec3> values) {
  return Field{std::move(quantity), std::move(unit), 3, flat_doubles(values), {}};
}

void write_triangles_vtu(const fs::path& path, const Nodes& nodes, const Triangles& triangles,
                         std::span<const Material> materials, const FieldSet& extra_point_fields,
                         const FieldSet& extra_cell_fields, const VtuOptions& options) {
  check_triangles(nodes, triangles, materials.size());
  const std::size_t n_nodes = nodes.size();
  const std::size_t n_tri = triangles.size();

  std::vector<double> current(2 * n_nodes);
  for (std::size_t i = 0; i < n_nodes; ++i) {
    const Vec2 x = nodes.X[i] + nodes.u[i];
    current[2 * i] = x.x();
    current[2 * i + 1] = x.y();
  }
  std::vector<vtkIdType> conn(3 * n_tri);
  for (std::size_t e = 0; e < n_tri; ++e)
    for (int k = 0; k < 3; ++k) conn[3 * e + k] = triangles.conn[e][k];
  auto grid = make_grid(current, VTK_TRIANGLE, 3, conn);

  // Derived cell quantities, computed once per frame.
  std::vector<double> s_max(n_tri), s_min(n_tri), von_mises(n_tri);
  std::vector<std::int32_t> zone(n_tri);
  for (std::size_t e = 0; e < n_tri; ++e) {
    const Material& m = materials[triangles.material[e]];
    const Vec3& s = triangles.stress[e];
    const double sigma_zz = m.plane_stress ? 0.0 : m.nu * (s[0] + s[1]);
    const StressInvariants inv = stress_invariants(s, sigma_zz);
    s_max[e] = inv.max_principal;
    s_min[e] = inv.min_principal;
    von_mises[e] = inv.von_mises;
    zone[e] = static_cast<std::int32_t>(triangles.zone[e]);
  }

  const FieldSet point_fields = {
      vector_field("displacement", "m", nodes.u),
      vector_field("velocity", "m_per_s", nodes.v),
      vector_field("acceleration", "m_per_s2", nodes.a),
  };
  const FieldSet cell_fields = {
      Field{"stress", "Pa", 3, flat_doubles(std::span<const Vec3>(triangles.stress)),
            {"xx", "yy", "xy"}},
      scalar_field("von_mises_stress", "Pa", von_mises),
      scalar_field("max_principal_stress", "Pa", s_max),
      scalar_field("min_principal_stress", "Pa", s_min),
      Field{"strain", "", 3, flat_doubles(std::span<const Vec3>(triangles.strain)),
            {"xx", "yy", "gamma_xy"}},
      scalar_field("group_id", "", std::span<const std::int32_t>(triangles.group)),
      scalar_field("material_id", "", std::span<const std::int32_t>(triangles.material)),
      scalar_field("zone", "", zone),
  };

  // The laws' state variables, each under its declared name and unit (law/registry.hpp).
  FieldSet state_fields;
  for (std::size_t k = 0; k < triangles.state.columns(); ++k)
    state_fields.push_back(scalar_field(triangles.state.names[k], unit_token(triangles.state.units[k]),
                                        std::span<const double>(triangles.state.values[k])));

  std::vector<std::string> point_names, cell_names;
  add_fields(grid->GetPointData(), point_fields, n_nodes, "point", point_names);
  add_fields(grid->GetPointData(), extra_point_fields, n_nodes, "point", point_names);
  add_fields(grid->GetCellData(), cell_fields, n_tri, "cell", cell_names);
  add_fields(grid->GetCellData(), state_fields, n_tri, "cell", cell_names);
  add_fields(grid->GetCellData(), extra_cell_fields, n_tri, "cell", cell_names);
  write_grid(path, grid, options);
}

void write_tetrahedra_vtu(const fs::path& path, const NodeArrays<3>& nodes, const Tetrahedra& tetrahedra,
                          std::span<const Material> materials, const FieldSet& extra_point_fields,
                          const FieldSet& extra_cell_fields, const VtuOptions& options) {
  const std::size_t n_nodes = nodes.size(), n_tet = tetrahedra.size();
  if (tetrahedra.group.size() != n_tet || tetrahedra.material.size() != n_tet || tetrahedra.stress.size() != n_tet ||
      tetrahedra.strain.size() != n_tet)
    throw std::invalid_argument("VTU: tetrahedron arrays of different lengths (stress and strain filled?)");
  if (nodes.u.size() != n_nodes || nodes.v.size() != n_nodes || nodes.a.size() != n_nodes)
    throw std::invalid_argument("VTU: node arrays of different lengths");
  std::vector<double> current(3 * n_nodes);
  for (std::size_t i = 0; i < n_nodes; ++i)
    for (int k = 0; k < 3; ++k) current[3 * i + k] = nodes.X[i][k] + nodes.u[i][k];
  std::vector<vtkIdType> conn(4 * n_tet);
  for (std::size_t e = 0; e < n_tet; ++e) {
    for (int k = 0; k < 4; ++k) {
      const Index i = tetrahedra.conn[e][k];
      if (i < 0 || static_cast<std::size_t>(i) >= n_nodes)
        throw std::invalid_argument(fmt::format("VTU: tetrahedron {} refers to node {} of {}", e, i, n_nodes));
      conn[4 * e + k] = i;
    }
    if (tetrahedra.material[e] < 0 || static_cast<std::size_t>(tetrahedra.material[e]) >= materials.size())
      throw std::invalid_argument(fmt::format("VTU: tetrahedron {} has material {} of {}", e, tetrahedra.material[e],
                                              materials.size()));
  }
  auto grid = make_grid(current, VTK_TETRA, 4, conn, 3);

  // Principal stresses (tension positive) and von Mises of each tetrahedron's stress.
  std::vector<double> s_max(n_tet), s_min(n_tet), von_mises(n_tet);
  for (std::size_t e = 0; e < n_tet; ++e) {
    const Vec6& s = tetrahedra.stress[e];
    Mat3 m;
    m << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
    const Vec3 ev = Eigen::SelfAdjointEigenSolver<Mat3>(m, Eigen::EigenvaluesOnly).eigenvalues();
    s_min[e] = ev[0];
    s_max[e] = ev[2];
    const double a = ev[0] - ev[1], b = ev[1] - ev[2], c = ev[2] - ev[0];
    von_mises[e] = std::sqrt(0.5 * (a * a + b * b + c * c));
  }
  const FieldSet point_fields = {
      vector_field("displacement", "m", nodes.u),
      vector_field("velocity", "m_per_s", nodes.v),
      vector_field("acceleration", "m_per_s2", nodes.a),
  };
  const FieldSet cell_fields = {
      Field{"stress", "Pa", 6, flat_doubles(std::span<const Vec6>(tetrahedra.stress)),
            {"xx", "yy", "zz", "yz", "xz", "xy"}},
      scalar_field("von_mises_stress", "Pa", von_mises),
      scalar_field("max_principal_stress", "Pa", s_max),
      scalar_field("min_principal_stress", "Pa", s_min),
      Field{"strain", "", 6, flat_doubles(std::span<const Vec6>(tetrahedra.strain)),
            {"xx", "yy", "zz", "gamma_yz", "gamma_xz", "gamma_xy"}},
      scalar_field("group_id", "", std::span<const std::int32_t>(tetrahedra.group)),
      scalar_field("material_id", "", std::span<const std::int32_t>(tetrahedra.material)),
  };
  std::vector<std::string> point_names, cell_names;
  add_fields(grid->GetPointData(), point_fields, n_nodes, "point", point_names);
  add_fields(grid->GetPointData(), extra_point_fields, n_nodes, "point", point_names);
  add_fields(grid->GetCellData(), cell_fields, n_tet, "cell", cell_names);
  add_fields(grid->GetCellData(), extra_cell_fields, n_tet, "cell", cell_names);
  write_grid(path, grid, options);
}

void write_segments_vtu(const fs::path& path, std::span<const std::array<Vec2, 2>> segments,
                        const FieldSet& cell_fields, const VtuOptions& options) {
  const std::size_t n = segments.size();
  std::vector<double> xy(4 * n);
  std::vector<vtkIdType> conn(2 * n);
  for (std::size_t s = 0; s < n; ++s) {
    for (int k = 0; k < 2; ++k) {
      xy[4 * s + 2 * k] = segments[s][k].x();
      xy[4 * s + 2 * k + 1] = segments[s][k].y();
      conn[2 * s + k] = static_cast<vtkIdType>(2 * s + k);
    }
  }
  auto grid = make_grid(xy, VTK_LINE, 2, conn);
  std::vector<std::string> names;
  add_fields(grid->GetCellData(), cell_fields, n, "cell", names);
  write_grid(path, grid, options);
}

void write_points_vtu(const fs::path& path, std::span<const Vec2> points,
                      const FieldSet& point_fields, const VtuOptions& options) {
  const std::size_t n = points.size();
  std::vector<vtkIdType> conn(n);
  for (std::size_t i = 0; i < n; ++i) conn[i] = static_cast<vtkIdType>(i);
  auto grid = make_grid(flat_doubles(points), VTK_VERTEX, 1, conn);
  std::vector<std::string> names;
  add_fields(grid->GetPointData(), point_fields, n, "point", names);
  write_grid(path, grid, options);
}

}  // namespace dsdem::io
