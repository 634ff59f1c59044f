// Unit tests of path validation, against independent (analytic) expectations.
#include <gtest/gtest.h>

#include "tests/path_planner/step_shapes.hpp"

namespace {
std::vector<Waypoint> square_path(double z) {
  std::vector<Waypoint> p;
  const Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  p.push_back({Vec3(0, 0, z + 0.05), q, 0.1, kApproach, -1});
  p.push_back({Vec3(0, 0, z), q, 0.05, kApproach, 0});
  p.push_back({Vec3(0.01, 0, z), q, 0.02, kLeadIn, 0});
  for (Vec2 c : {Vec2(0.1, 0), Vec2(0.1, 0.1), Vec2(0.01, 0.1), Vec2(0.01, 0)})
    p.push_back({Vec3(c.x(), c.y(), z), q, 0.02, kGrind, 0});
  p.push_back({Vec3(0.01, 0, z + 0.05), q, 0.05, kRetract, 0});
  return p;
}
}  // namespace

TEST(PathPlannerValidate, AcceptsAGoodPathAndRejectsEachFault) {
  Limits L;
  L.workspace_min = Vec3(-0.5, -0.5, 0);
  L.workspace_max = Vec3(0.5, 0.5, 0.5);
  L.table_z = 0.005;
  L.max_speed = 0.2;
  const Vec3 up(0, 0, 1);
  const Vec3 start(0, 0, 0.2);  // straight above the first waypoint: no corner there
  EXPECT_EQ(validate(square_path(0.01), L, up, start), "");
  auto p = square_path(0.01);
  p[4].position.x() = 0.6;
  EXPECT_NE(validate(p, L, up, start).find("waypoint 4: position (0.6000, 0.1000, 0.0100) m is outside the workspace"),
            std::string::npos);
  EXPECT_NE(validate(square_path(0.004), L, up, start).find("not above the table"), std::string::npos);
  p = square_path(0.01);
  p[3].speed = 0.3;
  EXPECT_NE(validate(p, L, up, start).find("speed"), std::string::npos);
  p = square_path(0.01);
  std::swap(p[4].position, p[5].position);  // bow tie
  EXPECT_NE(validate(p, L, up, start).find("intersects itself"), std::string::npos);
  // The corner at the foot of the descent: legs 50 mm (down) and 10 mm (along x) at right angles, so the
  // circle through the three points has the hypotenuse as diameter; 0.02 m/s there needs v^2 / r.
  L.max_accel = 0.001;
  const double r = std::hypot(0.05, 0.01) / 2, need = 0.02 * 0.02 / r;
  char want[160];
  std::snprintf(want, sizeof want,
                "waypoint 1 (approach): the corner (radius %.6f mm) at 0.020000 m/s needs %.6f m/s^2", r * 1e3, need);
  EXPECT_NE(validate(square_path(0.01), L, up, start).find(want), std::string::npos)
      << validate(square_path(0.01), L, up, start);
  L.max_accel = need * 1.001;  // just enough for that corner (and the square's wider ones)
  EXPECT_EQ(validate(square_path(0.01), L, up, start), "");
}

TEST(PathPlannerValidate, SelfIntersection) {
  EXPECT_FALSE(self_intersects(rect(0, 0, 1, 1)));
  EXPECT_TRUE(self_intersects({{0, 0}, {1, 1}, {1, 0}, {0, 1}}));
  const Ring big = circle({0, 0}, 1, 20000);
  EXPECT_FALSE(self_intersects(big));
  Ring spiked = big;
  spiked[5000] = Vec2(0, -0.5);  // a spike into the circle's inside crosses nothing
  EXPECT_FALSE(self_intersects(spiked));
  spiked[15000] = Vec2(0, -0.4);  // a second spike from the far side crosses the first
  EXPECT_TRUE(self_intersects(spiked));
  Ring crossing = big;
  crossing[100] = Vec2(-2, 0);  // a spike out through the far side of the circle
  EXPECT_TRUE(self_intersects(crossing));
  // Touching (a vertex on another segment) counts as an intersection.
  EXPECT_TRUE(self_intersects({{0, 0}, {2, 0}, {2, 2}, {1, 0}, {0, 2}}));
}
