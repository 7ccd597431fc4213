#include "io/vtu_writer.hpp"

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/io_test_util.hpp"

namespace dsdem::io {
namespace {

using test::bits;
using test::ScratchDir;

// Two triangles on the unit square, displaced, moving and stressed, with values that
// are not short decimals so that any precision loss shows.
struct TwoTriangles {
  Nodes nodes;
  Triangles tris;
  std::vector<Material> materials;

  TwoTriangles() {
    nodes.resize(4);
    nodes.X = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
    for (int i = 0; i < 4; ++i) {
      nodes.u[i] = Vec2(0.1 * i + 1.0 / 3.0, -0.02 * i * i + std::sqrt(2.0) * 1e-3);
      nodes.v[i] = Vec2(std::exp(-i), 3.0 - i / 7.0);
      nodes.a[i] = Vec2(-9.80665 * i, 1e-7 * i);
    }
    tris.resize(2);
    tris.conn = {{0, 1, 2}, {0, 2, 3}};
    tris.group = {3, 5};
    tris.material = {1, 0};
    tris.zone = {Zone::Discrete, Zone::ContactBedrock};
    tris.stress = {Vec3(1.5e6 / 3.0, -2.25e6, 3.3e5), Vec3(-1e5, -4e5 / 7.0, 0.0)};
    tris.strain = {Vec3(1e-4 / 3.0, -2e-4, 5e-5), Vec3(0.0, 1e-6, -3e-6)};
    Material rock;
    rock.name = "rock";
    rock.nu = 0.25;
    Material plate = rock;
    plate.name = "plate";
    plate.plane_stress = true;
    materials = {rock, plate};
  }
};

vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const std::filesystem::path& path) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_EQ(reader->GetErrorCode(), 0u) << path;
  vtkSmartPointer<vtkUnstructuredGrid> grid = reader->GetOutput();
  return grid;
}

vtkDataArray* array(vtkDataSetAttributes* data, const char* name) {
  vtkDataArray* a = data->GetArray(name);
  EXPECT_NE(a, nullptr) << "no array " << name;
  return a;
}

// Every encoding must reproduce the doubles exactly; VTK 9.1 writes ASCII numbers at
// round-trip precision too, but as text it drops the sign of a negative zero.
void expect_same(double read, double written, VtuEncoding encoding) {
  if (encoding == VtuEncoding::Ascii)
    EXPECT_EQ(read, written);
  else
    EXPECT_EQ(bits(read), bits(written)) << read << " vs " << written;
}

class VtuEncodingTest : public ::testing::TestWithParam<VtuEncoding> {};

TEST_P(VtuEncodingTest, TrianglesReadBackWithVtk) {
  const VtuEncoding enc = GetParam();
  ScratchDir dir;
  TwoTriangles m;
  const std::vector<double> damage = {0.25, 1.0 / 3.0};
  const std::vector<Vec2> body_force = {Vec2(1, 2), Vec2(3, 4), Vec2(5, 6), Vec2(7, 8)};
  const auto path = dir / "fields.vtu";
  write_triangles_vtu(path, m.nodes, m.tris, m.materials,
                      {vector_field("body_force", "N_per_m3", body_force)},
                      {scalar_field("damage", "", damage)}, {.encoding = enc, .time_s = 1.25});

  auto grid = read_vtu(path);
  ASSERT_EQ(grid->GetNumberOfPoints(), 4);
  ASSERT_EQ(grid->GetNumberOfCells(), 2);
  for (int e = 0; e < 2; ++e) {
    EXPECT_EQ(grid->GetCellType(e), VTK_TRIANGLE);
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    grid->GetCellPoints(e, n, ids);
    ASSERT_EQ(n, 3);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(ids[k], m.tris.conn[e][k]);
  }

  // Points are the current positions X + u, z = 0.
  auto* disp = array(grid->GetPointData(), "displacement_m");
  auto* vel = array(grid->GetPointData(), "velocity_m_per_s");
  auto* acc = array(grid->GetPointData(), "acceleration_m_per_s2");
  auto* force = array(grid->GetPointData(), "body_force_N_per_m3");
  ASSERT_TRUE(disp && vel && acc && force);
  EXPECT_EQ(disp->GetNumberOfComponents(), 3);
  for (int i = 0; i < 4; ++i) {
    double p[3];
    grid->GetPoint(i, p);
    const Vec2 x = m.nodes.X[i] + m.nodes.u[i];
    expect_same(p[0], x.x(), enc);
    expect_same(p[1], x.y(), enc);
    EXPECT_EQ(p[2], 0.0);
    for (int c = 0; c < 2; ++c) {
      expect_same(disp->GetComponent(i, c), m.nodes.u[i][c], enc);
      expect_same(vel->GetComponent(i, c), m.nodes.v[i][c], enc);
      expect_same(acc->GetComponent(i, c), m.nodes.a[i][c], enc);
      expect_same(force->GetComponent(i, c), body_force[i][c], enc);
    }
    EXPECT_EQ(disp->GetComponent(i, 2), 0.0);
  }

  auto* stress = array(grid->GetCellData(), "stress_Pa");
  auto* strain = array(grid->GetCellData(), "strain");
  auto* vm = array(grid->GetCellData(), "von_mises_stress_Pa");
  auto* s1 = array(grid->GetCellData(), "max_principal_stress_Pa");
  auto* s2 = array(grid->GetCellData(), "min_principal_stress_Pa");
  auto* group = array(grid->GetCellData(), "group_id");
  auto* material = array(grid->GetCellData(), "material_id");
  auto* zone = array(grid->GetCellData(), "zone");
  auto* dmg = array(grid->GetCellData(), "damage");
  ASSERT_TRUE(stress && strain && vm && s1 && s2 && group && material && zone && dmg);
  ASSERT_EQ(stress->GetNumberOfComponents(), 3);
  EXPECT_STREQ(stress->GetComponentName(2), "xy");
  EXPECT_STREQ(strain->GetComponentName(2), "gamma_xy");
  EXPECT_TRUE(vtkIntArray::SafeDownCast(group) != nullptr) << "ids are written as Int32";
  for (int e = 0; e < 2; ++e) {
    const Vec3& s = m.tris.stress[e];
    for (int c = 0; c < 3; ++c) {
      expect_same(stress->GetComponent(e, c), s[c], enc);
      expect_same(strain->GetComponent(e, c), m.tris.strain[e][c], enc);
    }
    // Principal values and von Mises by hand (triangle 0: plane stress, 1: plane strain).
    const double c = 0.5 * (s[0] + s[1]), r = std::hypot(0.5 * (s[0] - s[1]), s[2]);
    const double szz = e == 0 ? 0.0 : 0.25 * (s[0] + s[1]);
    const double vm_ref = std::sqrt(0.5 * ((s[0] - s[1]) * (s[0] - s[1]) +
                                           (s[1] - szz) * (s[1] - szz) +
                                           (szz - s[0]) * (szz - s[0])) +
                                    3 * s[2] * s[2]);
    EXPECT_NEAR(s1->GetComponent(e, 0), c + r, 1e-9 * std::abs(c + r));
    EXPECT_NEAR(s2->GetComponent(e, 0), c - r, 1e-9 * std::abs(c - r));
    EXPECT_NEAR(vm->GetComponent(e, 0), vm_ref, 1e-9 * vm_ref);
    EXPECT_EQ(group->GetComponent(e, 0), m.tris.group[e]);
    EXPECT_EQ(material->GetComponent(e, 0), m.tris.material[e]);
    EXPECT_EQ(zone->GetComponent(e, 0), static_cast<int>(m.tris.zone[e]));
    expect_same(dmg->GetComponent(e, 0), damage[e], enc);
  }

  vtkDataArray* time = grid->GetFieldData()->GetArray("TimeValue");
  ASSERT_NE(time, nullptr);
  EXPECT_EQ(time->GetComponent(0, 0), 1.25);
}

TEST_P(VtuEncodingTest, CrackSegmentsReadBackWithVtk) {
  const VtuEncoding enc = GetParam();
  ScratchDir dir;
  const std::vector<std::array<Vec2, 2>> segs = {{Vec2(0, 0), Vec2(1.0 / 3.0, 0.5)},
                                                 {Vec2(1.0 / 3.0, 0.5), Vec2(2, 0.1)},
                                                 {Vec2(-1, -1), Vec2(-1, std::sqrt(3.0))}};
  const std::vector<std::int32_t> state = {0, 1, 2};
  const std::vector<double> damage = {0.0, 0.5, 1.0};
  const std::vector<double> opening = {1e-6 / 3.0, 2e-4, 0.01};
  const std::vector<double> slip = {-1e-5, 0.0, 3e-3};
  const auto path = dir / "cracks.vtu";
  write_segments_vtu(path, segs,
                     {scalar_field("state", "", state), scalar_field("damage", "", damage),
                      scalar_field("opening", "m", opening), scalar_field("slip", "m", slip)},
                     {.encoding = enc});

  auto grid = read_vtu(path);
  ASSERT_EQ(grid->GetNumberOfCells(), 3);
  ASSERT_EQ(grid->GetNumberOfPoints(), 6);
  auto* st = array(grid->GetCellData(), "state");
  auto* dm = array(grid->GetCellData(), "damage");
  auto* op = array(grid->GetCellData(), "opening_m");
  auto* sl = array(grid->GetCellData(), "slip_m");
  ASSERT_TRUE(st && dm && op && sl);
  for (int s = 0; s < 3; ++s) {
    EXPECT_EQ(grid->GetCellType(s), VTK_LINE);
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    grid->GetCellPoints(s, n, ids);
    ASSERT_EQ(n, 2);
    for (int k = 0; k < 2; ++k) {
      double p[3];
      grid->GetPoint(ids[k], p);
      expect_same(p[0], segs[s][k].x(), enc);
      expect_same(p[1], segs[s][k].y(), enc);
    }
    EXPECT_EQ(st->GetComponent(s, 0), state[s]);
    expect_same(dm->GetComponent(s, 0), damage[s], enc);
    expect_same(op->GetComponent(s, 0), opening[s], enc);
    expect_same(sl->GetComponent(s, 0), slip[s], enc);
  }
}

TEST_P(VtuEncodingTest, ContactPointsReadBackWithVtk) {
  const VtuEncoding enc = GetParam();
  ScratchDir dir;
  const std::vector<Vec2> pts = {Vec2(0.5, 1.0 / 3.0), Vec2(2, 3), Vec2(-4.25, 1e-3)};
  const std::vector<Vec2> force = {Vec2(1e5 / 3.0, -2e4), Vec2(0, 0), Vec2(-7.5, 1e9)};
  const std::vector<double> overlap = {1e-4, 0.0, 2.5e-6};
  const auto path = dir / "contacts.vtu";
  write_points_vtu(path, pts,
                   {vector_field("contact_force", "N_per_m", force),
                    scalar_field("overlap", "m", overlap)},
                   {.encoding = enc});

  auto grid = read_vtu(path);
  ASSERT_EQ(grid->GetNumberOfPoints(), 3);
  ASSERT_EQ(grid->GetNumberOfCells(), 3);
  auto* f = array(grid->GetPointData(), "contact_force_N_per_m");
  auto* ov = array(grid->GetPointData(), "overlap_m");
  ASSERT_TRUE(f && ov);
  ASSERT_EQ(f->GetNumberOfComponents(), 3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(grid->GetCellType(i), VTK_VERTEX);
    double p[3];
    grid->GetPoint(i, p);
    expect_same(p[0], pts[i].x(), enc);
    expect_same(p[1], pts[i].y(), enc);
    expect_same(f->GetComponent(i, 0), force[i].x(), enc);
    expect_same(f->GetComponent(i, 1), force[i].y(), enc);
    EXPECT_EQ(f->GetComponent(i, 2), 0.0);
    expect_same(ov->GetComponent(i, 0), overlap[i], enc);
  }
}

INSTANTIATE_TEST_SUITE_P(Encodings, VtuEncodingTest,
                         ::testing::Values(VtuEncoding::AppendedRaw, VtuEncoding::InlineBase64,
                                           VtuEncoding::Ascii),
                         [](const auto& info) {
                           switch (info.param) {
                             case VtuEncoding::AppendedRaw: return std::string("AppendedRaw");
                             case VtuEncoding::InlineBase64: return std::string("InlineBase64");
                             case VtuEncoding::Ascii: return std::string("Ascii");
                           }
                           return std::string("Unknown");
                         });

TEST(VtuWriter, EmptySeriesAreValidFiles) {
  ScratchDir dir;
  write_segments_vtu(dir / "cracks.vtu", {}, {scalar_field("damage", "", std::span<const double>{})});
  write_points_vtu(dir / "contacts.vtu", {});
  EXPECT_EQ(read_vtu(dir / "cracks.vtu")->GetNumberOfCells(), 0);
  EXPECT_EQ(read_vtu(dir / "contacts.vtu")->GetNumberOfPoints(), 0);
}

TEST(VtuWriter, RejectsWrongFieldSizeAndWritesNothing) {
  ScratchDir dir;
  TwoTriangles m;
  const std::vector<double> three = {1, 2, 3};
  EXPECT_THROW(write_triangles_vtu(dir / "a.vtu", m.nodes, m.tris, m.materials, {},
                                   {scalar_field("damage", "", three)}),
               std::invalid_argument);
  EXPECT_THROW(write_triangles_vtu(dir / "a.vtu", m.nodes, m.tris, m.materials,
                                   {scalar_field("damage", "", three)}),
               std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "a.vtu"));
}

TEST(VtuWriter, RejectsNameClashWithBuiltInField) {
  ScratchDir dir;
  TwoTriangles m;
  const std::vector<double> two = {1, 2};
  EXPECT_THROW(write_triangles_vtu(dir / "a.vtu", m.nodes, m.tris, m.materials, {},
                                   {scalar_field("zone", "", two)}),
               std::invalid_argument);
}

TEST(VtuWriter, RejectsBadConnectivityOrMaterial) {
  ScratchDir dir;
  TwoTriangles m;
  m.tris.conn[1][2] = 4;
  EXPECT_THROW(write_triangles_vtu(dir / "a.vtu", m.nodes, m.tris, m.materials),
               std::invalid_argument);
  TwoTriangles m2;
  m2.tris.material[0] = 2;
  EXPECT_THROW(write_triangles_vtu(dir / "a.vtu", m2.nodes, m2.tris, m2.materials),
               std::invalid_argument);
}

TEST(VtuWriter, UnwritableDirectoryThrowsWithPath) {
  ScratchDir dir;
  TwoTriangles m;
  const auto path = dir / "missing" / "a.vtu";
  try {
    write_triangles_vtu(path, m.nodes, m.tris, m.materials);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(e.what(), path.string());
  }
}

// A third-party reader (meshio, as used by Python post-processing) agrees bit for bit.
TEST(VtuWriter, MeshioReadsTheDefaultEncoding) {
  if (!test::python_has("meshio, numpy")) GTEST_SKIP() << "no meshio in the system Python";
  ScratchDir dir;
  TwoTriangles m;
  const auto path = dir / "fields.vtu";
  write_triangles_vtu(path, m.nodes, m.tris, m.materials);
  const auto dump = dir / "dump.txt";
  const std::string script =
      "import meshio, sys\n"
      "m = meshio.read(sys.argv[1])\n"
      "vals = list(m.points[:, :2].ravel()) + list(m.point_data['displacement_m'][:, :2].ravel())"
      " + list(m.cell_data['stress_Pa'][0].ravel())\n"
      "assert m.cells[0].type == 'triangle' and m.cells[0].data.tolist() == [[0,1,2],[0,2,3]]\n"
      "open(sys.argv[2], 'w').write('\\n'.join(repr(float(v)) for v in vals))\n";
  {
    std::ofstream(dir / "check.py") << script;
  }
  const std::string cmd = std::string(test::kSystemPython) + " " + (dir / "check.py").string() +
                          " " + path.string() + " " + dump.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;

  std::vector<double> expected;
  for (int i = 0; i < 4; ++i) {
    const Vec2 x = m.nodes.X[i] + m.nodes.u[i];
    expected.insert(expected.end(), {x.x(), x.y()});
  }
  for (int i = 0; i < 4; ++i) expected.insert(expected.end(), {m.nodes.u[i].x(), m.nodes.u[i].y()});
  for (int e = 0; e < 2; ++e)
    for (int c = 0; c < 3; ++c) expected.push_back(m.tris.stress[e][c]);
  const auto lines = test::split(test::read_text(dump), '\n');
  ASSERT_EQ(lines.size(), expected.size());
  for (std::size_t k = 0; k < lines.size(); ++k)
    EXPECT_EQ(bits(std::strtod(lines[k].c_str(), nullptr)), bits(expected[k])) << "value " << k;
}

// The default encoding puts each array inline (base64), with no appended block: meshio's
// reader of an appended block renames each array's offset as it decodes and then looks the
// next array up by its raw offset, which an earlier array's new offset can equal. A water
// frame of a Dr2 run (899 particles: the pressure's new offset 28 804 was the points' raw
// offset) came back with the pressure as its points; ParaView read it.
TEST(VtuWriter, DefaultEncodingHasNoAppendedBlock) {
  ScratchDir dir;
  const std::vector<Vec2> x{Vec2(0.0, 0.0), Vec2(1.0, 0.5)};
  const std::vector<double> p{1.0, 2.0};
  write_points_vtu(dir / "water.vtu", x, {scalar_field("pressure", "Pa", p)});
  const std::string text = test::read_text(dir / "water.vtu");
  EXPECT_EQ(text.find("AppendedData"), std::string::npos);
  EXPECT_EQ(text.find("format=\"appended\""), std::string::npos);
  EXPECT_NE(text.find("format=\"binary\""), std::string::npos);
}

}  // namespace
}  // namespace dsdem::io
