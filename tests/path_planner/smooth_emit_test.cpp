// Emit (path_planner/smooth/emit.cpp): pieces made by hand or by the earlier stages on exact shapes, turned
// into points. Expectations from the geometry: corners exactly where given, arcs on their circle within the
// 5 um chord error, edge compensation of pitch/2 * max(|t_x|, |t_y|), a stadium followed along its length.
#include <gtest/gtest.h>

#include "tests/path_planner/stage_rings.hpp"
#include "tests/path_planner/truth.hpp"

using namespace hg::path_planner;
using namespace hg::path_planner::smooth;
using namespace hg::path_planner::stage_test;

namespace {

constexpr double kChord = 5e-6;

Ring circle_ring(double R, int n) {
  Ring r;
  for (int k = 0; k < n; ++k) r.push_back(R * Vec2(std::cos(2 * kPi * k / n), std::sin(2 * kPi * k / n)));
  return r;
}

// One circle piece over the whole ring, centred on the true centre.
Pieces whole_circle(const SmoothContext& c, double R) {
  Primitive p;
  p.circle = true, p.centre = -c.u.origin, p.radius = R, p.ccw = true, p.first = 0, p.last = c.n - 1;
  return {{p, 0, false, std::nullopt}};
}

}  // namespace

TEST(PathPlannerSmoothEmit, LinesBetweenCornersAreTheCornersAlone) {
  const Ring square = {{0, 0}, {0.2, 0}, {0.2, 0.2}, {0, 0.2}};
  const Sampled s = sample_polygon(square, 0.001);
  const auto c = make_context(s.ring, 0.001, exact_options());
  ASSERT_TRUE(c);
  Pieces p;
  Corners corners;
  for (int k = 0; k < 4; ++k) {
    p.push_back({line_piece(c->u, s.corner[k] + 3, (k == 3 ? long(s.ring.size()) : s.corner[k + 1]) - 3), k, false,
                 std::nullopt});
    corners.push_back({s.corner[k], kPi / 2, square[k] - c->u.origin});
  }
  const SmoothedRing out = emit_ring(*c, p, corners);
  ASSERT_EQ(out.points.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_LT((out.points[k] - square[k]).norm(), 1e-15);
    EXPECT_EQ(out.corner[k], 1);
  }
}

TEST(PathPlannerSmoothEmit, WholeCircleIsSampledWithinTheChordError) {
  for (double R : {0.005, 0.05, 0.3}) {
    SCOPED_TRACE("R " + std::to_string(R));
    const auto c = make_context(circle_ring(R, 2000), 0.0002, exact_options());
    ASSERT_TRUE(c);
    const SmoothedRing out = emit_ring(*c, whole_circle(*c, R), {});
    ASSERT_GT(out.points.size(), 8u);
    const std::size_t n = out.points.size();
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_NEAR(out.points[i].norm(), R, 1e-12 + 1e-12 * R);
      EXPECT_EQ(out.corner[i], 0);
      const double chord = (out.points[(i + 1) % n] - out.points[i]).norm();
      EXPECT_LE(R - std::sqrt(R * R - chord * chord / 4), kChord * (1 + 1e-9)) << "sagitta at " << i;
    }
  }
}

// With the pitch known, the circle moves outward by pitch/2 * max(|t_x|, |t_y|) for its tangent t: by
// pitch/2 where the tangent is along an axis, pitch/(2 sqrt 2) at 45 deg.
TEST(PathPlannerSmoothEmit, EdgeCompensationFollowsTheTangent) {
  const double R = 0.1, pitch = 0.002;
  const auto c = make_context(circle_ring(R, 2000), pitch, SmoothOptions{});
  ASSERT_TRUE(c);
  ASSERT_EQ(c->bias_scale, 1.0);
  const SmoothedRing out = emit_ring(*c, whole_circle(*c, R), {});
  for (const Vec2& q : out.points) {
    const Vec2 t(-q.y() / q.norm(), q.x() / q.norm());
    EXPECT_NEAR(q.norm() - R, 0.5 * pitch * std::max(std::abs(t.x()), std::abs(t.y())), 1e-12);
  }
}

// The exact stadium through segmentation, tangency and emit: every point, and every point of the straight
// runs between them, on the stadium within the arcs' 5 um chord error.
TEST(PathPlannerSmoothEmit, StadiumIsFollowedAlongItsLength) {
  const double L = 0.2, R = 0.05;
  const Stadium s = stadium(L, R, 0.001);
  const auto c = make_context(s.ring, 0.001, exact_options());
  ASSERT_TRUE(c);
  const Pieces p = make_tangent(*c, segment_run(*c, 0, c->n - 1, 0, true), true);
  const SmoothedRing out = emit_ring(*c, p, {});
  auto stadium_distance = [&](const Vec2& q) {
    return std::abs(hg::path_planner::test::segment_distance(q, Vec2(0, R), Vec2(L, R)) - R);
  };
  double worst = 0;
  for (const Vec2& q : hg::path_planner::test::densify(out.points, 0.0005))
    worst = std::max(worst, stadium_distance(q));
  EXPECT_LT(worst, kChord * (1 + 1e-6));
  double length = 0;
  for (std::size_t i = 0; i < out.points.size(); ++i)
    length += (out.points[(i + 1) % out.points.size()] - out.points[i]).norm();
  EXPECT_NEAR(length, 2 * L + 2 * kPi * R, 1e-4) << "closed, no gaps or doubled stretches";
}
