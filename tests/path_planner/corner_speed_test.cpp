// Unit tests of corner speeds (limit_corner_speeds) against the robot bridge's check, against independent (analytic)
// expectations.
#include <gtest/gtest.h>

#include "tests/path_planner/step_shapes.hpp"

namespace {
// A polyline in the z = 0.1 plane at one speed.
std::vector<Waypoint> polyline(const std::vector<Vec2>& pts, double speed) {
  std::vector<Waypoint> p;
  for (const Vec2& q : pts) p.push_back({Vec3(q.x(), q.y(), 0.1), Eigen::Quaterniond::Identity(), speed, kGrind, 0});
  return p;
}
}  // namespace

TEST(PathPlannerCornerSpeed, RadiusOfKnownTriangles) {
  // Right angle with legs s: the hypotenuse is a diameter, r = s sqrt(2) / 2.
  const double s = 0.002;
  EXPECT_NEAR(corner_radius(Vec3(0, 0, 0), Vec3(s, 0, 0), Vec3(s, s, 0)), s * std::sqrt(2.0) / 2, 1e-15);
  // Three points of a circle of radius R (any plane): R.
  const double R = 0.0137;
  const Vec3 c(0.3, -0.2, 0.5), e1 = Vec3(1, 2, 2) / 3, e2 = Vec3(2, 1, -2) / 3;
  auto on = [&](double t) { return Vec3(c + R * (std::cos(t) * e1 + std::sin(t) * e2)); };
  EXPECT_NEAR(corner_radius(on(0.1), on(0.9), on(2.5)), R, 1e-14);
  EXPECT_EQ(corner_radius(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0)), INFINITY);  // straight on
  EXPECT_EQ(corner_radius(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 0)), 0.0);     // reversal
}

TEST(PathPlannerCornerSpeed, LimitIsSqrtOfAccelTimesRadius) {
  for (double r : {1e-7, 7.07e-5, 0.001, 0.0137, 2.5}) {
    const double v = corner_speed_limit(r, 2.0);
    EXPECT_NEAR(v, std::sqrt(2.0 * r), 1e-8 * std::sqrt(2.0 * r)) << r;
    EXPECT_LE(v * v / r, 2.0) << r;  // exactly, in floating point, as the bridge computes it
  }
  EXPECT_EQ(corner_speed_limit(INFINITY, 2.0), INFINITY);
  EXPECT_EQ(corner_speed_limit(0.0, 2.0), 0.0);
}

TEST(PathPlannerCornerSpeed, RightAngleCornerSlowsBothSegmentsToSqrtAR) {
  // Straight in along x at step s, a right-angle corner at (3s, 0), straight out along y.
  const double a = 2.0;
  for (double s : {0.0001, 0.0002}) {
    auto p = polyline({{0, 0}, {s, 0}, {2 * s, 0}, {3 * s, 0}, {3 * s, s}, {3 * s, 2 * s}, {3 * s, 3 * s}}, 0.02);
    const Vec3 start(-s, 0, 0.1);  // in line with the first segment
    const double r = s * std::sqrt(2.0) / 2, want = std::sqrt(a * r);
    ASSERT_LT(want, 0.02);
    EXPECT_EQ(limit_corner_speeds(p, start, a), 2);
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (i == 3 || i == 4) {  // the segments ending at and leaving the corner
        EXPECT_NEAR(p[i].speed, want, 2e-9 * want) << "s " << s << " waypoint " << i;
      } else {
        EXPECT_EQ(p[i].speed, 0.02) << "s " << s << " waypoint " << i;
      }
    }
  }
  // At the 2 mm step the same corner takes 0.053 m/s: nothing to slow at 0.02 m/s.
  auto p = polyline({{0, 0}, {0.002, 0}, {0.002, 0.002}, {0.002, 0.004}}, 0.02);
  EXPECT_EQ(limit_corner_speeds(p, Vec3(-0.002, 0, 0.1), a), 0);
}

TEST(PathPlannerCornerSpeed, ArcOfRadiusRRunsAtSqrtAR) {
  const double R = 0.0001, a = 2.0;  // 0.1 mm arc: sqrt(2 * 1e-4) = 0.01414 m/s
  std::vector<Vec2> pts;
  for (int k = 0; k <= 40; ++k) pts.emplace_back(R * std::cos(0.05 * k), R * std::sin(0.05 * k));
  auto p = polyline(pts, 0.02);
  const Vec3 start(R * std::cos(-0.05), R * std::sin(-0.05), 0.1);
  limit_corner_speeds(p, start, a);
  // Every segment has a corner of radius R at one end at least (the last one at its start).
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_NEAR(p[i].speed, std::sqrt(a * R), 1e-6 * std::sqrt(a * R)) << i;
}

TEST(PathPlannerCornerSpeed, FirstCornerIsFromTheRobotAndReversalsAreRefused) {
  const double a = 2.0;
  auto p = polyline({{0, 0}, {0.0001, 0}, {0.0002, 0}}, 0.02);
  // From a start 0.1 mm to the side of waypoint 0: a right angle there with legs 0.1 mm.
  EXPECT_EQ(limit_corner_speeds(p, Vec3(0, -0.0001, 0.1), a), 2);
  EXPECT_NEAR(p[0].speed, std::sqrt(a * 0.0001 * std::sqrt(2.0) / 2), 1e-10);
  EXPECT_EQ(p[0].speed, p[1].speed);
  EXPECT_EQ(p[2].speed, 0.02);
  Limits L;
  L.table_z = 0;
  EXPECT_EQ(validate(p, L, Vec3(0, 0, 1), Vec3(0, -0.0001, 0.1)), "");
  // Going back the way it came: no speed helps; left alone and refused with the reason.
  auto back = polyline({{0, 0}, {0.001, 0}, {0.0005, 0}}, 0.02);
  EXPECT_EQ(limit_corner_speeds(back, Vec3(-0.001, 0, 0.1), a), 0);
  EXPECT_NE(validate(back, L, Vec3(0, 0, 1), Vec3(-0.001, 0, 0.1)).find("waypoint 1 (grind): the path reverses here"),
            std::string::npos);
}

// Independent expectation: the robot bridge's own check (robot_bridge/path.cpp), linked from its library.
hg::robot_bridge::Path to_bridge(const std::vector<Waypoint>& p) {
  hg::robot_bridge::Path b;
  for (const Waypoint& w : p) {
    b.position.push_back(w.position);
    b.orientation.push_back(w.orientation);
    b.speed.push_back(w.speed);
    b.kind.push_back(w.kind);
  }
  return b;
}

TEST(PathPlannerCornerSpeed, RandomZigzagsPassTheBridgeCheckAndValidateAgreesWithIt) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> step(1e-6, 0.003), turn(-3.1, 3.1), speed(0.005, 0.2);
  hg::robot_bridge::Limits bl;  // the bridge's defaults (max_accel 2.0, max_speed 0.25)
  Limits L;
  L.workspace_min = Vec3(-1.5, -1.5, -0.5);
  L.workspace_max = Vec3(1.5, 1.5, 1.5);
  L.table_z = -0.5;
  L.max_speed = bl.max_speed;
  L.max_accel = bl.max_accel;
  ASSERT_EQ(L.max_accel, 2.0);  // the planner's default is the bridge's
  int refused_before = 0, slowed = 0;
  int accepted_before = 0;
  for (int trial = 0; trial < 300; ++trial) {
    // Every third path gentle (slow, long steps) so that both verdicts occur.
    const double gentle = trial % 3 == 0 ? 0.03 : 1.0;
    std::vector<Waypoint> p;
    Vec3 at(0, 0, 0.2);
    double heading = 0;
    const Vec3 start = at;
    for (int k = 0; k < 60; ++k) {
      heading += turn(rng) * (k % 7 == 0 ? gentle : 0.1 * gentle);
      at += (gentle < 1 ? 0.003 + step(rng) : step(rng)) * Vec3(std::cos(heading), std::sin(heading), 0);
      // Travel moves: a random zigzag crosses itself, which validate refuses for grind loops only.
      p.push_back({at, Eigen::Quaterniond::Identity(), speed(rng) * (gentle < 1 ? 0.2 : 1.0), kTravel, -1});
    }
    const hg::robot_bridge::Pose bstart{start, Eigen::Quaterniond::Identity()};
    const std::string bridge_before = hg::robot_bridge::check_path(to_bridge(p), bstart, bl);
    const std::string ours_before = validate(p, L, Vec3(0, 0, 1), start);
    refused_before += !bridge_before.empty();
    accepted_before += bridge_before.empty();
    // Both refuse the same paths, at the same waypoint.
    EXPECT_EQ(bridge_before.empty(), ours_before.empty()) << bridge_before << " | " << ours_before;
    if (!bridge_before.empty() && !ours_before.empty()) {
      auto where = [](const std::string& why) { return std::string_view(why).substr(0, why.find(':')); };
      EXPECT_EQ(where(bridge_before), where(ours_before));  // "waypoint K (kind)"
    }
    slowed += limit_corner_speeds(p, start, L.max_accel);
    EXPECT_EQ(hg::robot_bridge::check_path(to_bridge(p), bstart, bl), "") << "trial " << trial;
    EXPECT_EQ(validate(p, L, Vec3(0, 0, 1), start), "") << "trial " << trial;
  }
  // Both verdicts occur: the agreement is tested both ways, and the limiter has work to do.
  EXPECT_GT(refused_before, 150);
  EXPECT_GT(accepted_before, 20);
  std::printf("  %d of 300 random paths refused by the bridge before, none after; %d speeds lowered\n", refused_before,
              slowed);
}
