// Unit tests of the smoothing step (smooth_ring end to end, estimate_pitch), against independent
// (analytic) expectations.
#include <gtest/gtest.h>

#include "tests/path_planner/step_shapes.hpp"

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
    for (const Vec2& q : densify(s.points, p / 2))
      EXPECT_NEAR((q - Vec2(0.10031, 0.10072)).norm(), R, 0.0005) << "R " << R;
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
