// Run segmentation (path_planner/smooth/segment.cpp) and tangency (smooth/tangency.cpp) on a stadium: two
// straights and two half circles, whose pieces, radii and tangent points are known by construction.
#include <gtest/gtest.h>

#include "tests/path_planner/stage_rings.hpp"

using namespace hg::path_planner;
using namespace hg::path_planner::smooth;
using namespace hg::path_planner::stage_test;

namespace {

constexpr double kLength = 0.2, kR = 0.05, kSpacing = 0.001;

}  // namespace

TEST(PathPlannerSmoothSegment, ExactStadiumIsLineArcLineArc) {
  const Stadium s = stadium(kLength, kR, kSpacing);
  const auto c = make_context(s.ring, kSpacing, exact_options());
  ASSERT_TRUE(c);
  const Pieces p = segment_run(*c, 0, c->n - 1, 0, true);
  ASSERT_EQ(p.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    SCOPED_TRACE("piece " + std::to_string(k));
    EXPECT_EQ(p[k].prim.circle, k % 2 == 1);
    EXPECT_EQ(p[k].run, 0);
    if (p[k].prim.circle) {
      EXPECT_NEAR(p[k].prim.radius, kR, 1e-9);
      EXPECT_LT((c->u.origin + p[k].prim.centre - s.centre[k / 2]).norm(), 1e-9);
      EXPECT_TRUE(p[k].prim.ccw);
    } else {
      EXPECT_NEAR(std::abs(p[k].prim.dir.x()), 1, 1e-12);
    }
    // the junctions refined onto the tangent points (a vertex on either side explains both primitives)
    EXPECT_NEAR(double(p[k].prim.first), double(s.start[k]), 1.0);
  }
  // the pieces cover the ring, in order, without overlap
  for (std::size_t k = 0; k + 1 < 4; ++k) EXPECT_EQ(p[k].prim.last + 1, p[k + 1].prim.first);
  EXPECT_EQ(p[0].prim.first, 0);
  EXPECT_EQ(p[3].prim.last, c->n - 1);
}

// Per-vertex noise of 0.2 mm: every vertex within 4 noise levels of its piece's primitive, the arcs'
// radii within 1 mm, and no piece longer than the feature it lies on (a piece spans no tangent point by more
// than a corner scale).
TEST(PathPlannerSmoothSegment, NoisyStadiumPiecesFitTheirVertices) {
  const Stadium s = stadium(kLength, kR, kSpacing);
  for (unsigned seed = 1; seed <= 6; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = make_context(with_noise(s.ring, 0.0002, seed), kSpacing, exact_options());
    ASSERT_TRUE(c);
    const Pieces p = segment_run(*c, 0, c->n - 1, 0, true);
    ASSERT_GE(p.size(), 4u);
    long covered = 0;
    for (const Piece& q : p) {
      covered += q.prim.last - q.prim.first + 1;
      if (q.prim.circle) {
        EXPECT_NEAR(q.prim.radius, kR, 0.001);
      }
      double worst_mean = 0;  // mean residual over the piece: no systematic misfit
      for (long j = q.prim.first; j <= q.prim.last; ++j) worst_mean += residual(q.prim, c->u.at(j));
      EXPECT_LT(std::abs(worst_mean) / double(q.prim.last - q.prim.first + 1), c->tolerance);
    }
    EXPECT_EQ(covered, c->n) << "every vertex in exactly one piece";
  }
}

// Tangency: the arcs of a noisy stadium are refitted tangent to the straights beside them: the distance of
// each straight from the arc's centre equals its radius, and the junctions are marked tangent.
TEST(PathPlannerSmoothTangency, ArcsBecomeTangentToTheirStraights) {
  const Stadium s = stadium(kLength, kR, kSpacing);
  int tested = 0;
  double free_worst = 0;  // the free circles' distance from tangency, for comparison
  for (unsigned seed = 1; seed <= 6; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = make_context(with_noise(s.ring, 0.0002, seed), kSpacing, exact_options());
    ASSERT_TRUE(c);
    const Pieces before = segment_run(*c, 0, c->n - 1, 0, true);
    if (before.size() != 4u) continue;  // the property below is stated for line-arc-line-arc
    ++tested;
    for (std::size_t k = 1; k < 4; k += 2)
      for (std::size_t l : {k - 1, (k + 1) % 4})
        free_worst = std::max(
            free_worst, std::abs(std::abs(cross(before[l].prim.dir, before[k].prim.centre - before[l].prim.centre)) -
                                 before[k].prim.radius));
    const Pieces after = make_tangent(*c, before, true);
    ASSERT_EQ(after.size(), 4u);
    for (std::size_t k = 1; k < 4; k += 2) {
      const Primitive& arc = after[k].prim;
      for (std::size_t l : {k - 1, (k + 1) % 4}) {
        const Primitive& line = after[l].prim;
        const double d = std::abs(cross(line.dir, arc.centre - line.centre));
        EXPECT_NEAR(d, arc.radius, 0.02 * 0.0002) << "arc " << k << ", line " << l;
      }
      EXPECT_TRUE(after[k - 1].tangent_next && after[k].tangent_next);
      EXPECT_NEAR(arc.radius, kR, 0.001);
    }
  }
  EXPECT_GE(tested, 4) << "most draws segment into line, arc, line, arc";
  EXPECT_GT(free_worst, 0.02 * 0.0002) << "the free circles were not tangent already";
}
