// The 3D viscous-spring boundary: its force kernel, the three-component free field, the
// surface profile and the boundary nodes of a box.
#include <gtest/gtest.h>

#include <cmath>

#include "boundary/boundary_setup3d.hpp"
#include "common/materials.hpp"
#include "mesh/model_builder3d.hpp"
#include "mesh/structured.hpp"

using namespace dsdem;

TEST(ViscousSpring3D, ForceSplitsAlongTheNormalAndTheBoundarysPlane) {
  const boundary::ViscousSpringCoefficients c{10.0, 4.0, 3.0, 2.0};
  const Vec3 n = Vec3(1.0, 2.0, 2.0) / 3.0;
  const Vec3 u(0.3, -0.1, 0.2), v(-1.0, 0.5, 2.0);
  const Vec3 f = boundary::viscous_spring_force_3d(c, n, u, v);
  const Vec3 un = u.dot(n) * n, vn = v.dot(n) * n;
  const Vec3 expected = -c.kn * un - c.kt * (u - un) - c.cn * vn - c.ct * (v - vn);
  EXPECT_LT((f - expected).norm(), 1e-14);
  // A motion in the plane meets only the tangential spring and dashpot.
  const Vec3 t = Vec3(2.0, -1.0, 0.0).normalized();
  EXPECT_LT((boundary::viscous_spring_force_3d(c, n, t, Vec3::Zero()) + c.kt * t).norm(), 1e-14);
}

TEST(FreeField3D, ComponentsGoWhereTheirWavesMove) {
  seismic::Accelerogram rec = seismic::integrate(0.01, std::vector<double>(200, 1.0), {false, 3});
  const boundary::IncidentMotion motion{&rec, 0.5};
  const boundary::ElasticMedium medium{2000.0, 4e8, 4e8};
  const double z = 30.0, H = 100.0, t = 0.9;
  const auto f2sv = boundary::free_field_column(boundary::IncidentWave::SV, motion, medium, z, H, t);
  const auto f2p = boundary::free_field_column(boundary::IncidentWave::P, motion, medium, z, H, t);
  const auto sx = boundary::free_field_column_3d(boundary::IncidentWave::SV, 0, motion, medium, z, H, t);
  const auto sy = boundary::free_field_column_3d(boundary::IncidentWave::SV, 1, motion, medium, z, H, t);
  const auto p = boundary::free_field_column_3d(boundary::IncidentWave::P, 2, motion, medium, z, H, t);
  EXPECT_EQ(sx.u, Vec3(f2sv.u.x(), 0, 0));
  EXPECT_EQ(sy.v, Vec3(0, f2sv.v.x(), 0));
  EXPECT_EQ(sx.stress[4], f2sv.stress[2]);  // sigma_xz
  EXPECT_EQ(sy.stress[3], f2sv.stress[2]);  // sigma_yz
  EXPECT_EQ(p.u, Vec3(0, 0, f2p.u.y()));
  EXPECT_EQ(p.stress[2], f2p.stress[1]);
  EXPECT_EQ(p.stress[0], f2p.stress[0]);
  EXPECT_EQ(p.stress[1], f2p.stress[0]);
  EXPECT_THROW(boundary::free_field_column_3d(boundary::IncidentWave::SV, 2, motion, medium, z, H, t),
               std::invalid_argument);
}

TEST(SurfaceProfile3, TopOfAStepAlongVerticalLines) {
  // Two boxes side by side: 2 m high on x in [0, 1], 3 m high on x in [1, 2].
  RawMesh3 low = mesh::box_mesh(2, 2, 2, 1.0, 1.0, 2.0);
  const RawMesh3 high = mesh::box_mesh(2, 2, 3, 1.0, 1.0, 3.0, Vec3(1.0, 0.0, 0.0));
  std::vector<std::array<Index, 4>> tets = low.tetrahedra;
  const Index offset = static_cast<Index>(low.nodes.size());
  std::vector<Vec3> X = low.nodes;
  X.insert(X.end(), high.nodes.begin(), high.nodes.end());
  for (auto t : high.tetrahedra) {
    for (auto& v : t) v += offset;
    tets.push_back(t);
  }
  const boundary::SurfaceProfile3 profile(X, tets);
  EXPECT_NEAR(profile.top(0.3, 0.4), 2.0, 1e-12);
  EXPECT_NEAR(profile.top(1.7, 0.2), 3.0, 1e-12);
  EXPECT_NEAR(profile.top(0.0, 0.0), 2.0, 1e-12);  // a corner of the model
  EXPECT_EQ(profile.top(5.0, 0.5), -std::numeric_limits<double>::infinity());
}

TEST(BoundarySetup3D, BoxFacesGetAreasNormalsAndColumns) {
  Model3 model = mesh::build_model_3d(mesh::box_mesh(2, 3, 4, 2.0, 3.0, 4.0), test::elastic_material("rock", 1e9, 0.25, 2000));
  const auto nodes = boundary::build_viscous_boundary_3d(
      model, {{"zmin", 100.0, std::nullopt, true}, {"xmax", std::nullopt, Vec3(0.0, 1.5, 2.0), false}});
  double base_area = 0.0, side_area = 0.0;
  for (const auto& bn : nodes) {
    const Vec3 X = model.nodes.X[bn.node];
    EXPECT_NEAR(bn.H, 4.0, 1e-12);
    EXPECT_NEAR(bn.height, X.z(), 1e-12);
    const bool base = std::abs(X.z()) < 1e-12, side = std::abs(X.x() - 2.0) < 1e-12;
    if (base && !side) {
      EXPECT_LT((bn.normal - Vec3(0, 0, -1)).norm(), 1e-12);
      base_area += bn.area;
      EXPECT_TRUE(bn.free_field);
    } else if (side && !base) {
      EXPECT_LT((bn.normal - Vec3(1, 0, 0)).norm(), 1e-12);
      side_area += bn.area;
      EXPECT_FALSE(bn.free_field);
    } else {  // the shared edge: both faces' areas, the normal between theirs
      EXPECT_GT(bn.normal.x(), 0.0);
      EXPECT_LT(bn.normal.z(), 0.0);
      EXPECT_NEAR(bn.normal.y(), 0.0, 1e-15);
      EXPECT_NEAR(bn.normal.norm(), 1.0, 1e-12);
    }
    EXPECT_GT(bn.coef.kn, bn.coef.kt);
  }
  // Tributary areas sum to the faces' (edge nodes counted apart above).
  double total = 0.0;
  for (const auto& bn : nodes) total += bn.area;
  EXPECT_NEAR(total, 2.0 * 3.0 + 3.0 * 4.0, 1e-12);
  EXPECT_GT(base_area, 0.0);
  EXPECT_GT(side_area, 0.0);
  EXPECT_THROW(boundary::build_viscous_boundary_3d(model, {{"domain", 1.0, std::nullopt, true}}), std::invalid_argument);
}
