// Where the moving water's wave is measured (docs/theory.md §12): beyond the slide's front, in
// the direction the wave runs from the slide's bank, so that the splash over the slide and
// the water it displaces as it sinks or lies on the bed are not taken for the impulse wave.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "app/cli_util.hpp"
#include "io/scenario.hpp"
#include "run/runner.hpp"
#include "run/slide_impact.hpp"
#include "run/water_watch.hpp"

using dsdem::run::crest_beyond;
using dsdem::run::wave_columns;

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

// Still water 2 m deep from a vertical wall (no water left of x = 1) to a bank that shoals to
// the right: the search takes the columns at least 0.5 m deep; the column against the wall is
// flagged (a crest there is the reflection), the last one before the bank's shallows is not.
// A pool between two vertical walls (its first and last columns the water's edges) flags both.
TEST(WaterWatch, TheWavesColumnsAgainstAWallAreFlagged) {
  constexpr double kDry = std::numeric_limits<double>::infinity();
  const std::vector<double> bottom{kDry, 0.0, 0.0, 0.0, 1.0, 1.7, 1.9};
  const auto c = wave_columns(bottom, 0.0, 1.0, 2.0, 0.5);
  ASSERT_EQ(c.x.size(), 4u);
  EXPECT_DOUBLE_EQ(c.x.front(), 1.5);
  EXPECT_DOUBLE_EQ(c.x.back(), 4.5);
  EXPECT_EQ(c.at_wall, (std::vector<bool>{true, false, false, false}));
  const auto pool = wave_columns(std::vector<double>{0.0, 0.0, 0.0}, 10.0, 0.5, 2.0, 0.5);
  EXPECT_EQ(pool.at_wall, (std::vector<bool>{true, false, true}));
}

// A splash of 0.3 m over the slide at x = 1 and a wave of 0.1 m at x = 3: beyond a front at
// x = 2 (the wave running toward +x) the crest is the wave; toward -x from a front at 2 it is
// the splash; with no front known, the highest of all.
TEST(WaterWatch, TheCrestIsSoughtBeyondTheSlidesFront) {
  const std::vector<double> xs{0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5};
  const std::vector<double> surface{1.0, 1.3, 1.05, 1.02, 1.04, 1.1, kNaN};
  const auto wave = crest_beyond(xs, surface, 1.0, 2.0, +1);
  EXPECT_NEAR(wave.amplitude, 0.1, 1e-12);
  EXPECT_EQ(wave.x, 3.0);
  const auto back = crest_beyond(xs, surface, 1.0, 2.0, -1);
  EXPECT_NEAR(back.amplitude, 0.3, 1e-12);
  EXPECT_EQ(back.x, 1.0);
  const auto all = crest_beyond(xs, surface, 1.0, kNaN, +1);
  EXPECT_NEAR(all.amplitude, 0.3, 1e-12);
  EXPECT_NEAR(crest_beyond(xs, surface, 1.0, 2.0, 0).amplitude, 0.3, 1e-12);
  // The column at the front itself is not beyond it; a trough is a negative amplitude.
  const auto at_front = crest_beyond(xs, std::vector<double>{kNaN, kNaN, kNaN, 1.5, 0.9, kNaN, kNaN}, 1.0, 2.0, +1);
  EXPECT_NEAR(at_front.amplitude, -0.1, 1e-12);
  EXPECT_EQ(at_front.x, 2.5);
  // Nothing wet beyond the front: no crest.
  const auto none = crest_beyond(xs, surface, 1.0, 3.5, +1);
  EXPECT_TRUE(std::isnan(none.amplitude));
  EXPECT_TRUE(std::isnan(none.x));
}

// The slide's front is the discrete zone's node furthest toward the open water: the block of
// the bank scenario (its bank on the left of the reservoir, the wave running toward +x).
TEST(WaterWatch, TheSlidesFrontIsItsFurthestNodeTowardTheOpenWater) {
  auto sc = dsdem::io::load_scenario(std::string(DSDEM_TEST_DATA_DIR) + "/reservoir/bank.yaml", {});
  const auto prepared = dsdem::run::prepare_run(sc, dsdem::test::fresh_dir("water_watch_front").string());
  ASSERT_TRUE(prepared.shore.has_value());
  EXPECT_EQ(dsdem::run::wave_direction(*prepared.shore), 1);
  const auto& m = prepared.model;
  double front = -INFINITY, bedrock_front = -INFINITY;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (auto i : m.triangles.conn[t])
      (m.triangles.zone[t] == dsdem::Zone::Discrete ? front : bedrock_front) =
          std::max(m.triangles.zone[t] == dsdem::Zone::Discrete ? front : bedrock_front, m.nodes.x(i).x());
  EXPECT_EQ(dsdem::run::slide_front(m, *prepared.shore), front);
  EXPECT_LT(front, bedrock_front);  // not the model's extent
}

// The still level the wave is measured from is the wet columns' mean surface (a dry column,
// NaN, is left out); with none wet there is none.
TEST(WaterWatch, TheStillLevelIsTheMeanOfTheWetColumns) {
  using dsdem::run::mean_surface;
  EXPECT_NEAR(mean_surface(std::vector<double>{0.99, kNaN, 1.0, 0.98}), 0.99, 1e-12);
  EXPECT_TRUE(std::isnan(mean_surface(std::vector<double>{kNaN, kNaN})));
  // A crest 0.1 above a settled level of 0.99 is 0.1 tall, not 0.09.
  const std::vector<double> xs{1.0, 2.0}, surface{1.09, 0.99};
  EXPECT_NEAR(crest_beyond(xs, surface, mean_surface(std::vector<double>{0.99, 0.99}), kNaN, 0).amplitude, 0.1, 1e-12);
}

// Water inside the rock is counted: a particle at each triangle's centroid, one on a face and
// one beyond the model: exactly the centroids count, whatever the cell size.
TEST(WaterWatch, ParticlesInsideTheSolidAreCounted) {
  auto sc = dsdem::io::load_scenario(std::string(DSDEM_TEST_DATA_DIR) + "/reservoir/bank.yaml", {});
  const auto prepared = dsdem::run::prepare_run(sc, dsdem::test::fresh_dir("water_watch_inside").string());
  const auto& m = prepared.model;
  dsdem::sph::FluidParticles f;
  f.mass = 1.0;
  for (const auto& t : m.triangles.conn) {
    const dsdem::Vec2 c = (m.nodes.x(t[0]) + m.nodes.x(t[1]) + m.nodes.x(t[2])) / 3.0;
    f.add(c.x(), c.y(), 1000.0);
  }
  const auto& t0 = m.triangles.conn[0];
  const dsdem::Vec2 on_face = 0.5 * (m.nodes.x(t0[0]) + m.nodes.x(t0[1]));
  f.add(on_face.x(), on_face.y(), 1000.0);
  f.add(1e4, 1e4, 1000.0);
  for (double cell : {0.05, 0.5, 5.0})
    EXPECT_EQ(dsdem::run::particles_in_solid(f, m, cell), static_cast<long>(m.triangles.size())) << "cell " << cell;
}
