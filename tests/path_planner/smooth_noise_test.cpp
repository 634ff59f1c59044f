// Noise and pitch estimation (path_planner/smooth/noise.cpp): rings with a known added noise (several
// seeds), clean rings, staircases of known pitch.
#include <gtest/gtest.h>

#include "sim/partgen/synth.hpp"
#include "tests/path_planner/stage_rings.hpp"

using namespace hg::path_planner;
using namespace hg::path_planner::stage_test;

namespace {

// A circle of n vertices, radius R, each moved radially by Gaussian noise of sigma.
Ring noisy_circle(double R, int n, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, sigma);
  Ring r;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * kPi * k / n;
    r.push_back((R + g(rng)) * Vec2(std::cos(a), std::sin(a)));
  }
  return r;
}

}  // namespace

// estimate_noise is the noise of a window mean: sigma / sqrt(window) for independent per-vertex noise
// across the edge. 20 000 vertices: the median of ~500 independent windows, within 20 %.
TEST(PathPlannerSmoothNoise, WindowMeanNoiseOfAKnownNoise) {
  const SmoothOptions o;
  const double window = std::max(5.0, std::round(2 * o.window_pitches));
  for (double sigma : {0.0001, 0.0004}) {
    for (unsigned seed = 1; seed <= 6; ++seed) {
      SCOPED_TRACE("sigma " + std::to_string(sigma) + " seed " + std::to_string(seed));
      const double est = estimate_noise({{false, noisy_circle(0.2, 20000, sigma, seed)}}, o);
      EXPECT_NEAR(est, sigma / std::sqrt(window), 0.2 * sigma / std::sqrt(window));
    }
  }
}

TEST(PathPlannerSmoothNoise, CleanCurvedRingHasNone) {
  const double est = estimate_noise({{false, noisy_circle(0.2, 20000, 0, 1)}}, SmoothOptions{});
  EXPECT_LT(est, 1e-8) << "curvature is cancelled by the estimator";
}

TEST(PathPlannerSmoothNoise, PooledOverLoops) {
  const double sigma = 0.0003;
  const SmoothOptions o;
  const double window = std::max(5.0, std::round(2 * o.window_pitches));
  std::vector<Loop> loops;
  for (unsigned k = 0; k < 4; ++k) loops.push_back({k > 0, noisy_circle(0.05 + 0.03 * k, 6000, sigma, 10 + k)});
  EXPECT_NEAR(estimate_noise(loops, o), sigma / std::sqrt(window), 0.2 * sigma / std::sqrt(window));
}

// Full-precision pitches, rotated polygons: every staircase step is one pitch long.
TEST(PathPlannerSmoothNoise, PitchOfStaircasesIsExact) {
  const Ring poly = {{0.01, 0.02}, {0.41, 0.05}, {0.33, 0.3}, {0.05, 0.27}};
  for (double pitch : {0.0013417, 0.002, 0.00071}) {
    const Ring stair = hg::partgen::pixel_staircase(poly, pitch);
    EXPECT_NEAR(estimate_pitch({{false, stair}}), pitch, 1e-9 * pitch) << "pitch " << pitch;
  }
}

TEST(PathPlannerSmoothNoise, NoPitchForNoisyStaircasesOrDrawnPolygons) {
  const Ring poly = {{0.01, 0.02}, {0.41, 0.05}, {0.33, 0.3}, {0.05, 0.27}};
  EXPECT_EQ(estimate_pitch({{false, poly}}), 0) << "a drawn polygon";
  for (unsigned seed = 1; seed <= 4; ++seed)
    EXPECT_EQ(estimate_pitch({{false, with_noise(hg::partgen::pixel_staircase(poly, 0.002), 0.0006, seed)}}), 0)
        << "noise of 0.3 pitch loses the lattice, seed " << seed;
}
