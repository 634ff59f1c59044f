// The outline service's computation without LCM: outline and part pose from a plate cloud, and the error
// statuses for clouds that give no valid loop. The part pose itself: part_pose_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <limits>

#include "outline_service/outline_service.hpp"
#include "outline_service/part_pose.hpp"
#include "test_clouds.hpp"

namespace os = hg::outline_service;
using hg::outline::Loop;
using hg::outline::Vec2;

namespace {

// The message says what the outline knows about its cloud, so the planner needs no pixel pitch: the point
// spacing of a regular grid is its pitch (sqrt(2 x median triangle area)), the mode, whether R was chosen
// automatically (R = k x h) or given, and the dropout holes dropped.
TEST(OutlineServiceCompute, MessageCarriesSpacingModeAndAutomaticRadius) {
  for (double p : {0.0013, 0.004}) {
    SCOPED_TRACE(p);
    const auto cloud = hg::test::plate_with_hole(0.4, 0.2, 0.1, 0.2, 0.05, 0.15, p);
    os::ServiceOptions automatic;
    const auto a = os::compute(cloud, automatic);
    ASSERT_EQ(a.outline.status, +hullgrind::outline_t::STATUS_OK) << a.outline.error_text;
    EXPECT_NEAR(a.outline.point_spacing, p, 1e-3 * p);
    EXPECT_TRUE(a.outline.alpha_automatic);
    EXPECT_EQ(a.outline.alpha_mode, "global");
    EXPECT_NEAR(a.outline.alpha_radius, 1.7 * p, 0.05 * p) << "R = k h, k = 1.7 for a regular grid";
    EXPECT_EQ(a.outline.quality, +hullgrind::outline_t::QUALITY_UNKNOWN);
    os::ServiceOptions given;
    given.alpha_radius = 2 * p;
    const auto g = os::compute(cloud, given);
    EXPECT_FALSE(g.outline.alpha_automatic);
    EXPECT_EQ(g.outline.alpha_radius, 2 * p);
    os::ServiceOptions local;
    local.alpha_mode = hg::outline::AlphaMode::Local;
    const auto l = os::compute(cloud, local);
    EXPECT_EQ(l.outline.alpha_mode, "local");
    EXPECT_TRUE(l.outline.alpha_automatic);
    EXPECT_NEAR(l.outline.point_spacing, p, 1e-3 * p);
  }
}

TEST(OutlineServiceCompute, PlateWithHoleGivesOuterLoopHoleAndPose) {
  const double p = 0.005;
  auto cloud = hg::test::plate_with_hole(0.4, 0.2, 0.1, 0.2, 0.05, 0.15, p);
  cloud.header.seq = 41;
  os::ServiceOptions opt;
  opt.alpha_radius = 2 * p;
  opt.order = hg::outline::Order::Hilbert;
  auto c = os::compute(cloud, opt);
  ASSERT_EQ(c.outline.status, +hullgrind::outline_t::STATUS_OK) << c.outline.error_text;
  EXPECT_EQ(c.outline.cloud_seq, 41);
  ASSERT_EQ(c.outline.num_loops, 2);
  int holes = 0;
  for (const auto& l : c.outline.loops) {
    holes += l.hole;
    EXPECT_EQ(l.n, int(l.u.size()));
  }
  EXPECT_EQ(holes, 1);
  EXPECT_EQ(c.outline.points_used, cloud.n);
  EXPECT_EQ(c.outline.points_read, cloud.n);
  EXPECT_EQ(c.outline.duplicates_merged, 0);
  EXPECT_EQ(c.outline.mode, "dshi");
  EXPECT_EQ(c.outline.order, "hilbert");  // the message says which order was used
  EXPECT_GT(c.outline.time_triangulate, 0);
  EXPECT_LE(c.outline.time_triangulate + c.outline.time_alpha + c.outline.time_loops, c.outline.compute_time);
  EXPECT_GT(c.outline.search_cost, 0);
  // Expected area, from the alpha-shape definition: the outer rectangle's boundary runs through its
  // corner points (convex corners are kept whole), but each corner of the hole is chamfered by the kept
  // triangles whose circumradius is <= R: a chamfer with legs L has circumradius L/sqrt(2), so with
  // R = 2p the legs reach 2p (2p/sqrt(2) = 1.41p <= 2p; 3p/sqrt(2) = 2.12p > 2p). The four chamfers take
  // 4 * (2p)^2 / 2 off the hole and are symmetric about its centre (0.15, 0.1).
  const double hole_area = 0.01 - 4 * 0.5 * (2 * p) * (2 * p);
  const double area = 0.08 - hole_area;
  // The pose's area is the steel's: the loops run through the last points, h/2 x max(|t_u|, |t_v|) inside
  // the edge, restored along both loops: h/2 x their length in the max norm (the rectangle's 1.2 m; the
  // hole's four sides less the chamfers' legs, 4 x (0.1 - 4p), and four chamfers of 2p).
  const double h = c.outline.point_spacing;
  const double steel = area + 0.5 * h * (1.2 + 4 * (0.1 - 4 * p) + 4 * 2 * p);
  ASSERT_EQ(c.poses.size(), 1u);
  EXPECT_NEAR(c.poses[0].area, steel, 1e-6);
  EXPECT_EQ(c.poses[0].num_parts, 1);
  // Centroid: (0.08*(0.2,0.1) - hole_area*(0.15,0.1)) / area; to the camera frame through the plane.
  double cu = (0.08 * 0.2 - hole_area * 0.15) / area;
  EXPECT_NEAR(c.poses[0].centroid_uv[0], cu, 1e-6);
  EXPECT_NEAR(c.poses[0].centroid_uv[1], 0.1, 1e-6);
  EXPECT_NEAR(c.poses[0].centroid_xyz[0], cu, 1e-6);
  EXPECT_NEAR(c.poses[0].centroid_xyz[1], -0.1, 1e-6);
  EXPECT_NEAR(c.poses[0].centroid_xyz[2], 1, 1e-12);
  EXPECT_NEAR(c.poses[0].principal_axis_angle, 0, 1e-6);
}

// The part's area on a pixel lattice is its pixels' area at any angle of its edges to the lattice, through
// the alpha shape as the service runs it. Along an edge at a slope of 1/2 or 1/3 to the lattice the loop
// bridges the staircase's notches (the triangle across a notch, circumradius 1.58 h, is under the
// automatic R = 1.7 h), so the loop's length in the max norm does not count its lattice points: h/2 x that
// length is half a pixel too much per notch (0.1-0.6 % of knee-scallop's area at pm806,
// docs/BENCHMARKS-outline.md). The expectation is independent of the outline: the points counted, x h^2.
TEST(OutlineServiceCompute, PartAreaIsItsPixelsWhateverTheEdgesSlopeToTheLattice) {
  const double h = 0.002;
  // A right triangle (legs 120 and 120 mm) with its right angle rounded (R30), turned by each angle: its
  // straight edges at slopes 0, 1/2, 1/3 and in between to the lattice, its arc at every slope. (Convex, so
  // that no chord of the loop passes over a lattice point outside it, which the area would count.)
  for (double turn : {0.0, std::atan(0.5), std::atan(1.0 / 3), 0.3, 0.7, 1.1}) {
    SCOPED_TRACE(turn);
    const double c = std::cos(turn), s = std::sin(turn), a = 0.12, r = 0.03;
    hullgrind::plate_cloud_t cloud = hg::test::plate_with_hole(0, 0, 0, 0, 0, 0, h);  // frame only
    cloud.u.clear(), cloud.v.clear(), cloud.part.clear();
    for (int j = -120; j <= 120; ++j)
      for (int i = -120; i <= 120; ++i) {
        const double x = c * i * h + s * j * h, y = -s * i * h + c * j * h;  // in the triangle's frame
        const bool fillet = x < r && y < r && (x - r) * (x - r) + (y - r) * (y - r) > r * r;
        if (x < 0 || y < 0 || x + y > a || fillet) continue;
        cloud.u.push_back(float(i * h)), cloud.v.push_back(float(j * h)), cloud.part.push_back(0);
      }
    cloud.n = int32_t(cloud.u.size());
    const os::Computed got = os::compute(cloud, os::ServiceOptions{});
    ASSERT_EQ(got.outline.status, +hullgrind::outline_t::STATUS_OK) << got.outline.error_text;
    ASSERT_EQ(got.poses.size(), 1u);
    EXPECT_NEAR(got.poses[0].area, cloud.n * h * h, 0.5 * h * h) << cloud.n << " points";
  }
}

TEST(OutlineServiceCompute, GapsOfMissingPixelsAreNotHoles) {
  const double p = 0.005;
  auto cloud = hg::test::plate_with_hole(0.4, 0.2, 0.1, 0.2, 0.05, 0.15, p);
  // A 2 x 2 block of pixels missing far from the real hole: with R = 1.5 p the triangles across the gap
  // are outside and the alpha shape has a hole of 3x3 p^2 less the four corner chamfers (p^2/2 each):
  // 7 p^2 (checked below), less than (3 p)^2.
  std::vector<std::size_t> gap;
  for (std::size_t i = 0; i < cloud.u.size(); ++i)
    if ((std::abs(cloud.v[i] - 0.1f) < 1e-6f || std::abs(cloud.v[i] - 0.105f) < 1e-6f) &&
        (std::abs(cloud.u[i] - 0.3f) < 1e-6f || std::abs(cloud.u[i] - 0.305f) < 1e-6f))
      gap.push_back(i);
  ASSERT_EQ(gap.size(), 4u);
  for (auto it = gap.rbegin(); it != gap.rend(); ++it) {
    cloud.u.erase(cloud.u.begin() + long(*it));
    cloud.v.erase(cloud.v.begin() + long(*it));
    cloud.part.erase(cloud.part.begin() + long(*it));
  }
  cloud.n -= 4;
  os::ServiceOptions opt;
  opt.alpha_radius = 1.5 * p;
  auto holes = [](const os::Computed& c) {
    int n = 0;
    for (const auto& l : c.outline.loops) n += l.hole;
    return n;
  };
  os::ServiceOptions keep_all = opt;
  keep_all.min_hole_spacings = 0;
  auto kept = os::compute(cloud, keep_all);
  ASSERT_EQ(kept.outline.status, +hullgrind::outline_t::STATUS_OK);
  EXPECT_EQ(holes(kept), 2);  // the cut-out and the gap
  EXPECT_EQ(kept.holes_dropped, 0);
  for (const auto& l : kept.outline.loops)
    if (l.hole && l.area < 0.001) {
      EXPECT_NEAR(l.area, 7 * p * p, 1e-9);
    }
  auto filtered = os::compute(cloud, opt);  // the process default, the core's 4.5 spacings
  EXPECT_EQ(holes(filtered), 1);            // the cut-out only: 0.1 m wide, far above (4.5 p)^2
  EXPECT_EQ(filtered.holes_dropped, 1);
  for (const auto& l : filtered.outline.loops)
    if (l.hole) {
      EXPECT_GT(l.area, 0.009);
    }
}

TEST(OutlineServiceCompute, ThreeByThreeDropoutIsNotAHoleButASmallCutOutIs) {
  const double p = 0.005;
  auto cloud = hg::test::plate_with_hole(0.4, 0.2, 0.1, 0.2, 0.05, 0.15, p);
  // A 3 x 3 block of pixels missing (pm806 frames show such gaps): with R = 1.5 p its hole is the 4 x 4 p
  // square through the neighbours less four corner chamfers of p^2 / 2: 14 p^2 (checked below), under the
  // default (4.5 p)^2. And a cut-out 8 x 8 pixels wide (the boundary through its neighbours: 9 x 9 p less the
  // chamfers, 79 p^2), elsewhere on the plate, is a real small hole: kept.
  auto missing = [&](float u, float v) {
    const bool gap = u > 0.2925f && u < 0.3075f && v > 0.0925f && v < 0.1075f;  // 3 x 3
    const bool cut = u > 0.0425f && u < 0.0825f && v > 0.0425f && v < 0.0825f;  // 8 x 8
    return gap || cut;
  };
  hullgrind::plate_cloud_t kept_points = cloud;
  kept_points.u.clear(), kept_points.v.clear(), kept_points.part.clear();
  for (std::size_t i = 0; i < cloud.u.size(); ++i)
    if (!missing(cloud.u[i], cloud.v[i])) {
      kept_points.u.push_back(cloud.u[i]);
      kept_points.v.push_back(cloud.v[i]);
      kept_points.part.push_back(cloud.part[i]);
    }
  ASSERT_EQ(cloud.u.size() - kept_points.u.size(), 9u + 64u);
  kept_points.n = int32_t(kept_points.u.size());
  os::ServiceOptions opt;
  opt.alpha_radius = 1.5 * p;
  std::vector<double> areas;
  os::ServiceOptions keep_all = opt;
  keep_all.min_hole_spacings = 0;
  const auto all = os::compute(kept_points, keep_all);
  ASSERT_EQ(all.outline.status, +hullgrind::outline_t::STATUS_OK);
  for (const auto& l : all.outline.loops)
    if (l.hole) areas.push_back(l.area);
  std::sort(areas.begin(), areas.end());
  ASSERT_EQ(areas.size(), 3u);  // the gap, the small cut-out, the 0.1 m cut-out
  EXPECT_NEAR(areas[0], 14 * p * p, 1e-9);
  EXPECT_NEAR(areas[1], 79 * p * p, 1e-9);
  const auto filtered = os::compute(kept_points, opt);  // the process default
  ASSERT_EQ(filtered.outline.status, +hullgrind::outline_t::STATUS_OK);
  EXPECT_EQ(filtered.holes_dropped, 1);
  int holes = 0;
  for (const auto& l : filtered.outline.loops) {
    holes += l.hole;
    if (l.hole) {
      EXPECT_GT(l.area, 25 * p * p);
    }
  }
  EXPECT_EQ(holes, 2);
}

TEST(OutlineServiceCompute, OuterOnlyFillsTheHole) {
  auto cloud = hg::test::plate_with_hole(0.4, 0.2, 0.1, 0.2, 0.05, 0.15, 0.005);
  os::ServiceOptions opt;
  opt.alpha_radius = 0.01;
  opt.outer_only = true;
  auto c = os::compute(cloud, opt);
  ASSERT_EQ(c.outline.status, +hullgrind::outline_t::STATUS_OK);
  ASSERT_EQ(c.outline.num_loops, 1);
  EXPECT_FALSE(c.outline.loops[0].hole);
}

TEST(OutlineServiceCompute, CloudWithoutPartIsNoLoopWithReason) {
  auto cloud = hg::test::plate_with_hole(0.1, 0.1, 1, 1, 1, 1, 0.01);
  cloud.status = hullgrind::plate_cloud_t::STATUS_NO_PART;
  cloud.status_text = "nothing above the table";
  auto c = os::compute(cloud, {});
  EXPECT_EQ(c.outline.status, +hullgrind::outline_t::STATUS_NO_LOOP);
  EXPECT_NE(c.outline.error_text.find("nothing above the table"), std::string::npos);
  EXPECT_EQ(c.outline.num_loops, 0);
  EXPECT_TRUE(c.outline.loops.empty());
  EXPECT_TRUE(c.poses.empty());
}

TEST(OutlineServiceCompute, TooFewCollinearOrInvalidPointsAreErrorsNotLoops) {
  hullgrind::plate_cloud_t two{};
  two.status = hullgrind::plate_cloud_t::STATUS_OK;
  two.n = 2;
  two.u = {0, 1};
  two.v = {0, 1};
  two.part = {0, 0};
  auto a = os::compute(two, {});
  EXPECT_EQ(a.outline.status, +hullgrind::outline_t::STATUS_NO_LOOP);
  EXPECT_EQ(a.outline.num_loops, 0);

  hullgrind::plate_cloud_t line = two;
  line.n = 50;
  line.u.clear(), line.v.clear(), line.part.assign(50, 0);
  for (int i = 0; i < 50; ++i) line.u.push_back(0.01f * i), line.v.push_back(0.02f * i);
  auto b = os::compute(line, {});
  EXPECT_NE(b.outline.status, +hullgrind::outline_t::STATUS_OK);
  EXPECT_FALSE(b.outline.error_text.empty());
  EXPECT_EQ(b.outline.num_loops, 0);

  // A non-finite point (a no-return pixel) is skipped, as the core does for every input: the outline is
  // that of the same cloud without it.
  auto nan = hg::test::plate_with_hole(0.1, 0.1, 1, 1, 1, 1, 0.01);
  auto without = nan;
  without.u.erase(without.u.begin() + 7), without.v.erase(without.v.begin() + 7),
      without.part.erase(without.part.begin() + 7);
  without.n -= 1;
  nan.u[7] = std::numeric_limits<float>::quiet_NaN();
  auto d = os::compute(nan, {});
  auto e = os::compute(without, {});
  EXPECT_EQ(d.outline.status, +hullgrind::outline_t::STATUS_OK) << d.outline.error_text;
  ASSERT_EQ(d.outline.num_loops, e.outline.num_loops);
  EXPECT_GT(d.outline.num_loops, 0);
  for (int i = 0; i < d.outline.num_loops; ++i) {
    EXPECT_EQ(d.outline.loops[std::size_t(i)].hole, e.outline.loops[std::size_t(i)].hole);
    EXPECT_EQ(d.outline.loops[std::size_t(i)].u, e.outline.loops[std::size_t(i)].u);
    EXPECT_EQ(d.outline.loops[std::size_t(i)].v, e.outline.loops[std::size_t(i)].v);
  }
}

}  // namespace
