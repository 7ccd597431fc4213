// The tetrahedra of a 3D model as VTU: points, cells, every built-in field read back by VTK.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>

#include "common/materials.hpp"
#include "io/io_test_util.hpp"
#include "io/vtu_writer.hpp"
#include "mesh/model_builder3d.hpp"
#include "mesh/structured.hpp"

namespace dsdem::io {
namespace {

using test::bits;
using test::ScratchDir;

TEST(VtuTetrahedra, PointsCellsAndFieldsReadBack) {
  ScratchDir dir;
  Model3 model = mesh::build_model_3d(mesh::box_mesh(2, 1, 1, 2.0, 1.0, 1.0), dsdem::test::elastic_material("rock", 1e9, 0.25, 2500));
  auto& n = model.nodes;
  for (std::size_t i = 0; i < n.size(); ++i) {
    n.u[i] = Vec3(1.0 / 3.0 * i, -1e-3 * i, std::sqrt(2.0) * 1e-4);
    n.v[i] = Vec3(std::exp(-double(i)), 0.5, -0.25 * i);
  }
  auto& t = model.tetrahedra;
  t.stress.resize(t.size());
  t.strain.resize(t.size());
  for (std::size_t e = 0; e < t.size(); ++e) {
    t.stress[e] << -1e6 - e, -2e6, -3e6, 1e5, -2e5 / 3.0, 3e5;
    t.strain[e] << 1e-4, -2e-4, 3e-4, 1e-5, 2e-5, -3e-5;
  }
  const auto path = dir / "tets.vtu";
  write_tetrahedra_vtu(path, n, t, model.materials);
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_EQ(grid->GetNumberOfPoints(), static_cast<vtkIdType>(n.size()));
  ASSERT_EQ(grid->GetNumberOfCells(), static_cast<vtkIdType>(t.size()));
  for (std::size_t e = 0; e < t.size(); ++e) {
    EXPECT_EQ(grid->GetCellType(static_cast<vtkIdType>(e)), VTK_TETRA);
    vtkIdType np = 0;
    const vtkIdType* ids = nullptr;
    grid->GetCellPoints(static_cast<vtkIdType>(e), np, ids);
    ASSERT_EQ(np, 4);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(ids[k], t.conn[e][k]);
  }
  for (std::size_t i = 0; i < n.size(); ++i) {
    double p[3];
    grid->GetPoint(static_cast<vtkIdType>(i), p);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(p[k]), bits(n.X[i][k] + n.u[i][k]));
  }
  vtkDataArray* stress = grid->GetCellData()->GetArray("stress_Pa");
  ASSERT_NE(stress, nullptr);
  EXPECT_EQ(stress->GetNumberOfComponents(), 6);
  EXPECT_EQ(stress->GetComponent(3, 4), t.stress[3][4]);
  vtkDataArray* velocity = grid->GetPointData()->GetArray("velocity_m_per_s");
  ASSERT_NE(velocity, nullptr);
  EXPECT_EQ(velocity->GetComponent(5, 2), n.v[5][2]);
  // Principal stresses and von Mises of the first cell against their closed forms' invariants.
  vtkDataArray* vm = grid->GetCellData()->GetArray("von_mises_stress_Pa");
  vtkDataArray* smax = grid->GetCellData()->GetArray("max_principal_stress_Pa");
  vtkDataArray* smin = grid->GetCellData()->GetArray("min_principal_stress_Pa");
  ASSERT_TRUE(vm && smax && smin);
  const Vec6& s = t.stress[0];
  const double j2 = ((s[0] - s[1]) * (s[0] - s[1]) + (s[1] - s[2]) * (s[1] - s[2]) + (s[2] - s[0]) * (s[2] - s[0])) / 6.0 +
                    s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
  EXPECT_NEAR(vm->GetComponent(0, 0), std::sqrt(3.0 * j2), 1e-9 * std::sqrt(3.0 * j2));
  // The principal values bound the diagonal, and their sum is the trace.
  EXPECT_GE(smax->GetComponent(0, 0), s.head<3>().maxCoeff());
  EXPECT_LE(smin->GetComponent(0, 0), s.head<3>().minCoeff());
  for (const char* name : {"strain", "group_id", "material_id", "displacement_m", "acceleration_m_per_s2"})
    EXPECT_TRUE(grid->GetCellData()->GetArray(name) || grid->GetPointData()->GetArray(name)) << name;
  // Stress not filled: refused, nothing written.
  t.stress.clear();
  EXPECT_THROW(write_tetrahedra_vtu(dir / "none.vtu", n, t, model.materials), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "none.vtu"));
}

}  // namespace
}  // namespace dsdem::io
