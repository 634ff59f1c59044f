// Unit tests of each planning step against independent (analytic) expectations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <sstream>
#include <string_view>

#include "partgen/synth.hpp"
#include "path_planner/io.hpp"
#include "path_planner/pipeline.hpp"
#include "robot_bridge/path.hpp"
#include "tests/path_planner/truth.hpp"

using namespace hg::path_planner;

namespace {

constexpr double kPi = 3.14159265358979323846;
double deg(double d) { return d * kPi / 180; }

using hg::path_planner::test::densify;
using hg::path_planner::test::turn;
double ring_dist(const Vec2& p, const Ring& r) { return hg::path_planner::test::ring_distance(p, r); }
// Distance from p to the nearest vertex of `r`.
double vertex_dist(const Vec2& p, const Ring& r) {
  double d = 1e300;
  for (const Vec2& v : r) d = std::min(d, (p - v).norm());
  return d;
}

Ring rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }
Ring rotated(const Ring& r, double a, const Vec2& c) {
  const Eigen::Rotation2Dd R(a);
  Ring o;
  for (const Vec2& p : r) o.push_back(c + R * (p - c));
  return o;
}
Ring circle(const Vec2& c, double R, int n, bool cw = false) {
  Ring o;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * kPi * k / n * (cw ? -1 : 1);
    o.emplace_back(c.x() + R * std::cos(t), c.y() + R * std::sin(t));
  }
  return o;
}

// A pixel staircase of a polygon (partgen::pixel_staircase): symmetric +-pitch/2 error, no inward bias (so
// tests of it turn edge compensation off).
Ring staircase(const Ring& poly, double pitch) { return hg::partgen::pixel_staircase(poly, pitch); }


// Turn at each detected corner of a smoothed ring, measured from the corner to the ring points `reach`
// away on both sides (the fitted straight runs).
std::vector<std::pair<Vec2, double>> corner_turns(const SmoothedRing& s, double reach) {
  std::vector<std::pair<Vec2, double>> out;
  const long n = long(s.points.size());
  for (long i = 0; i < n; ++i) {
    if (!s.corner[i]) continue;
    const Vec2 c = s.points[i];
    long b = i - 1, f = i + 1;
    while ((s.points[((b % n) + n) % n] - c).norm() < reach && i - b < n) --b;
    while ((s.points[f % n] - c).norm() < reach && f - i < n) ++f;
    out.push_back({c, turn(c - s.points[((b % n) + n) % n], s.points[f % n] - c)});
  }
  return out;
}

SmoothOptions no_compensation() {
  SmoothOptions o;
  o.edge_compensation = false;
  return o;
}

}  // namespace

// ---- 1. smoothing ----

TEST(PathPlannerSmooth, PitchEstimateOfAStaircase) {
  const double p = 0.001;
  const Ring s = staircase(rotated(rect(0, 0, 0.3, 0.2), 0.2, {0.15, 0.1}), p);
  EXPECT_NEAR(estimate_pitch({{false, s}}), p, 0.05 * p);
  // A drawn polygon with a few long edges has no pitch: nothing to de-noise.
  EXPECT_EQ(estimate_pitch({{false, rect(0, 0, 0.3, 0.2)}}), 0.0);
}

TEST(PathPlannerSmooth, RotatedRectangleStaysOnTheEdgeAndKeepsItsCorners) {
  const double p = 0.001;
  for (double angle : {0.13, 0.35, 0.61}) {
    const Ring truth = rotated(rect(0.02, 0.03, 0.32, 0.21), angle, {0.17, 0.12});
    const Ring stairs = staircase(truth, p);
    const SmoothedRing s = smooth_ring(stairs, p, no_compensation());
    int far = 0;
    double worst = 0;
    for (const Vec2& q : densify(s.points, p / 2)) {
      if (vertex_dist(q, truth) < 0.005) continue;  // away from corners
      worst = std::max(worst, ring_dist(q, truth));
      ++far;
    }
    EXPECT_GT(far, 500);
    EXPECT_LT(worst, 0.0005) << "angle " << angle;
    // Raw staircase for comparison: its error reaches ~pitch/sqrt(2).
    const auto turns = corner_turns(s, 0.015);
    ASSERT_EQ(turns.size(), 4u) << "angle " << angle;
    for (const auto& [c, t] : turns) {
      EXPECT_LT(vertex_dist(c, truth), 0.0015);
      EXPECT_NEAR(t, deg(90), deg(5)) << "angle " << angle;
    }
  }
}

TEST(PathPlannerSmooth, AcuteAndObtuseCornersKeepTheirAngle) {
  const double p = 0.001;
  // Trapezoid with 60 and 120 degree turns, rotated against the grid.
  const double h = 0.15, inset = h / std::tan(deg(60));
  const Ring truth = rotated({{0, 0}, {0.4, 0}, {0.4 - inset, h}, {inset, h}}, 0.21, {0.2, 0.07});
  const SmoothedRing s = smooth_ring(staircase(truth, p), p, no_compensation());
  const auto turns = corner_turns(s, 0.015);
  ASSERT_EQ(turns.size(), 4u);
  for (const auto& [c, t] : turns) {
    // The true turn at the nearest true vertex.
    std::size_t k = 0;
    for (std::size_t i = 1; i < truth.size(); ++i)
      if ((truth[i] - c).norm() < (truth[k] - c).norm()) k = i;
    const std::size_t n = truth.size();
    const double expected = turn(truth[k] - truth[(k + n - 1) % n], truth[(k + 1) % n] - truth[k]);
    EXPECT_NEAR(t, expected, deg(5));
  }
}

TEST(PathPlannerSmooth, CircleHasNoCornersAndKeepsItsRadius) {
  const double p = 0.001;
  for (double R : {0.008, 0.012, 0.025, 0.05}) {  // down to 8 pitches: a tight arc is not a corner
    const Ring truth = circle({0.10031, 0.10072}, R, 2000);
    const SmoothedRing s = smooth_ring(staircase(truth, p), p, no_compensation());
    int corners = 0;
    for (auto c : s.corner) corners += c;
    EXPECT_EQ(corners, 0) << "R " << R;
    for (const Vec2& q : densify(s.points, p / 2)) EXPECT_NEAR((q - Vec2(0.10031, 0.10072)).norm(), R, 0.0005) << "R " << R;
  }
}

// An L plate whose inner corner is a fillet of radius R and whose outer corner opposite is rounded with R
// too, as a noisy staircase (per-vertex noise 0.45 pitch at the pm806's 1.34 mm: its edge). Under that
// noise the greedy pieces used to share a short fillet out between the two straights, which then met at
// their intersection, or the corner detector took the fillet for a corner: the path cut 0.41 R across the
// inner fillet into the material. Both fillets must be followed along their whole length (within 1 mm),
// for every noise draw. (R10, 7.5 pixels, is at the limit: 6 of these 8 draws tell it from a sharp corner.)
TEST(PathPlannerSmooth, NoisyFilletsAreFollowedNotCutToACorner) {
  const double p = 0.00134, sigma = 0.45 * p;
  for (double R : {0.015, 0.025, 0.040}) {
    // Legs 300 x 200, width 60; (0, 0) is the rounded outer corner, the fillet is at (60, 60).
    auto arc = [&](Ring& ring, const Vec2& c, double a0, double a1) {
      for (int k = 0; k <= 64; ++k) {
        const double a = a0 + (a1 - a0) * k / 64;
        ring.push_back(c + R * Vec2(std::cos(a), std::sin(a)));
      }
    };
    Ring truth;
    arc(truth, {R, R}, kPi, 1.5 * kPi);
    truth.push_back({0.30, 0}), truth.push_back({0.30, 0.06});
    arc(truth, {0.06 + R, 0.06 + R}, 1.5 * kPi, kPi);
    truth.push_back({0.06, 0.20}), truth.push_back({0, 0.20});
    const std::vector<Vec2> sharp{{0.30, 0}, {0.30, 0.06}, {0.06, 0.20}, {0, 0.20}};
    const Ring shifted = rotated(truth, 0.1, {0.15, 0.1});
    std::vector<Vec2> corners;
    for (const Vec2& c : sharp) corners.push_back(rotated({c}, 0.1, {0.15, 0.1})[0]);
    for (unsigned seed = 1; seed <= 8; ++seed) {
      std::mt19937 rng(seed);
      std::normal_distribution<double> noise(0, sigma);
      Ring noisy = staircase(shifted, p);
      for (Vec2& q : noisy) q += Vec2(noise(rng), noise(rng));
      SmoothOptions o = no_compensation();
      o.noise = estimate_noise({Loop{false, noisy}}, o);
      const SmoothedRing s = smooth_ring(noisy, p, o);
      double worst = 0;
      int checked = 0;
      for (const Vec2& q : densify(s.points, p / 2)) {
        bool near_corner = false;
        for (const Vec2& c : corners) near_corner |= (q - c).norm() < 0.01;
        if (near_corner) continue;
        worst = std::max(worst, ring_dist(q, shifted));
        ++checked;
      }
      EXPECT_GT(checked, 500);
      EXPECT_LT(worst, 0.001) << "R " << R << " seed " << seed;
      std::printf("  R %2.0f mm, seed %u: worst %.2f mm\n", R * 1e3, seed, worst * 1e3);
    }
  }
}

TEST(PathPlannerSmooth, EdgeCompensationMovesOutwardByHalfAPitch) {
  // A staircase whose points are the outermost pixel centres of a square at 0..0.1: pixel centres lie at
  // half a pitch inside the edge. Compensation must bring the straight runs back onto the edge.
  const double p = 0.001;
  const Ring inner = staircase(rect(0.0005, 0.0005, 0.0995, 0.0995), p);
  const SmoothedRing s = smooth_ring(inner, p, SmoothOptions{});
  const Ring truth = rect(0, 0, 0.1, 0.1);
  for (const Vec2& q : densify(s.points, p / 2)) {
    if (vertex_dist(q, truth) < 0.005) continue;
    EXPECT_LT(ring_dist(q, truth), 1e-4);
  }
}

// ---- 2. offset ----

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

// ---- 3. resample ----

TEST(PathPlannerResample, FixedStepAndCornersKept) {
  const Ring sq = rect(0, 0, 0.1, 0.05);
  const double step = 0.003;
  const SampledRing s = resample_ring(sq, step, deg(10));
  // Every corner is a waypoint; each side of length L has ceil(L/step) equal steps.
  for (const Vec2& c : sq) EXPECT_LT(vertex_dist(c, s.points), 1e-12);
  const std::size_t expected = 2 * std::size_t(std::ceil(0.1 / step)) + 2 * std::size_t(std::ceil(0.05 / step));
  EXPECT_EQ(s.points.size(), expected);
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    const double d = (s.points[(i + 1) % s.points.size()] - s.points[i]).norm();
    EXPECT_LE(d, step + 1e-12);
    EXPECT_GT(d, 0.9 * step);  // 0.1 / 34 and 0.05 / 17 are both close to the step
    EXPECT_LT(ring_dist(s.points[i], sq), 1e-12);
  }
  int corners = 0;
  for (auto c : s.corner) corners += c;
  EXPECT_EQ(corners, 4);
}

TEST(PathPlannerResample, CircleSpacingAlongTheArc) {
  const Ring c = circle({0, 0}, 0.05, 3000);
  const SampledRing s = resample_ring(c, 0.002, deg(10));
  const double L = ring_length(c);
  EXPECT_EQ(s.points.size(), std::size_t(std::ceil(L / 0.002 - 1e-9)));
  for (std::size_t i = 0; i < s.points.size(); ++i)
    EXPECT_NEAR((s.points[(i + 1) % s.points.size()] - s.points[i]).norm(), L / double(s.points.size()), 1e-6);
}

// ---- 4. orientation and direction ----

TEST(PathPlannerOrient, ToolAxisTiltEqualsTheChamferAngle) {
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
      EXPECT_NEAR(z.head<2>().dot(t), 0, 1e-12);      // tilt is in the plane of the edge normal
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
    const auto path = sequence(loops, Vec2(-1, -1), o);
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

// ---- 5. leads, approach, order ----

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
  for (int k = 0; k < 3; ++k) loops.push_back({resample_ring(rect(k * 0.3, 0, k * 0.3 + 0.1, 0.1), 0.01, deg(10)), false, k});
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
  o.safe_height = 0.07;
  o.z = 0.001;
  const auto path = sequence(loops, Vec2(0, 0), o);
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
      EXPECT_DOUBLE_EQ(w.speed, o.travel_speed);
    }
    if (w.kind == kGrind || w.kind == kLeadIn || w.kind == kLeadOut) {
      EXPECT_NEAR(w.position.z(), 0.001, 1e-12);
      EXPECT_DOUBLE_EQ(w.speed, o.grind_speed);
    }
  }
  EXPECT_EQ(travel, 1);
}

// ---- 6. frames ----

TEST(PathPlannerFrame, KnownPointsIntoTheBaseFrame) {
  // Camera 1.2 m above the base at x = 0.5, looking down (roll = pi): camera x = base x, camera y = -base y.
  const Eigen::Isometry3d cam = pose_from_xyz_rpy(Vec3(0.5, 0, 1.2), Vec3(kPi, 0, 0));
  // Plate 1 m in front of the camera, u = camera x, v = camera -y, normal toward the camera.
  const Plane plane{Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1)};
  const Eigen::Isometry3d T = plate_to_base(plane, cam);
  // plate (0.1, 0.2, 0) -> camera (0.1, -0.2, 1) -> base (0.6, 0.2, 0.2)
  EXPECT_LT((T * Vec3(0.1, 0.2, 0) - Vec3(0.6, 0.2, 0.2)).norm(), 1e-12);
  EXPECT_LT((T * Vec3(0, 0, 0.05) - Vec3(0.5, 0, 0.25)).norm(), 1e-12);  // plate up = base up
  const std::vector<PlateWaypoint> p = {{Vec3(0.1, 0.2, 0), tool_orientation(Vec2(1, 0), Vec2(0, -1), 0), 0.1, kGrind, 0}};
  const auto b = to_base(p, T);
  EXPECT_LT((b[0].orientation.toRotationMatrix().col(2) - Vec3(0, 0, -1)).norm(), 1e-12);  // tool points down
  EXPECT_LT((b[0].orientation.toRotationMatrix().col(0) - Vec3(1, 0, 0)).norm(), 1e-12);
}

TEST(PathPlannerFrame, MatrixAndXyzRpyConfigAgree) {
  const Eigen::Isometry3d ref = pose_from_xyz_rpy(Vec3(0.3, -0.2, 1.1), Vec3(3.0, 0.1, -0.4));
  std::string m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.17g", ref.matrix()(r, c));
      if (!m.empty()) m += ',';
      m += buf;
    }
  auto defaults = planner_params();
  auto lookup = [&](std::map<std::string, std::string> over) {
    return ParamLookup{[=](const std::string& k) {
                         if (over.count(k)) return over.at(k);
                         for (auto& p : defaults)
                           if (p.name == k) return p.default_value;
                         return std::string();
                       },
                       [=](const std::string& k) {
                         std::string text = over.count(k) ? over.at(k) : "";
                         if (text.empty())
                           for (auto& p : defaults)
                             if (p.name == k) text = p.default_value;
                         std::vector<double> v;
                         std::stringstream ss(text);
                         std::string item;
                         while (std::getline(ss, item, ',')) v.push_back(std::stod(item));
                         return v;
                       }};
  };
  const PlannerConfig a = config_from(lookup({{"camera-to-base", m}}));
  const PlannerConfig b = config_from(lookup({{"camera-xyz", "0.3,-0.2,1.1"}, {"camera-rpy", "3.0,0.1,-0.4"}}));
  EXPECT_LT((a.camera_to_base.matrix() - b.camera_to_base.matrix()).norm(), 1e-12);
  EXPECT_THROW(config_from(lookup({{"camera-to-base", "1,0,0,0, 0,2,0,0, 0,0,1,0, 0,0,0,1"}})), hg::runtime::ConfigError);
  EXPECT_THROW(config_from(lookup({{"tool-radius", "-1"}})), hg::runtime::ConfigError);
}

TEST(PathPlannerFrame, NormalPointingDownIsTurnedUpWithoutMovingThePlate) {
  const Eigen::Isometry3d cam = pose_from_xyz_rpy(Vec3(0.5, 0, 1.2), Vec3(kPi, 0, 0));
  OutlineInput in;
  in.plane = {Vec3(0.01, 0.02, 1), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};  // normal away from the camera
  in.loops = {{false, rect(0, 0, 0.2, 0.1)}};
  auto to3 = [](const Plane& pl, const Vec2& p) { return Vec3(pl.origin + p.x() * pl.u + p.y() * pl.v); };
  std::vector<Vec3> before;
  for (const Vec2& p : in.loops[0].points) before.push_back(to3(in.plane, p));
  normalize_up(in, cam);
  EXPECT_GT((cam.linear() * in.plane.normal).z(), 0);
  EXPECT_GT(in.plane.u.cross(in.plane.v).dot(in.plane.normal), 0);
  EXPECT_GT(signed_area(in.loops[0].points), 0);  // still canonical
  for (const Vec2& p : in.loops[0].points) {
    double best = 1e9;
    for (const Vec3& q : before) best = std::min(best, (to3(in.plane, p) - q).norm());
    EXPECT_LT(best, 1e-15);
  }
}

TEST(PathPlannerFrame, FlipMirrorsAcrossThePrincipalAxisThroughTheCentroid) {
  // 0.4 x 0.2 plate with a 0.04 x 0.04 hole centred at (0.2, 0.05): symmetric about x = 0.2, so the
  // principal axis is exactly x.
  Ring hole = rect(0.18, 0.03, 0.22, 0.07);
  std::reverse(hole.begin(), hole.end());
  const std::vector<Loop> loops = {{false, rect(0, 0, 0.4, 0.2)}, {true, hole}};
  const double A = 0.08 - 0.0016;
  const double cx = 0.2, cy = (0.08 * 0.1 - 0.0016 * 0.05) / A;
  const AreaMoments m = area_moments(loops);
  EXPECT_NEAR(m.area, A, 1e-15);
  EXPECT_NEAR(m.centroid.x(), cx, 1e-12);
  EXPECT_NEAR(m.centroid.y(), cy, 1e-12);
  EXPECT_NEAR(std::abs(m.major_axis.x()), 1, 1e-12);
  const auto f = mirror_for_flip(loops);
  EXPECT_LT(signed_area(f[1].points), 0);  // holes stay clockwise
  EXPECT_GT(signed_area(f[0].points), 0);
  Vec2 hc = Vec2::Zero();
  for (const Vec2& p : f[1].points) hc += p / 4;
  // Mirror of (0.1, 0.05) across the axis through the centroid.
  const Eigen::Matrix2d Rf = 2 * m.major_axis * m.major_axis.transpose() - Eigen::Matrix2d::Identity();
  EXPECT_LT((hc - (m.centroid + Rf * (Vec2(0.2, 0.05) - m.centroid))).norm(), 1e-12);
  EXPECT_NEAR(hc.x(), 0.2, 1e-12);
  EXPECT_NEAR(hc.y(), 2 * cy - 0.05, 1e-12);
  EXPECT_NEAR(area_moments(f).area, A, 1e-12);
}

// ---- 6b. corner speeds ----

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
  std::printf("  %d of 300 random paths refused by the bridge before, none after; %d speeds lowered\n", refused_before, slowed);
}

// ---- 7. validation ----

namespace {
std::vector<Waypoint> square_path(double z) {
  std::vector<Waypoint> p;
  const Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  p.push_back({Vec3(0, 0, z + 0.05), q, 0.1, kApproach, -1});
  p.push_back({Vec3(0, 0, z), q, 0.05, kApproach, 0});
  p.push_back({Vec3(0.01, 0, z), q, 0.02, kLeadIn, 0});
  for (Vec2 c : {Vec2(0.1, 0), Vec2(0.1, 0.1), Vec2(0.01, 0.1), Vec2(0.01, 0)}) p.push_back({Vec3(c.x(), c.y(), z), q, 0.02, kGrind, 0});
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
  EXPECT_NE(validate(p, L, up, start).find("waypoint 4: position (0.6000, 0.1000, 0.0100) m is outside the workspace"), std::string::npos);
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
  std::snprintf(want, sizeof want, "waypoint 1 (approach): the corner (radius %.6f mm) at 0.020000 m/s needs %.6f m/s^2",
                r * 1e3, need);
  EXPECT_NE(validate(square_path(0.01), L, up, start).find(want), std::string::npos) << validate(square_path(0.01), L, up, start);
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

// ---- composition ----

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
// test_coverage.cpp). Clockwise (canonical for a hole).
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
  jp.chamfer_angle = 0;
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
    EXPECT_NEAR(tilt, cfg.defaults.chamfer_angle, 1e-9);
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
  EXPECT_EQ(r.reason, "tool_radius must be > 0 m");
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

TEST(PathPlannerIo, OutlineJsonErrorsNameThePlace) {
  const Plane pl;
  try {
    read_outline_json("{\"loops\": [", pl);  // 11 bytes: the error is at the end, byte 12
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("byte 12"), std::string::npos) << e.what();
  }
  try {
    read_outline_json(R"({"loops": [{"hole": false, "points": [[0,0],[1,0],["x",1]]}]})", pl);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("loops[0].points[2]"), std::string::npos) << e.what();
  }
  const OutlineInput in = read_outline_json(
      R"({"plane": {"origin": [1,2,3], "normal": [0,0,1], "u": [1,0,0], "v": [0,1,0]},
          "loops": [{"hole": true, "area": 1, "perimeter": 4, "points": [[0,0],[0,1],[1,1],[1,0]]}]})", pl);
  ASSERT_EQ(in.loops.size(), 1u);
  EXPECT_TRUE(in.loops[0].hole);
  EXPECT_EQ(in.plane.origin, Vec3(1, 2, 3));
  EXPECT_EQ(in.loops[0].points[2], Vec2(1, 1));
}
