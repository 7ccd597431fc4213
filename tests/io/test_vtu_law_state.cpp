// Law state variables (Triangles::state) become VTU cell fields named after their
// declaration, with the unit in the name as for the built-in fields.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "io/io_test_util.hpp"
#include "io/vtu_writer.hpp"
#include "law/laws.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"

using namespace dsdem;

namespace {

vtkSmartPointer<vtkUnstructuredGrid> read_back(const std::filesystem::path& path) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_EQ(reader->GetErrorCode(), 0u) << path;
  return reader->GetOutput();
}

Model model_of(const std::string& law_name) {
  Material m;
  m.name = "soil";
  m.model = law_name;
  m.E = 5e7;
  m.nu = 0.3;
  m.rho = 1800;
  return mesh::build_model(mesh::rectangle_mesh(2, 1, 1.0, 0.5), m);
}

}  // namespace

TEST(VtuLawState, EachDeclaredStateVariableIsACellField) {
  io::test::ScratchDir dir;
  Model model = model_of("mohr_coulomb");
  model.triangles.stress.assign(model.triangles.size(), Vec3::Zero());
  model.triangles.strain.assign(model.triangles.size(), Vec3::Zero());
  const auto& decl = law::material_laws().get("mohr_coulomb");
  ASSERT_EQ(model.triangles.state.columns(), decl.state.size());
  for (std::size_t k = 0; k < decl.state.size(); ++k)
    for (std::size_t t = 0; t < model.triangles.size(); ++t)
      model.triangles.state.values[k][t] = 1e-3 * static_cast<double>(k + 1) + static_cast<double>(t) / 3.0;
  const auto path = dir / "state.vtu";
  io::write_triangles_vtu(path, model.nodes, model.triangles, model.materials);
  auto grid = read_back(path);
  vtkCellData* cells = grid->GetCellData();
  for (std::size_t k = 0; k < decl.state.size(); ++k) {
    const std::string name = decl.state[k].name == "plastic_dissipation" ? "plastic_dissipation_J_per_m3"
                                                                         : decl.state[k].name;
    vtkDataArray* a = cells->GetArray(name.c_str());
    ASSERT_NE(a, nullptr) << name;
    ASSERT_EQ(a->GetNumberOfComponents(), 1);
    ASSERT_EQ(a->GetNumberOfTuples(), static_cast<vtkIdType>(model.triangles.size()));
    for (std::size_t t = 0; t < model.triangles.size(); ++t)
      EXPECT_EQ(io::test::bits(a->GetTuple1(static_cast<vtkIdType>(t))), io::test::bits(model.triangles.state.values[k][t]))
          << name << " triangle " << t;
  }
}

TEST(VtuLawState, AnElasticModelWritesNoStateFields) {
  io::test::ScratchDir dir;
  Model elastic = model_of("linear_elastic");
  Model plastic = model_of("mohr_coulomb");
  for (Model* m : {&elastic, &plastic}) {
    m->triangles.stress.assign(m->triangles.size(), Vec3::Zero());
    m->triangles.strain.assign(m->triangles.size(), Vec3::Zero());
  }
  EXPECT_TRUE(elastic.triangles.state.empty());
  io::write_triangles_vtu(dir / "e.vtu", elastic.nodes, elastic.triangles, elastic.materials);
  io::write_triangles_vtu(dir / "p.vtu", plastic.nodes, plastic.triangles, plastic.materials);
  const int n_elastic = read_back(dir / "e.vtu")->GetCellData()->GetNumberOfArrays();
  const int n_plastic = read_back(dir / "p.vtu")->GetCellData()->GetNumberOfArrays();
  EXPECT_EQ(n_plastic - n_elastic, static_cast<int>(law::mohr_coulomb::kStates));
  EXPECT_EQ(read_back(dir / "e.vtu")->GetCellData()->GetArray("plastic_strain_xx"), nullptr);
}
