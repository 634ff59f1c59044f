// The fillet stage (path_planner/smooth/fillet.cpp) on a square with one filleted corner, without the corner
// detector: the pieces beside the fillet are made by hand. Expectations from the construction: the fillet's
// radius and centre, the tangent points; a sharp corner gets no fillet.
#include <gtest/gtest.h>

#include "tests/path_planner/stage_rings.hpp"

using namespace hg::path_planner;
using namespace hg::path_planner::smooth;
using namespace hg::path_planner::stage_test;

namespace {

constexpr double kSide = 0.2, kSpacing = 0.001, kPitch = 0.001;

// Index of the vertex of the square's bottom edge at x (vertex i is at x = i * spacing there), of its right
// edge at y.
long at_x(double x) { return long(std::lround(x / kSpacing)); }
long at_y(const FilletedSquare& f, double y, double R) { return f.arc_last + long(std::lround((y - R) / kSpacing)); }

}  // namespace

TEST(PathPlannerSmoothFillet, ExactFilletIsFoundWithItsRadiusAndCentre) {
  for (double R : {0.010, 0.015, 0.020}) {
    SCOPED_TRACE("R " + std::to_string(R));
    const FilletedSquare f = filleted_square(kSide, R, kSpacing);
    const auto c = make_context(f.ring, kPitch, exact_options());
    ASSERT_TRUE(c);
    Fillet fil;
    ASSERT_TRUE(fit_fillet(*c, at_x(0.08), at_x(0.15), at_y(f, 0.05, R), at_y(f, 0.12, R), fil));
    EXPECT_NEAR(fil.arc.radius, R, 1e-5);
    EXPECT_LT((c->u.origin + fil.arc.centre - f.centre).norm(), 1e-5);
    EXPECT_LT((c->u.origin + fil.t1 - Vec2(kSide - R, 0)).norm(), 1e-5) << "tangent point on the bottom edge";
    EXPECT_LT((c->u.origin + fil.t2 - Vec2(kSide, R)).norm(), 1e-5) << "tangent point on the right edge";
    EXPECT_TRUE(fil.arc.ccw) << "a convex fillet of a counter-clockwise ring turns left";
    EXPECT_NEAR(std::abs(fil.a.dir.x()), 1, 1e-9);
    EXPECT_NEAR(std::abs(fil.b.dir.y()), 1, 1e-9);
  }
}

// Per-vertex noise of 0.2 pitch: the fillet within 1 mm in radius and centre (the accuracy the planner's
// end-to-end fillet test asks of the path), for every draw.
TEST(PathPlannerSmoothFillet, NoisyFilletIsFoundWithinAMillimetre) {
  const double R = 0.015;
  const FilletedSquare f = filleted_square(kSide, R, kSpacing);
  for (unsigned seed = 1; seed <= 8; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = make_context(with_noise(f.ring, 0.0002, seed), kPitch, exact_options());
    ASSERT_TRUE(c);
    Fillet fil;
    ASSERT_TRUE(fit_fillet(*c, at_x(0.08), at_x(0.15), at_y(f, 0.05, R), at_y(f, 0.12, R), fil));
    EXPECT_NEAR(fil.arc.radius, R, 0.001);
    EXPECT_LT((c->u.origin + fil.arc.centre - f.centre).norm(), 0.001);
  }
}

TEST(PathPlannerSmoothFillet, SharpCornerHasNoFillet) {
  const FilletedSquare f = filleted_square(kSide, 0, kSpacing);
  for (unsigned seed = 0; seed <= 8; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = make_context(seed == 0 ? f.ring : with_noise(f.ring, 0.0002, seed), kPitch, exact_options());
    ASSERT_TRUE(c);
    Fillet fil;
    EXPECT_FALSE(fit_fillet(*c, at_x(0.08), at_x(0.15), at_y(f, 0.05, 0), at_y(f, 0.12, 0), fil))
        << "radius " << fil.arc.radius;
  }
}

namespace {

// Pieces of run 0 over the bottom edge up to x = a_end, over the arc region in two short lines split at
// its middle, and over the right edge from y = b_start: what the greedy segmentation makes of a noisy fillet.
Pieces hand_made_pieces(const SmoothContext& c, const FilletedSquare& f, double R, double a_end, double b_start) {
  const long a0 = at_x(0.02), a1 = at_x(a_end), b0 = at_y(f, b_start, R), b1 = at_y(f, 0.18, R);
  const long mid = (f.arc_first + f.arc_last) / 2;
  Pieces p;
  for (auto [from, to] : {std::pair{a0, a1}, {a1 + 1, mid}, {mid + 1, b0 - 1}, {b0, b1}})
    p.push_back({line_piece(c.u, from, to), 0, false, std::nullopt});
  return p;
}

}  // namespace

TEST(PathPlannerSmoothFillet, StageReplacesTheShortPiecesByStraightFilletStraight) {
  const double R = 0.015;
  const FilletedSquare f = filleted_square(kSide, R, kSpacing);
  for (unsigned seed = 0; seed <= 6; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = make_context(seed == 0 ? f.ring : with_noise(f.ring, 0.0002, seed), kPitch, exact_options());
    ASSERT_TRUE(c);
    const Pieces in = hand_made_pieces(*c, f, R, 0.17, 0.035);
    ASSERT_FALSE(long_line(*c, in[1].prim) || long_line(*c, in[2].prim)) << "the middle pieces are short";
    ASSERT_TRUE(long_line(*c, in[0].prim) && long_line(*c, in[3].prim));
    const Pieces out = fit_fillets(*c, in, false);
    ASSERT_EQ(out.size(), 2u) << "straight (carrying the fillet), straight";
    ASSERT_TRUE(out[0].fillet.has_value());
    EXPECT_FALSE(out[1].fillet.has_value());
    EXPECT_FALSE(out[0].prim.circle || out[1].prim.circle);
    EXPECT_NEAR(out[0].fillet->arc.radius, R, 0.001);
    EXPECT_LT((c->u.origin + out[0].fillet->arc.centre - f.centre).norm(), 0.001);
    EXPECT_EQ(out[0].prim.first, in[0].prim.first);
    EXPECT_EQ(out[1].prim.last, in[3].prim.last);
    // the straights end near the tangent points (within the fillet's vertices)
    EXPECT_NEAR(double(out[0].prim.last), double(f.arc_first), 3);
    EXPECT_NEAR(double(out[1].prim.first), double(f.arc_last), 3);
  }
}

TEST(PathPlannerSmoothFillet, StageLeavesASharpCornerAlone) {
  const FilletedSquare f = filleted_square(kSide, 0, kSpacing);
  for (unsigned seed = 0; seed <= 6; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = make_context(seed == 0 ? f.ring : with_noise(f.ring, 0.0002, seed), kPitch, exact_options());
    ASSERT_TRUE(c);
    const Pieces in = hand_made_pieces(*c, f, 0, 0.17, 0.035);
    const Pieces out = fit_fillets(*c, in, false);
    ASSERT_EQ(out.size(), in.size());
    for (const Piece& p : out) EXPECT_FALSE(p.fillet.has_value());
  }
}
