// Corner candidates and their confirmation (path_planner/smooth/corners.cpp) on exact polygons with known
// corners, the same with noise, a circle and a square with round corners (no corners).
#include <gtest/gtest.h>

#include "tests/path_planner/stage_rings.hpp"

using namespace hg::path_planner;
using namespace hg::path_planner::smooth;
using namespace hg::path_planner::stage_test;

namespace {

constexpr double kSpacing = 0.001;

// Turns of 40 to 110 deg, edges of 110 to 300 mm.
const Ring kPentagon = {{0, 0}, {0.3, 0}, {0.35, 0.15}, {0.15, 0.25}, {-0.05, 0.12}};

}  // namespace

TEST(PathPlannerSmoothCorners, CandidatesOfAnExactPolygonAreItsCorners) {
  const Sampled s = sample_polygon(kPentagon, kSpacing);
  const auto c = make_context(s.ring, kSpacing, exact_options());
  ASSERT_TRUE(c);
  const Corners found = corner_candidates(*c);
  ASSERT_EQ(found.size(), kPentagon.size());
  for (std::size_t k = 0; k < found.size(); ++k) {
    EXPECT_EQ(found[k].vertex, s.corner[k]);
    const Vec2 in = kPentagon[k] - kPentagon[(k + kPentagon.size() - 1) % kPentagon.size()];
    const Vec2 out = kPentagon[(k + 1) % kPentagon.size()] - kPentagon[k];
    EXPECT_NEAR(found[k].turn, turn(in, out), 1e-9) << "corner " << k;
  }
}

TEST(PathPlannerSmoothCorners, ConfirmedCornersOfAnExactPolygonSitOnItsVertices) {
  const Sampled s = sample_polygon(kPentagon, kSpacing);
  const auto c = make_context(s.ring, kSpacing, exact_options());
  ASSERT_TRUE(c);
  Corners corners = corner_candidates(*c);
  const Pieces pieces = confirm_corners(*c, corners);
  ASSERT_EQ(corners.size(), kPentagon.size());
  for (std::size_t k = 0; k < corners.size(); ++k)
    EXPECT_LT((c->u.origin + corners[k].at - kPentagon[k]).norm(), 1e-9) << "corner " << k;
  ASSERT_EQ(pieces.size(), kPentagon.size()) << "one straight per edge";
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    EXPECT_FALSE(pieces[k].prim.circle);
    EXPECT_EQ(pieces[k].run, int(k));
  }
}

// Per-vertex noise of 0.2 mm at 1 mm spacing: every corner found and confirmed, within a millimetre.
TEST(PathPlannerSmoothCorners, NoisyPolygonKeepsItsCorners) {
  const Sampled s = sample_polygon(kPentagon, kSpacing);
  for (unsigned seed = 1; seed <= 8; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = make_context(with_noise(s.ring, 0.0002, seed), kSpacing, exact_options());
    ASSERT_TRUE(c);
    Corners corners = corner_candidates(*c);
    confirm_corners(*c, corners);
    ASSERT_EQ(corners.size(), kPentagon.size());
    for (std::size_t k = 0; k < corners.size(); ++k)
      EXPECT_LT((c->u.origin + corners[k].at - kPentagon[k]).norm(), 0.001) << "corner " << k;
  }
}

TEST(PathPlannerSmoothCorners, CircleHasNone) {
  Ring ring;
  for (int k = 0; k < 1000; ++k)
    ring.push_back(0.15 * Vec2(std::cos(2 * kPi * k / 1000), std::sin(2 * kPi * k / 1000)));
  for (unsigned seed = 0; seed <= 4; ++seed) {
    const auto c = make_context(seed == 0 ? ring : with_noise(ring, 0.0002, seed), kSpacing, exact_options());
    ASSERT_TRUE(c);
    Corners corners = corner_candidates(*c);
    confirm_corners(*c, corners);
    EXPECT_TRUE(corners.empty()) << "seed " << seed << ": " << corners.size();
  }
}

// A square with R 25 fillets on all corners (each turns 90 deg over 39 mm): arcs, not corners.
TEST(PathPlannerSmoothCorners, RoundedCornersAreNotConfirmed) {
  Ring ring;
  const double half = 0.1, R = 0.025;
  for (int q = 0; q < 4; ++q) {
    const Eigen::Rotation2Dd rot(q * kPi / 2);
    for (int i = 0; i < 150; ++i) ring.push_back(rot * Vec2(half, -(half - R) + 2 * (half - R) * i / 150));
    for (int i = 0; i < 39; ++i)
      ring.push_back(rot *
                     (Vec2(half - R, half - R) + R * Vec2(std::cos(kPi / 2 * i / 39), std::sin(kPi / 2 * i / 39))));
  }
  for (unsigned seed = 0; seed <= 4; ++seed) {
    const auto c = make_context(seed == 0 ? ring : with_noise(ring, 0.0002, seed), kSpacing, exact_options());
    ASSERT_TRUE(c);
    Corners corners = corner_candidates(*c);
    confirm_corners(*c, corners);
    EXPECT_TRUE(corners.empty()) << "seed " << seed << ": " << corners.size();
  }
}
