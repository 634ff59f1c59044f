// Unit tests of the offset by the tool radius, against independent (analytic) expectations.
#include <gtest/gtest.h>

#include "tests/path_planner/step_shapes.hpp"

TEST(PathPlannerOffset, SquareGrowsByTheRadius) {
  const double r = 0.01;
  const Ring sq = rect(0, 0, 0.1, 0.1);
  const auto off = offset_ring(sq, false, r, 1e-5);
  ASSERT_EQ(off.size(), 1u);
  EXPECT_GT(signed_area(off[0]), 0);  // canonical: counter-clockwise
  for (const Vec2& q : off[0]) EXPECT_NEAR(ring_dist(q, sq), r, 2e-5);
  // Straight parts lie exactly on the lines x = -r, x = 0.1 + r, ...
  int on_lines = 0;
  for (const Vec2& q : off[0])
    on_lines += std::abs(q.x() + r) < 2e-6 || std::abs(q.x() - 0.1 - r) < 2e-6 || std::abs(q.y() + r) < 2e-6 ||
                std::abs(q.y() - 0.1 - r) < 2e-6;
  EXPECT_GE(on_lines, 8);
  // Area of the rounded square: s^2 + 4 s r + pi r^2.
  EXPECT_NEAR(signed_area(off[0]), 0.01 + 4 * 0.1 * r + kPi * r * r, 2e-6);
}

TEST(PathPlannerOffset, HoleShrinksByTheRadiusAndStaysClockwise) {
  const double r = 0.01;
  Ring hole = rect(0, 0, 0.06, 0.04);
  std::reverse(hole.begin(), hole.end());  // canonical hole: clockwise
  const auto off = offset_ring(hole, true, r, 1e-5);
  ASSERT_EQ(off.size(), 1u);
  EXPECT_LT(signed_area(off[0]), 0);
  EXPECT_NEAR(std::abs(signed_area(off[0])), (0.06 - 2 * r) * (0.04 - 2 * r), 1e-7);
  for (const Vec2& q : off[0]) EXPECT_NEAR(ring_dist(q, hole), r, 2e-6);
}

TEST(PathPlannerOffset, HoleTooSmallForTheToolGivesNothing) {
  EXPECT_TRUE(offset_ring(circle({0, 0}, 0.009, 400, true), true, 0.01, 1e-5).empty());
  EXPECT_EQ(offset_ring(circle({0, 0}, 0.011, 400, true), true, 0.01, 1e-5).size(), 1u);
}

TEST(PathPlannerOffset, NoMicroSegmentsFromIntegerRounding) {
  // Jittered dense rings (what smoothing hands over from noisy pieces): Clipper's whole-micrometre vertices
  // would leave neighbours 1-2 um apart, stepping back against the travel. None closer than 3 um remain,
  // and the offset stays at the tool radius.
  std::mt19937 rng(3);
  std::normal_distribution<double> jitter(0, 5e-6);
  int rings = 0;
  for (int trial = 0; trial < 20; ++trial) {
    Ring ring = circle({0.1, 0.05}, 0.03 + 0.001 * trial, 3000 + 100 * trial, trial % 2 == 1);
    for (Vec2& p : ring) p += Vec2(jitter(rng), jitter(rng));
    for (const Ring& r : offset_ring(ring, trial % 2 == 1, 0.01, 1e-5)) {
      ++rings;
      for (std::size_t i = 0; i < r.size(); ++i) {
        EXPECT_GT((r[(i + 1) % r.size()] - r[i]).norm(), 3e-6) << "trial " << trial << " vertex " << i;
        // Where two round joins' chords (each up to the 10 um arc tolerance inside its arc) cross, a vertex
        // sits up to about twice that inside; cleaning only removes vertices, it moves none.
        EXPECT_NEAR(ring_dist(r[i], ring), 0.01, 2.5e-5) << "trial " << trial << " vertex " << i;
      }
    }
  }
  EXPECT_EQ(rings, 20);
}
