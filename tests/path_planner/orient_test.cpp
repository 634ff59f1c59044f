// Unit tests of tool orientation and grinding direction, against independent (analytic) expectations.
#include <gtest/gtest.h>

#include "tests/path_planner/step_shapes.hpp"

TEST(PathPlannerOrient, ToolAxisTiltEqualsTheJobTilt) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-kPi, kPi);
  for (double tilt : {0.0, deg(15), deg(30), deg(45), deg(60)}) {
    for (int k = 0; k < 20; ++k) {
      const double a = U(rng);
      const Vec2 t(std::cos(a), std::sin(a)), m(t.y(), -t.x());
      const Eigen::Quaterniond q = tool_orientation(t, m, tilt);
      EXPECT_NEAR(q.norm(), 1, 1e-12);
      const Eigen::Matrix3d R = q.toRotationMatrix();
      const Vec3 z = R.col(2), x = R.col(0);
      EXPECT_NEAR(std::acos(std::clamp(z.dot(Vec3(0, 0, -1)), -1.0, 1.0)), tilt, 1e-9);
      if (tilt > 0) {
        EXPECT_LT(z.head<2>().dot(m), 0);  // axis points toward the material, tool leans out
      }
      EXPECT_NEAR(z.head<2>().dot(t), 0, 1e-12);  // tilt is in the plane of the edge normal
      EXPECT_NEAR((x - Vec3(t.x(), t.y(), 0)).norm(), 0, 1e-9);
      EXPECT_NEAR(R.determinant(), 1, 1e-12);
    }
  }
}

TEST(PathPlannerOrient, ClimbGoesClockwiseOutsideAndCounterClockwiseInHoles) {
  EXPECT_TRUE(travel_reversed(Direction::Climb, true));
  EXPECT_FALSE(travel_reversed(Direction::Conventional, true));
  EXPECT_FALSE(travel_reversed(Direction::Climb, false));
  Ring hole = rect(0.03, 0.03, 0.05, 0.05);
  std::reverse(hole.begin(), hole.end());
  std::vector<GrindLoop> loops = {{resample_ring(rect(0, 0, 0.1, 0.1), 0.005, deg(10)), false, 0},
                                  {resample_ring(hole, 0.005, deg(10)), true, 1}};
  for (Direction d : {Direction::Climb, Direction::Conventional}) {
    SequenceOptions o;
    o.direction = d;
    const auto path = flatten({sequence(loops, Vec2(-1, -1), o)});
    for (int loop : {0, 1}) {
      Ring g;
      for (const auto& w : path)
        if (w.kind == kGrind && w.loop == loop) g.push_back(w.position.head<2>());
      g.pop_back();  // the closing repeat of the start point
      const bool cw = signed_area(g) < 0;
      const bool outer_cw = d == Direction::Climb;
      EXPECT_EQ(cw, loop == 0 ? outer_cw : !outer_cw) << "direction " << int(d) << " loop " << loop;
    }
  }
}
