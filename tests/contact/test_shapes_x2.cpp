#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "contact/shapes_x2.hpp"

using namespace dsdem;
using namespace dsdem::contact;

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

void expect_same(const Spheropolygon& got, const CoreEdgeScales& got_s, const std::array<Vec2, 3>& p, double r,
                 bool with_scales, int lane) {
  const Spheropolygon want = make_spheropolygon(p[0], p[1], p[2], r);
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(same_bits(got.core[k].x(), want.core[k].x())) << "lane " << lane << " core " << k;
    EXPECT_TRUE(same_bits(got.core[k].y(), want.core[k].y())) << "lane " << lane << " core " << k;
  }
  EXPECT_TRUE(same_bits(got.r, want.r));
  if (!with_scales) return;
  const CoreEdgeScales ws = core_edge_scales(want.core);
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(same_bits(got_s.inv_len2[k], ws.inv_len2[k])) << "lane " << lane << " edge " << k;
    EXPECT_TRUE(same_bits(got_s.n_scale[k], ws.n_scale[k])) << "lane " << lane << " edge " << k;
  }
  EXPECT_EQ(got_s.proper, ws.proper) << "lane " << lane;
}

}  // namespace

#if defined(DSDEM_SHAPES_X2)
TEST(ShapesX2, EachLaneEqualsTheScalarShapeAndEdgeScalesBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-500.0, 1500.0), offset(-4.0, 4.0), unit(0.0, 1.0);
  auto random_triangle = [&](int kind) {
    const Vec2 base(coord(rng), coord(rng));
    std::array<Vec2, 3> p{base, base + Vec2(offset(rng), offset(rng)), base + Vec2(offset(rng), offset(rng))};
    if (kind == 1) p[2] = p[1];                          // a zero-length edge
    if (kind == 2) p[1] = p[2] = p[0];                   // collapsed to a point: no perimeter
    if (kind == 3) p[2] = p[0] + 0.5 * (p[1] - p[0]);    // three points on a line
    if (kind == 4) std::swap(p[1], p[2]);                // the other orientation
    return p;
  };
  for (int trial = 0; trial < 20000; ++trial) {
    const int kind_a = trial % 7 < 5 ? trial % 5 : 0, kind_b = (trial / 7) % 5;
    const std::array<Vec2, 3> pa = random_triangle(kind_a), pb = random_triangle(kind_b);
    // Rounding radii from 0 to above the inradius (the core then collapses to the incentre).
    const double ra = trial % 11 == 0 ? 10.0 : 0.05 * unit(rng), rb = trial % 13 == 0 ? 0.0 : 0.05 * unit(rng);
    const bool with_scales = trial % 3 != 0;
    Spheropolygon a, b;
    CoreEdgeScales sa, sb;
    make_shapes_x2(pa, pb, ra, rb, a, b, with_scales ? &sa : nullptr, &sb);
    expect_same(a, sa, pa, ra, with_scales, 0);
    expect_same(b, sb, pb, rb, with_scales, 1);
    if (HasFailure()) FAIL() << "trial " << trial;
  }
}
#endif
