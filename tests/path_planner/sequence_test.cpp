// Unit tests of leads, approach/retract and the loop order, against independent (analytic) expectations.
#include <gtest/gtest.h>

#include "tests/path_planner/step_shapes.hpp"

TEST(PathPlannerSequence, LeadInArcIsTangentAndOnTheAirSide) {
  const Vec2 p0(0.2, 0.1), t(0, 1), m(1, 0);
  const double rho = 0.01;
  const auto arc = lead_in_arc(p0, t, m, rho, deg(90), 0.001);
  ASSERT_GE(arc.size(), 4u);
  EXPECT_LT((arc.back() - p0).norm(), 1e-15);
  const Vec2 c = p0 + rho * m;
  for (const Vec2& q : arc) {
    EXPECT_NEAR((q - c).norm(), rho, 1e-12);
    EXPECT_GE((q - p0).dot(m), -1e-15);
  }
  // The arc's tangent at p0 is perpendicular to the radius there, i.e. along t; the last chord deviates
  // by half its angle.
  const Vec2 last = (arc.back() - arc[arc.size() - 2]).normalized();
  const double chord_angle = deg(90) / double(arc.size() - 1);
  EXPECT_NEAR(std::acos(last.dot(t)), chord_angle / 2, 1e-9);
  EXPECT_NEAR((arc.front() - (p0 + rho * m - rho * t)).norm(), 0, 1e-12);  // starts a quarter turn back
  const auto out = lead_out_arc(p0, t, m, rho, deg(90), 0.001);
  EXPECT_LT((out.front() - p0).norm(), 1e-15);
  EXPECT_NEAR((out.back() - (p0 + rho * m + rho * t)).norm(), 0, 1e-12);
  const Vec2 first = (out[1] - out[0]).normalized();
  EXPECT_NEAR(std::acos(first.dot(t)), chord_angle / 2, 1e-9);
}

TEST(PathPlannerSequence, GreedyOrderFromTheRobotAndNearestStart) {
  std::vector<GrindLoop> loops;
  for (int k = 0; k < 3; ++k)
    loops.push_back({resample_ring(rect(k * 0.3, 0, k * 0.3 + 0.1, 0.1), 0.01, deg(10)), false, k});
  Ordering a = order_loops(loops, Vec2(-0.5, 0.05));
  EXPECT_EQ(a.order, (std::vector<int>{0, 1, 2}));
  Ordering b = order_loops(loops, Vec2(1.5, 0.05));
  EXPECT_EQ(b.order, (std::vector<int>{2, 1, 0}));
  // Start vertex of the first loop: nearest non-corner point to the robot: on the left edge x = 0 at y
  // 0.05 (a sample point there, since 0.1 / 0.01 = 10 equal steps).
  const Vec2 s = loops[0].ring.points[a.start_vertex[0]];
  EXPECT_NEAR(s.x(), 0, 1e-12);
  EXPECT_NEAR(s.y(), 0.05, 1e-12);
}

TEST(PathPlannerSequence, ApproachAndRetractAtSafeHeight) {
  std::vector<GrindLoop> loops = {{resample_ring(rect(0, 0, 0.1, 0.1), 0.005, deg(10)), false, 0},
                                  {resample_ring(rect(0.3, 0, 0.4, 0.1), 0.005, deg(10)), false, 1}};
  SequenceOptions o;
  const double safe_height = 0.07, travel_speed = 0.2;
  o.z = 0.001;
  ToolPath tp{sequence(loops, Vec2(0, 0), o)};
  std::vector<std::unique_ptr<PathModifier>> list;
  list.push_back(std::make_unique<LeadArcs>(0.01, deg(90), 0.002, o.grind_speed));
  list.push_back(std::make_unique<Approach>(safe_height, travel_speed));
  list.push_back(std::make_unique<Retract>(safe_height, o.approach_speed));
  CompoundModifier(std::move(list)).apply(tp);
  const auto path = flatten(tp);
  ASSERT_FALSE(path.empty());
  EXPECT_EQ(path.front().kind, kApproach);
  EXPECT_NEAR(path.front().position.z(), 0.071, 1e-12);
  EXPECT_EQ(path.back().kind, kRetract);
  EXPECT_NEAR(path.back().position.z(), 0.071, 1e-12);
  int travel = 0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const auto& w = path[i];
    if (w.kind == kTravel) {
      ++travel;
      EXPECT_NEAR(w.position.z(), 0.071, 1e-12);
      EXPECT_EQ(path[i - 1].kind, kRetract);
      EXPECT_DOUBLE_EQ(w.speed, travel_speed);
    }
    if (w.kind == kGrind || w.kind == kLeadIn || w.kind == kLeadOut) {
      EXPECT_NEAR(w.position.z(), 0.001, 1e-12);
      EXPECT_DOUBLE_EQ(w.speed, o.grind_speed);
    }
  }
  EXPECT_EQ(travel, 1);
}
