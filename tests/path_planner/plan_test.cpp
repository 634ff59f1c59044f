// Unit tests of plan(), the composition of the steps, against independent (analytic) expectations.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/path_planner/step_shapes.hpp"

namespace {
PlannerConfig simple_config() {
  PlannerConfig c;
  c.camera_to_base = pose_from_xyz_rpy(Vec3(0.5, 0, 1.2), Vec3(kPi, 0, 0));
  c.limits.workspace_min = Vec3(-1, -1, 0);
  c.limits.workspace_max = Vec3(2, 1, 1);
  c.limits.table_z = 0;
  return c;
}
// A square hole with corner fillets of radius min(15 mm, half side): larger than the default 10 mm tool, so
// the round tool reaches all of its edge (a sharp-cornered hole FAILS for its unreached corners,
// coverage_test.cpp). Clockwise (canonical for a hole).
OutlineInput plate_with_hole(double hole_half) {
  OutlineInput in;
  in.plane = {Vec3(0, 0, 1.19), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1)};
  const double r = std::min(0.015, hole_half), c = hole_half - r;
  Ring hole;
  for (int q = 0; q < 4; ++q) {  // counter-clockwise, fillet centres at (+-c, +-c) about the hole's centre
    const Vec2 centre = Vec2(0.1, 0.05) + c * Vec2(q == 0 || q == 3 ? 1 : -1, q < 2 ? 1 : -1);
    for (int k = 0; k <= (c > 0 ? 16 : 15); ++k) {  // c = 0: a circle, no repeated points
      // unequal steps (smoothstep): equal ones near the axes would pass for a pixel staircase (estimate_pitch)
      const double t = k / 16.0, a = (q + t * t * (3 - 2 * t)) * kPi / 2;
      hole.push_back(centre + r * Vec2(std::cos(a), std::sin(a)));
    }
  }
  std::reverse(hole.begin(), hole.end());
  in.loops = {{false, rect(0, 0, 0.3, 0.1)}, {true, hole}};
  return in;
}
}  // namespace

TEST(PathPlannerPlan, EveryLoopGroundAtTheToolRadius) {
  const PlannerConfig cfg = simple_config();
  const OutlineInput in = plate_with_hole(0.02);
  JobParams jp;  // zero: defaults
  jp.tool_radius = 0;
  jp.tilt = 0;
  jp.grind_speed = 0;
  jp.travel_speed = 0;
  jp.step = 0;
  jp.safe_height = 0;
  const PlanResult r = plan(in, jp, cfg, std::nullopt);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_EQ(r.loops_planned, 2);
  EXPECT_DOUBLE_EQ(r.params.tool_radius, cfg.defaults.tool_radius);
  const Eigen::Isometry3d Tinv = plate_to_base(in.plane, cfg.camera_to_base).inverse();
  int grind[2] = {0, 0};
  for (const Waypoint& w : r.path) {
    EXPECT_NEAR(w.orientation.norm(), 1, 1e-12);
    if (w.kind != kGrind) continue;
    ASSERT_GE(w.loop, 0);
    ++grind[w.loop];
    const Vec3 p = Tinv * w.position;
    EXPECT_NEAR(p.z(), 0, 1e-12);
    EXPECT_NEAR(ring_dist(p.head<2>(), in.loops[w.loop].points), cfg.defaults.tool_radius, 2e-5);
    const double tilt = std::acos(std::clamp(w.orientation.toRotationMatrix().col(2).dot(Vec3(0, 0, -1)), -1.0, 1.0));
    EXPECT_NEAR(tilt, cfg.defaults.tilt, 1e-9);
  }
  EXPECT_GT(grind[0], 100);
  EXPECT_GT(grind[1], 10);
}

TEST(PathPlannerPlan, StartsNearTheRobot) {
  const PlannerConfig cfg = simple_config();
  const OutlineInput in = plate_with_hole(0.02);
  // Plate (x, y) maps to base (0.5 + x, y, 0.01). Robot above the far right end of the plate.
  const PlanResult r = plan(in, JobParams{}, cfg, Vec3(0.5 + 0.35, 0.05, 0.3));
  ASSERT_TRUE(r.ok) << r.reason;
  const Waypoint& first = r.path[1];  // the lead-in start at grind height
  EXPECT_EQ(first.loop, 0);
  EXPECT_GT(first.position.x(), 0.5 + 0.3);
}

TEST(PathPlannerPlan, HoleTooSmallFailsOrIsSkippedPerConfig) {
  PlannerConfig cfg = simple_config();
  const OutlineInput in = plate_with_hole(0.008);  // 16 mm hole, 20 mm tool
  PlanResult r = plan(in, JobParams{}, cfg, std::nullopt);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("hole 1 is too small"), std::string::npos) << r.reason;
  // The measured cause: the widest circle inside the 16 mm hole (a circle, drawn as 64 chords) against the tool.
  EXPECT_NE(r.reason.find("the widest circle inside its edge is 16.0 mm across, the tool is 20.0 mm"),
            std::string::npos)
      << r.reason;
  cfg.small_hole = SmallHolePolicy::Skip;
  r = plan(in, JobParams{}, cfg, std::nullopt);
  ASSERT_TRUE(r.ok) << r.reason;
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("hole 1"), std::string::npos);
  EXPECT_EQ(r.loops_planned, 1);
}

TEST(PathPlannerPlan, OutOfWorkspaceAndBadInputFail) {
  PlannerConfig cfg = simple_config();
  cfg.limits.workspace_max = Vec3(0.7, 1, 1);  // the plate reaches x = 0.8 (+ tool)
  PlanResult r = plan(plate_with_hole(0.02), JobParams{}, cfg, std::nullopt);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("validation: waypoint"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("outside the workspace box"), std::string::npos) << r.reason;
  OutlineInput bad = plate_with_hole(0.02);
  bad.loops[1].points[2].x() = std::nan("");
  r = plan(bad, JobParams{}, simple_config(), std::nullopt);
  EXPECT_EQ(r.reason, "bad outline: loop 1 point 2 is not finite");
  JobParams neg;
  neg.tool_radius = -0.01;
  r = plan(plate_with_hole(0.02), neg, simple_config(), std::nullopt);
  EXPECT_EQ(r.reason, "tool_radius -0.01 m is outside [0.001, 0.2] m");
}

// A job's quantities are checked against their one range (runtime/quantities.hpp), the range the cell, the
// DDS gateway and hg-lcm-send check: both ends in, beyond either end the reason names the quantity.
TEST(PathPlannerPlan, EveryJobQuantityIsCheckedAgainstItsOneRange) {
  namespace qn = hg::quantity;
  const JobParams defaults;
  int checked = 0;
  for (int which = 0; which < 6; ++which) {
    for (int end = 0; end < 4; ++end) {  // min, max, just below min, just above max
      JobParams req;
      std::string name, expected;
      int i = 0;
      qn::for_each_job_quantity(
          [&](const qn::Quantity& q, double& v) {
            if (i++ != which) return;
            const double below = q.min > 0 ? std::nextafter(q.min, -1.0) : -1e-9;
            v = end == 0 ? q.min : end == 1 ? q.max : end == 2 ? below : std::nextafter(q.max, 10.0);
            name = q.name;
            if (end >= 2) expected = std::string(q.name) + " " + qn::number_text(v) + " " + q.unit + " is outside [";
          },
          req);
      JobParams out;
      const std::string why = resolve_params(req, defaults, out);
      SCOPED_TRACE(name + " end " + std::to_string(end));
      if (expected.empty()) {
        EXPECT_EQ(why, "");
      } else {
        EXPECT_EQ(why.rfind(expected, 0), 0u) << why;
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, 24);
}

TEST(PathPlannerPlan, FlippedPathIsTheMirrorImage) {
  const PlannerConfig cfg = simple_config();
  OutlineInput in = plate_with_hole(0.02);
  JobParams jp;
  jp.flipped = true;
  const PlanResult r = plan(in, jp, cfg, std::nullopt);
  ASSERT_TRUE(r.ok) << r.reason;
  const std::vector<Loop> mirrored = mirror_for_flip(in.loops);
  const Eigen::Isometry3d Tinv = plate_to_base(in.plane, cfg.camera_to_base).inverse();
  for (const Waypoint& w : r.path) {
    if (w.kind == kGrind) {
      EXPECT_NEAR(ring_dist((Tinv * w.position).head<2>(), mirrored[w.loop].points), cfg.defaults.tool_radius, 2e-5);
    }
  }
}

// The inscribed width is the diameter of the widest circle inside a hole: a circle's diameter, a slot's width.
TEST(PathPlannerPlan, InscribedWidthIsTheWidestCircleInside) {
  for (double d : {0.012, 0.03, 0.1}) {
    Ring circle;
    for (int k = 0; k < 200; ++k)
      circle.push_back(0.5 * d * Vec2(std::cos(-2 * kPi * k / 200), std::sin(-2 * kPi * k / 200)));
    EXPECT_NEAR(inscribed_width(circle, true, 1e-7), d, 4e-5 + d * (1 - std::cos(kPi / 200)));
  }
  const Ring slot = rect(0, 0, 0.12, 0.04);  // a 120 x 40 rectangle: 40 mm wide
  Ring cw(slot.rbegin(), slot.rend());
  EXPECT_NEAR(inscribed_width(cw, true, 1e-7), 0.04, 4e-5);
  EXPECT_TRUE(std::isinf(inscribed_width(slot, false, 1e-6)));
}

// A loop with any stretch unreached never reads "100.0 % reached" (the fraction is rounded down), and the
// message gives how far beyond the tool's reach the edge lies and the tool's radius at a tight corner.
TEST(PathPlannerPlan, UnreachedTextNeverSaysAHundredPercentAndGivesTheDepth) {
  LoopCoverage c;
  c.loop = 2;
  c.hole = true;
  c.length = 1.0;
  UnreachedStretch s;
  s.length = 1e-5;  // 0.001 % of the edge
  s.depth = 0.0004;
  s.concave = true;
  c.unreached = {s};
  c.unreached_length = s.length;
  const std::string t = describe_unreached(c, Eigen::Isometry3d::Identity(), 0.01, 0.0002, "robot_base");
  EXPECT_EQ(t.find("100.0 %"), std::string::npos) << t;
  EXPECT_NE(t.find("(99.9 % reached)"), std::string::npos) << t;
  EXPECT_NE(t.find("(up to 0.4 mm beyond)"), std::string::npos) << t;
  EXPECT_NE(t.find("tighter than the tool's 10.0 mm radius"), std::string::npos) << t;
}
