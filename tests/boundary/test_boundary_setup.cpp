// Free-field column heights of the viscous-spring boundary nodes (docs/theory.md §5).
#include <gtest/gtest.h>

#include <cmath>

#include "boundary/boundary_setup.hpp"
#include "common/materials.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"

using namespace dsdem;

TEST(SurfaceProfile, TopOfTheOutlineAlongVerticalLines) {
  // A trapezoid (0,0) (10,0) (10,5) (0,2) in two triangles, and a detached triangle
  // further right with a vertical left side.
  const std::vector<Vec2> X{{0, 0}, {10, 0}, {10, 5}, {0, 2}, {20, 0}, {30, 0}, {20, 8}};
  const std::vector<std::array<Index, 3>> conn{{0, 1, 2}, {0, 2, 3}, {4, 5, 6}};
  const boundary::SurfaceProfile s(X, conn);
  EXPECT_DOUBLE_EQ(s.top(0.0), 2.0);
  EXPECT_DOUBLE_EQ(s.top(5.0), 3.5);
  EXPECT_DOUBLE_EQ(s.top(10.0), 5.0);
  EXPECT_DOUBLE_EQ(s.top(20.0), 8.0);  // the vertical edge: its upper end
  EXPECT_DOUBLE_EQ(s.top(25.0), 4.0);
  EXPECT_TRUE(std::isinf(s.top(15.0)) && s.top(15.0) < 0.0);  // the gap between the two parts
  EXPECT_TRUE(std::isinf(s.top(-1.0)) && s.top(-1.0) < 0.0);
}

// The column height used to be the highest node within half a mean element of x. Under a
// sloping surface whose nodes do not stand above the base nodes (a graded mesh) that read
// the wrong height: 10 m too high here, up to 58 m on Dr2's default mesh and 225 m at h = 12 m.
TEST(BoundarySetup, FreeFieldColumnReachesTheSurfaceDirectlyAbove) {
  const double W = 400.0, H = 100.0;
  Model model = mesh::build_model(mesh::rectangle_mesh(4, 1, W, H, mesh::Diagonal::Alternate),
                                  test::elastic_material("rock", 1e9, 0.25, 2000));
  // Top nodes at x = 100, 200, 300 moved 40 m right; the top rises by 1 in 4.
  for (auto& X : model.nodes.X)
    if (X.y() == H) {
      if (X.x() > 0.0 && X.x() < W) X.x() += 40.0;
      X.y() = H + 0.25 * X.x();
    }
  io::BoundarySpec bottom;
  bottom.group = "bottom";
  bottom.type = io::BoundaryType::ViscousSpring;
  bottom.R = 1e4;
  const auto nodes = boundary::build_viscous_boundary(model, {bottom});
  int checked = 0;
  for (const auto& bn : nodes) {
    const double x = model.nodes.X[bn.node].x();
    // The surface through (0, 100) (140, 135) (240, 160) (340, 185) (400, 200).
    const double xs[] = {0, 140, 240, 340, 400}, ys[] = {100, 135, 160, 185, 200};
    double expected = 0.0;
    for (int k = 0; k + 1 < 5; ++k)
      if (x >= xs[k] && x <= xs[k + 1]) expected = ys[k] + (x - xs[k]) * (ys[k + 1] - ys[k]) / (xs[k + 1] - xs[k]);
    EXPECT_NEAR(bn.H, expected, 1e-9) << "base node at x = " << x;
    EXPECT_DOUBLE_EQ(bn.height, 0.0);
    ++checked;
  }
  EXPECT_EQ(checked, 5);
}
