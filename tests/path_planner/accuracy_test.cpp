// Accuracy against ground truth: partgen's exact hull-part shapes, rasterised to a pixel cloud, outlined by
// the real outline core (the staircase the planner gets in production), then smoothed and offset here.
// Errors are measured against the exact polygon, away from its corners (vertices turning >= 20 deg).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "outline_core/outline.hpp"
#include "sim/partgen/shapes.hpp"
#include "sim/partgen/synth.hpp"
#include "path_planner/pipeline.hpp"
#include "robot_bridge/path.hpp"
#include "tests/path_planner/truth.hpp"

using namespace hg::path_planner;
namespace pg = hg::partgen;

namespace {

constexpr double kPitch = 0.0005;  // 2048 px across about 1 m (the high-density camera)
constexpr double kTool = 0.01;
constexpr double kCornerZone = 0.005;  // "away from corners": nearest true point farther than this from a corner

struct Truth {
  std::vector<Ring> rings;
  std::vector<Vec2> corners;
  std::vector<std::pair<Vec2, double>> straight_corners;  // corners between two edges >= 15 mm, with their turn
};

using hg::path_planner::test::turn;

Truth truth_of(const pg::PolygonWithHoles& poly) {
  Truth t;
  t.rings.push_back(poly.outer);
  for (const auto& h : poly.holes) t.rings.push_back(h);
  for (const Ring& r : t.rings) {
    const std::size_t n = r.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 a = r[i] - r[(i + n - 1) % n], b = r[(i + 1) % n] - r[i];
      const double tr = turn(a, b);
      if (std::abs(tr) < 20 * M_PI / 180) continue;
      t.corners.push_back(r[i]);
      if (a.norm() >= 0.015 && b.norm() >= 0.015) t.straight_corners.push_back({r[i], tr});
    }
  }
  return t;
}

// Distance from p to the true boundary, and whether the nearest true point is near a corner.
std::pair<double, bool> to_truth(const Vec2& p, const Truth& t) {
  double best = 1e300;
  Vec2 at = p;
  for (const Ring& r : t.rings)
    for (std::size_t i = 0; i < r.size(); ++i) {
      const Vec2 a = r[i], ab = r[(i + 1) % r.size()] - a;
      const double s = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      const double d = (a + s * ab - p).norm();
      if (d < best) best = d, at = a + s * ab;
    }
  bool near = false;
  for (const Vec2& c : t.corners) near |= (at - c).norm() < kCornerZone;
  return {best, near};
}

// Result polylines are checked every 0.25 mm along their segments: a smoothed ring represents a straight
// run by its end points, so the error is checked along the whole run, not only at vertices.
Ring densify(const Ring& r) { return hg::path_planner::test::densify(r, 0.00025); }

struct Case {
  std::vector<Loop> loops;
  Truth truth;
  int holes = 0;
};

Case make_case(const std::string& shape, double rotation, bool noisy, unsigned seed) {
  const pg::Scene scene = pg::single_part_scene(pg::make_shape(shape), rotation);
  pg::CloudOptions o;
  o.pitch = kPitch;
  if (noisy) {
    o.in_plane_sigma = 0.0003;
    o.jagged = true;
    o.seed = seed;
  }
  const pg::Cloud cloud = pg::synthesize(scene, o);
  std::vector<hg::outline::Vec2> pts(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) pts[i] = {cloud.xyz[3 * i], cloud.xyz[3 * i + 1]};
  hg::outline::Options opt;
  if (noisy) opt.alpha_radius = 2 * kPitch;  // jittered points: a fixed radius above the gaps noise opens
  const hg::outline::Result r = hg::outline::compute_outline(pts, opt);
  Case c;
  for (const auto& l : r.loops) {
    Loop loop;
    loop.hole = l.hole;
    for (const auto& p : l.points) loop.points.emplace_back(p.x, p.y);
    c.loops.push_back(std::move(loop));
  }
  make_canonical(c.loops);
  c.truth = truth_of(scene.parts[0].placed);
  c.holes = scene.parts[0].shape.exact_hole_count;
  return c;
}

struct Stats {
  double max = 0;
  Vec2 at = Vec2::Zero();
  int n = 0;
  void add(double e, const Vec2& p) {
    if (e > max) max = e, at = p;
    ++n;
  }
};

void check_shape(const std::string& shape, bool noisy, double smooth_limit, double offset_limit, unsigned seed = 11) {
  const Case c = make_case(shape, 0.3, noisy, seed);
  // Noise-free staircases give the pitch by themselves. Noise of 0.6 pitch erases the lattice from the
  // boundary (docs/path_planner.md): the estimate must say so (0) rather than guess, and the pitch is
  // configured (pixel_pitch), as a deployment does from the camera's intrinsics and distance.
  const double estimated = estimate_pitch(c.loops);
  if (noisy) {
    EXPECT_EQ(estimated, 0.0) << shape;
  } else {
    ASSERT_NEAR(estimated, kPitch, 0.02 * kPitch) << shape;
  }
  const double pitch = noisy ? kPitch : estimated;
  int holes = 0;
  for (const Loop& l : c.loops) holes += l.hole;
  ASSERT_EQ(holes, c.holes) << shape;
  Stats smooth, offset;
  int corners_checked = 0;
  std::vector<std::uint8_t> found(c.truth.straight_corners.size(), 0);
  // As plan() does: the noise level pooled over the part's loops.
  SmoothOptions options;
  options.noise = estimate_noise(c.loops, options);
  for (const Loop& l : c.loops) {
    const SmoothedRing s = smooth_ring(l.points, pitch, options);
    for (const Vec2& p : densify(s.points)) {
      auto [d, near] = to_truth(p, c.truth);
      if (!near) smooth.add(d, p);
    }
    // Corners between straight edges keep their angle.
    const long n = long(s.points.size());
    for (long i = 0; i < n; ++i) {
      if (!s.corner[i]) continue;
      for (std::size_t k = 0; k < c.truth.straight_corners.size(); ++k) {
        const auto& [tc, tturn] = c.truth.straight_corners[k];
        if ((s.points[i] - tc).norm() > 0.003) continue;
        long b = i - 1, f = i + 1;
        while ((s.points[((b % n) + n) % n] - s.points[i]).norm() < 0.008 && i - b < n) --b;
        while ((s.points[f % n] - s.points[i]).norm() < 0.008 && f - i < n) ++f;
        const double got = turn(s.points[i] - s.points[((b % n) + n) % n], s.points[f % n] - s.points[i]);
        EXPECT_NEAR(got * 180 / M_PI, tturn * 180 / M_PI, 5.0) << shape << " corner at " << tc.transpose();
        found[k] = 1;
        ++corners_checked;
      }
    }
    const auto off = offset_ring(s.points, l.hole, kTool, 1e-5);
    ASSERT_FALSE(off.empty()) << shape;
    for (const Ring& r : off)
      for (const Vec2& p : densify(r)) {
        auto [d, near] = to_truth(p, c.truth);
        if (!near) offset.add(std::abs(d - kTool), p);
      }
  }
  for (std::size_t k = 0; k < found.size(); ++k)
    EXPECT_TRUE(found[k]) << shape << ": corner at " << c.truth.straight_corners[k].first.transpose() << " not found";
  std::printf(
      "  %-16s %-10s smoothed max %.3f mm (%d pts)  offset max %.3f mm (%d pts)  corners %d  (worst at %.4f %.4f / %.4f %.4f)\n",
      shape.c_str(), noisy ? ("noisy/" + std::to_string(seed)).c_str() : "noise-free", smooth.max * 1e3, smooth.n,
      offset.max * 1e3, offset.n, corners_checked, smooth.at.x(), smooth.at.y(), offset.at.x(), offset.at.y());
  EXPECT_GT(smooth.n, 100);
  EXPECT_LE(smooth.max, smooth_limit) << shape << " seed " << seed;
  EXPECT_LE(offset.max, offset_limit) << shape << " seed " << seed;

  // The whole pipeline: every hole gets a grind loop.
  OutlineInput in;
  in.plane = {Vec3(0, 0, 1.19), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1)};
  in.loops = c.loops;
  PlannerConfig cfg;
  cfg.camera_to_base = pose_from_xyz_rpy(Vec3(0.5, 0, 1.2), Vec3(M_PI, 0, 0));
  cfg.limits.workspace_min = Vec3(-2, -2, 0);
  cfg.limits.workspace_max = Vec3(2, 2, 2);
  cfg.limits.table_z = 0;
  // Planned whatever the coverage check finds (small_hole: skip): this test is about accuracy and what the
  // robot bridge accepts. The check holds the path to the smoothed edge, whose lumps on the noisy D30 holes
  // leave 20-44 mm per hole farther than 5 + 0.2 mm from a 5 mm tool's path (0.4-2.8 mm even at + 1.0 mm),
  // and a 0.4 mm dent one flipped noise-free D100 hole (docs/path_planner.md, Coverage: a known gap).
  cfg.small_hole = SmallHolePolicy::Skip;
  JobParams jp;
  jp.tool_radius = 0.005;  // the smallest holes are 30 mm across
  const PlanResult res = plan(in, jp, cfg, std::nullopt);
  ASSERT_TRUE(res.ok) << shape << ": " << res.reason;
  std::vector<int> ground(c.loops.size(), 0);
  for (const Waypoint& w : res.path)
    if (w.kind == kGrind) ++ground[w.loop];
  for (std::size_t k = 0; k < c.loops.size(); ++k) EXPECT_GT(ground[k], 10) << shape << " loop " << k;

  // The robot bridge runs what the planner publishes: its own check (robot_bridge/path.cpp, linked) with
  // its default limits (max_accel 2 m/s^2, max_speed 0.25 m/s), from the position the planner started
  // from. Job variants: both tool radii, both directions, flipped, robot at home or elsewhere.
  hg::robot_bridge::Limits bl;
  bl.workspace_min = cfg.limits.workspace_min;
  bl.workspace_max = cfg.limits.workspace_max;
  bl.table_z = cfg.limits.table_z;
  ASSERT_EQ(cfg.limits.max_accel, bl.max_accel);
  struct Variant {
    double tool;
    Direction dir;
    bool flipped;
    std::optional<Vec3> robot;
    double grind_speed;  // 0: the default 0.02 m/s; 0.1 m/s needs corner radii of 5 mm
  };
  const Variant variants[] = {{0.005, Direction::Climb, false, std::nullopt, 0},
                              {0.01, Direction::Conventional, false, std::nullopt, 0},
                              {0.005, Direction::Climb, true, Vec3(0.2, -0.3, 0.15), 0},
                              {0.005, Direction::Climb, false, std::nullopt, 0.1}};
  for (const Variant& v : variants) {
    JobParams j;
    j.grind_speed = v.grind_speed;
    j.tool_radius = v.tool;
    j.direction = v.dir;
    j.flipped = v.flipped;
    const PlanResult pr = plan(in, j, cfg, v.robot);
    ASSERT_TRUE(pr.ok) << shape << ": " << pr.reason;
    hg::robot_bridge::Path bp;
    double slowest = 1e9, grind_time = 0, grind_time_nominal = 0;
    for (std::size_t i = 0; i < pr.path.size(); ++i) {
      const Waypoint& w = pr.path[i];
      bp.position.push_back(w.position);
      bp.orientation.push_back(w.orientation);
      bp.speed.push_back(w.speed);
      bp.kind.push_back(w.kind);
      if (w.kind == kGrind) {
        const double len = (w.position - pr.path[i - 1].position).norm();
        slowest = std::min(slowest, w.speed);
        grind_time += len / w.speed;
        grind_time_nominal += len / pr.params.grind_speed;
      }
    }
    const Vec3 start = v.robot ? *v.robot : cfg.home;
    EXPECT_EQ(hg::robot_bridge::check_path(bp, {start, Eigen::Quaterniond::Identity()}, bl), "")
        << shape << (noisy ? " noisy" : "") << " tool " << v.tool << (v.flipped ? " flipped" : "");
    std::printf(
        "    tool %2.0f mm %-12s %-7s %.2f m/s: %5zu waypoints, %3d speeds lowered, slowest grind %.4f m/s, grind time %.1f s (%.1f s at constant speed)\n",
        v.tool * 1e3, v.dir == Direction::Climb ? "climb" : "conventional", v.flipped ? "flipped" : "",
        pr.params.grind_speed, pr.path.size(), pr.slowed, slowest, grind_time, grind_time_nominal);
  }
}

}  // namespace

// Targets of issue 5: smoothed loop within 0.5 mm of the true edge (noisy parts); offset path within
// 0.3 mm (noise-free) and 1.0 mm (noisy) of the true offset; corners within 5 degrees.
TEST(PathPlannerAccuracy, NoiseFreeParts) {
  for (const std::string& s : pg::shape_names()) check_shape(s, false, 0.0005, 0.0003);
}

// Six noise draws each: the targets must hold for the noise, not for one draw of it (the l-bracket's R15
// fillet met 0.5 mm with seed 11 but reached 0.9-1.0 mm with seeds 12, 14 and 16 before fillets were fitted).
TEST(PathPlannerAccuracy, NoisyParts) {
  for (unsigned seed = 11; seed <= 16; ++seed)
    for (const std::string& s : pg::shape_names()) check_shape(s, true, 0.0005, 0.001, seed);
}
