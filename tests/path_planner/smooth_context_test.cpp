// The smoothing context (path_planner/smooth/context.cpp): which rings are fitted, the unit, the edge
// compensation switch, and the noise it measures on a ring of known noise.
#include <gtest/gtest.h>

#include "tests/path_planner/stage_rings.hpp"

using namespace hg::path_planner;
using namespace hg::path_planner::smooth;
using namespace hg::path_planner::stage_test;

TEST(PathPlannerSmoothContext, RingsLeftAsTheyAre) {
  const Ring square = {{0, 0}, {0.2, 0}, {0.2, 0.2}, {0, 0.2}};
  EXPECT_FALSE(make_context(square, 0.001, SmoothOptions{})) << "fewer than 8 vertices";
  const Sampled sparse = sample_polygon(square, 0.02);  // 40 vertices, 20 mm apart
  EXPECT_FALSE(make_context(sparse.ring, 0, SmoothOptions{})) << "a drawn polygon of unknown pitch";
  EXPECT_TRUE(make_context(sparse.ring, 0.001, SmoothOptions{})) << "the pitch given: fitted";
  EXPECT_FALSE(make_context(sample_polygon(square, 0.001).ring, -1, SmoothOptions{})) << "a negative pitch";
}

TEST(PathPlannerSmoothContext, DenseRingOfUnknownPitchIsFittedWithoutCompensation) {
  const Sampled s = sample_polygon({{0, 0}, {0.2, 0}, {0.2, 0.2}, {0, 0.2}}, 0.0005);
  const auto c = make_context(with_noise(s.ring, 0.0001, 3), 0, SmoothOptions{});
  ASSERT_TRUE(c);
  EXPECT_EQ(c->bias_scale, 0.0);
  EXPECT_GT(c->unit, 0.0005) << "noise spreads the vertices: the unit is their spacing, beyond the sampling";
  EXPECT_EQ(c->unit, c->spacing);
  const auto given = make_context(s.ring, 0.001, SmoothOptions{});
  ASSERT_TRUE(given);
  EXPECT_EQ(given->bias_scale, 1.0);
  EXPECT_EQ(given->unit, 0.001) << "the pitch, larger than the spacing";
}

// The ring's own noise (SmoothOptions::noise 0): a window mean's sigma, so the tolerance exceeds 4 of them
// and the corner scale 60 of them.
TEST(PathPlannerSmoothContext, NoiseOfTheRingSetsTolerancesAndScale) {
  const Sampled s = sample_polygon({{0, 0}, {0.4, 0}, {0.4, 0.4}, {0, 0.4}}, 0.0002);
  const double sigma = 0.0004, window_sigma = sigma / std::sqrt(8.0);
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const auto c = make_context(with_noise(s.ring, sigma, seed), 0.0002, exact_options());
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->sigma, window_sigma, 0.25 * window_sigma) << "seed " << seed;
    EXPECT_GE(c->tolerance, 4 * c->sigma);
    EXPECT_GE(c->scale, 60 * c->sigma);
    EXPECT_GE(c->scale, 8 * c->unit);
  }
}
