// The smoothing's geometry (path_planner/smooth/fits.cpp): TLS lines from the ring's moments, geometric
// circles, intersections; against points placed exactly on known lines and circles (full-precision
// coordinates far from the origin), and with known noise.
#include <gtest/gtest.h>

#include "tests/path_planner/stage_rings.hpp"

using namespace hg::path_planner;
using namespace hg::path_planner::smooth;
using namespace hg::path_planner::stage_test;

namespace {

// A ring: an arc of radius R about `centre` from angle a0 over `sweep`, then the chord back (sampled).
Ring arc_and_chord(const Vec2& centre, double R, double a0, double sweep, int n) {
  Ring r;
  for (int k = 0; k <= n; ++k)
    r.push_back(centre + R * Vec2(std::cos(a0 + sweep * k / n), std::sin(a0 + sweep * k / n)));
  const Vec2 a = r.back(), b = r.front();
  for (int k = 1; k < n; ++k) r.push_back(a + (b - a) * (double(k) / n));
  return r;
}

}  // namespace

TEST(PathPlannerSmoothFits, LineThroughExactPointsFarFromTheOrigin) {
  const Vec2 base(12.3456789012345, -7.65432109876543), dir = Vec2(0.8, 0.6);
  Ring r;
  for (int k = 0; k < 50; ++k) r.push_back(base + dir * (0.001 * k));
  for (int k = 49; k > 0; --k) r.push_back(base + dir * (0.001 * k) + Vec2(-0.6, 0.8) * 0.01);  // back, 10 mm left
  const Unrolled u(r);
  const Line l = fit_line(u, 0, 49);
  ASSERT_TRUE(l.ok);
  EXPECT_NEAR(l.dir.x(), dir.x(), 1e-9);
  EXPECT_NEAR(l.dir.y(), dir.y(), 1e-9);
  EXPECT_LT(l.rms, 1e-9);
  EXPECT_LT(std::abs(cross(l.dir, u.origin + l.centre - base)), 1e-9) << "the centre lies on the line";
  // the same range unwrapped one loop on gives the same line; reversed order the opposite direction
  const Line again = fit_line(u, long(r.size()), long(r.size()) + 49);
  EXPECT_NEAR((again.dir - l.dir).norm(), 0, 1e-9);
  EXPECT_NEAR((fit_line(u, 50, 97).dir + dir).norm(), 0, 1e-9);
}

TEST(PathPlannerSmoothFits, LineResidualOfNoiseIsItsSigma) {
  const double sigma = 0.0003;
  Ring r;
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, sigma);
  for (int k = 0; k < 20000; ++k) r.push_back(Vec2(0.00001 * k, g(rng)));
  for (int k = 1; k < 10; ++k) r.push_back(Vec2(0.2 - 0.02 * k, 0.05));
  const Line l = fit_line(Unrolled(r), 0, 19999);
  EXPECT_NEAR(l.rms, sigma, 0.03 * sigma);
  EXPECT_NEAR(std::abs(l.dir.x()), 1, 1e-6);
}

TEST(PathPlannerSmoothFits, CircleThroughExactArcs) {
  for (double sweep : {0.5, 1.5, 3.0}) {
    const Vec2 centre(3.14159, -2.71828);
    const double R = 0.0375;
    const Ring r = arc_and_chord(centre, R, 0.3, sweep, 60);
    const Unrolled u(r);
    Primitive c;
    ASSERT_TRUE(fit_circle(u, 0, 60, c)) << "sweep " << sweep;
    EXPECT_NEAR(c.radius, R, 1e-9);
    EXPECT_LT((u.origin + c.centre - centre).norm(), 1e-9);
    EXPECT_TRUE(c.ccw);
    for (long j = 0; j <= 60; ++j) EXPECT_NEAR(residual(c, u.at(j)), 0, 1e-9);
  }
}

TEST(PathPlannerSmoothFits, IntersectionsOfLinesAndCircles) {
  Primitive h, v, circle;
  h.dir = Vec2(1, 0), h.centre = Vec2(0, 0.1);
  v.dir = Vec2(0, 1), v.centre = Vec2(0.3, 0);
  circle.circle = true, circle.centre = Vec2(0, 0), circle.radius = 0.5;
  Vec2 x;
  ASSERT_TRUE(intersect(h, v, 0, 0, Vec2::Zero(), x));
  EXPECT_LT((x - Vec2(0.3, 0.1)).norm(), 1e-15);
  ASSERT_TRUE(intersect(h, circle, 0, 0, Vec2(1, 0), x));
  EXPECT_LT((x - Vec2(std::sqrt(0.25 - 0.01), 0.1)).norm(), 1e-12) << "the root nearest the hint";
  ASSERT_TRUE(intersect(h, circle, 0, 0, Vec2(-1, 0), x));
  EXPECT_LT((x - Vec2(-std::sqrt(0.25 - 0.01), 0.1)).norm(), 1e-12);
  Primitive far = h;
  far.centre = Vec2(0, 0.7);
  EXPECT_FALSE(intersect(far, circle, 0, 0, Vec2::Zero(), x)) << "a line beyond the circle";
  // edge compensation moves each line outward (right of travel) by pitch/2 for an axis-parallel edge
  ASSERT_TRUE(intersect(h, v, 0.002, 1, Vec2::Zero(), x));
  EXPECT_LT((x - Vec2(0.3 + 0.001, 0.1 - 0.001)).norm(), 1e-15) << "h moves to -y, v to +x";
}
