// Unit tests of resampling at a fixed step, against independent (analytic) expectations.
#include <gtest/gtest.h>

#include "tests/path_planner/step_shapes.hpp"

TEST(PathPlannerResample, FixedStepAndCornersKept) {
  const Ring sq = rect(0, 0, 0.1, 0.05);
  const double step = 0.003;
  const SampledRing s = resample_ring(sq, step, deg(10));
  // Every corner is a waypoint; each side of length L has ceil(L/step) equal steps.
  for (const Vec2& c : sq) EXPECT_LT(vertex_dist(c, s.points), 1e-12);
  const std::size_t expected = 2 * std::size_t(std::ceil(0.1 / step)) + 2 * std::size_t(std::ceil(0.05 / step));
  EXPECT_EQ(s.points.size(), expected);
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    const double d = (s.points[(i + 1) % s.points.size()] - s.points[i]).norm();
    EXPECT_LE(d, step + 1e-12);
    EXPECT_GT(d, 0.9 * step);  // 0.1 / 34 and 0.05 / 17 are both close to the step
    EXPECT_LT(ring_dist(s.points[i], sq), 1e-12);
  }
  int corners = 0;
  for (auto c : s.corner) corners += c;
  EXPECT_EQ(corners, 4);
}

TEST(PathPlannerResample, CircleSpacingAlongTheArc) {
  const Ring c = circle({0, 0}, 0.05, 3000);
  const SampledRing s = resample_ring(c, 0.002, deg(10));
  const double L = ring_length(c);
  EXPECT_EQ(s.points.size(), std::size_t(std::ceil(L / 0.002 - 1e-9)));
  for (std::size_t i = 0; i < s.points.size(); ++i)
    EXPECT_NEAR((s.points[(i + 1) % s.points.size()] - s.points[i]).norm(), L / double(s.points.size()), 1e-6);
}
