// The outline on several threads (Options::threads) against the one-thread result and an exact check.
// Properties over many seeds and input kinds: the loops (indices, order, hole flags, coordinates, areas)
// and the radius are identical to one thread's; the strips' owned triangles together are exactly a
// Delaunay triangulation of all the points (GMP rationals); an unsafe margin falls back to one thread.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <string>

#include "clouds.hpp"
#include "exact_checker.hpp"
#include "outline_core/threads.hpp"

namespace hg::outline {
namespace {

using testing::exact;
using testing::Q2;

Result run(std::span<const Vec2> pts, int threads, bool keep = false, double radius = 0) {
  Options o;
  o.threads = threads;
  o.min_points_per_thread = 500;  // small clouds, so that many seeds run
  o.keep_triangles = keep;
  o.alpha_radius = radius;
  return compute_outline(pts, o);
}

void expect_same(const Result& one, const Result& many, const std::string& what) {
  EXPECT_EQ(one.alpha_radius, many.alpha_radius) << what;
  EXPECT_EQ(one.spacing, many.spacing) << what;
  EXPECT_EQ(one.nn_spacing_median, many.nn_spacing_median) << what;
  EXPECT_EQ(one.stats.triangles, many.stats.triangles) << what;
  EXPECT_EQ(one.points_used, many.points_used) << what;
  EXPECT_EQ(one.points_skipped, many.points_skipped) << what;
  EXPECT_EQ(one.duplicates_merged, many.duplicates_merged) << what;
  EXPECT_EQ(one.holes_dropped, many.holes_dropped) << what;
  ASSERT_EQ(one.loops.size(), many.loops.size()) << what;
  for (std::size_t i = 0; i < one.loops.size(); ++i) {
    const Loop &a = one.loops[i], &b = many.loops[i];
    EXPECT_EQ(a.hole, b.hole) << what << " loop " << i;
    EXPECT_EQ(a.point_index, b.point_index) << what << " loop " << i;
    EXPECT_EQ(a.area, b.area) << what << " loop " << i;
    EXPECT_EQ(a.perimeter, b.perimeter) << what << " loop " << i;
    ASSERT_EQ(a.points.size(), b.points.size());
    for (std::size_t k = 0; k < a.points.size(); ++k)
      EXPECT_TRUE(a.points[k].x == b.points[k].x && a.points[k].y == b.points[k].y) << what << " loop " << i;
  }
}

// "" when `tris` (input indices, counter-clockwise) is exactly a Delaunay triangulation of the finite
// input points: every triangle positive, each directed edge once, each edge either shared (the two
// opposite vertices not strictly inside the other's circle: locally Delaunay, hence Delaunay) or on the
// hull, the areas summing to the hull's, every distinct point a vertex. All in GMP rationals.
std::string check_triangulation(std::span<const Vec2> in, const std::vector<std::array<std::uint32_t, 3>>& tris) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> opposite;  // directed edge -> 3rd vertex
  mpq_class area2 = 0;
  for (const auto& t : tris) {
    const Q2 a = exact(in[t[0]]), b = exact(in[t[1]]), c = exact(in[t[2]]);
    const mpq_class o = testing::orient_q(a, b, c);
    if (sgn(o) <= 0) return "a triangle not counter-clockwise";
    area2 += o;
    for (int i = 0; i < 3; ++i)
      if (!opposite.emplace(std::pair{t[i], t[(i + 1) % 3]}, t[(i + 2) % 3]).second) return "a directed edge twice";
  }
  for (const auto& [e, c] : opposite) {
    const auto it = opposite.find({e.second, e.first});
    if (it == opposite.end()) continue;  // a hull edge (the area check below confirms the cover)
    if (sgn(testing::incircle_q(exact(in[e.first]), exact(in[e.second]), exact(in[c]), exact(in[it->second]))) > 0)
      return "an edge not locally Delaunay";
  }
  std::vector<Q2> all;
  std::map<std::pair<double, double>, bool> seen;
  for (std::uint32_t i = 0; i < in.size(); ++i)
    if (std::isfinite(in[i].x) && std::isfinite(in[i].y) && seen.emplace(std::pair{in[i].x, in[i].y}, false).second)
      all.push_back(exact(in[i]));
  if (area2 != testing::hull_area2_q(all)) return "the triangles do not cover the hull exactly";
  for (const auto& [e, c] : opposite) seen[{in[e.first].x, in[e.first].y}] = true;
  for (const auto& [p, used] : seen)
    if (!used) return "a point is no vertex";
  return "";
}

// A plate with a rectangular and a round cut-out and a notch, from any cloud over [0, w] x [0, h].
std::vector<Vec2> cut(std::vector<Vec2> p, double w, double h) {
  std::erase_if(p, [&](const Vec2& q) {
    const double u = q.x / w, v = q.y / h;
    const bool rect = u > 0.45 && u < 0.6 && v > 0.3 && v < 0.55;  // across the middle strip boundary
    const bool round = std::hypot(u - 0.25, v - 0.7) < 0.1;
    const bool notch = u > 0.5 && u < 0.56 && v > 0.9;
    return rect || round || notch;
  });
  return p;
}

// The input kinds: an exact grid (cocircular ties everywhere), full-precision jitter, noise as strong
// as the spacing, a Poisson cloud, duplicates and NaN points, all with cut-outs.
std::vector<Vec2> cloud(int kind, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> size(70, 110);
  const int w = size(rng), h = size(rng);
  switch (kind) {
    case 0: return cut(testing::grid_cloud(w, h), w, h);
    case 1: {
      const double step = 0.0123456789 * (1 + 0.1 * static_cast<double>(seed % 7));
      auto p = testing::grid_cloud(w, h, step, {1234.5678901, -98.7654321}, 0.2, seed);
      for (Vec2& q : p) q = {(q.x - 1234.5678901) / step, (q.y + 98.7654321) / step};  // full-precision
      return cut(p, w, h);
    }
    case 2: return cut(testing::grid_cloud(w, h, 1, {}, 0.5, seed), w, h);
    case 3: return cut(testing::random_cloud(static_cast<std::size_t>(w * h), seed, 1), 1, 1);
    default: {
      auto p = cut(testing::grid_cloud(w, h, 1, {}, 0.3, seed), w, h);
      std::uniform_int_distribution<std::size_t> pick(0, p.size() - 1);
      for (int i = 0; i < 300; ++i) p.push_back(p[pick(rng)]);
      for (int i = 0; i < 50; ++i) p.push_back({std::numeric_limits<double>::quiet_NaN(), 1.0 * i});
      std::shuffle(p.begin(), p.end(), rng);
      return p;
    }
  }
}

TEST(OutlineThreads, LoopsAndRadiusIdenticalToOneThread) {
  for (int kind = 0; kind < 5; ++kind)
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      const std::vector<Vec2> pts = cloud(kind, seed);
      const Result one = run(pts, 1);
      ASSERT_EQ(one.threads_used, 1);
      ASSERT_GE(one.loops.size(), 3u) << "kind " << kind;  // the plate and its two cut-outs at least
      for (int threads : {2, 3}) {
        const std::string what =
            "kind " + std::to_string(kind) + " seed " + std::to_string(seed) + " threads " + std::to_string(threads);
        const Result many = run(pts, threads);
        EXPECT_EQ(many.threads_used, threads) << what;  // the threaded path ran, not the fallback
        expect_same(one, many, what);
      }
    }
}

TEST(OutlineThreads, OwnedTrianglesAreExactlyDelaunayForAllPoints) {
  for (int kind = 0; kind < 5; ++kind)
    for (std::uint64_t seed = 11; seed <= 12; ++seed) {
      const std::vector<Vec2> pts = cloud(kind, seed);
      for (int threads : {2, 3}) {
        const Result many = run(pts, threads, true);
        const std::string what = "kind " + std::to_string(kind) + " seed " + std::to_string(seed);
        EXPECT_EQ(many.threads_used, threads) << what;
        EXPECT_EQ(many.delaunay_triangles.size(), many.stats.triangles) << what;
        EXPECT_EQ(check_triangulation(pts, many.delaunay_triangles), "") << what;
      }
    }
}

TEST(OutlineThreads, UnsafeMarginFallsBackToOneThread) {
  for (int kind = 0; kind < 5; ++kind) {
    const std::vector<Vec2> pts = cloud(kind, 21);
    Options o;
    o.min_points_per_thread = 500;
    Result probe;
    StripSurvey survey;
    ASSERT_TRUE(run_threaded(pts, o, 2, probe, &survey));
    // An explicit radius wider than a quarter of the margin: the split cannot prove its loops.
    const double radius = 0.3 * survey.margin;
    o.alpha_radius = radius;
    EXPECT_FALSE(run_threaded(pts, o, 2, probe));
    const Result one = run(pts, 1, false, radius), many = run(pts, 2, false, radius);
    EXPECT_EQ(many.threads_used, 1) << "kind " << kind;
    expect_same(one, many, "fallback kind " + std::to_string(kind));
    // Just inside the margin the split runs, and agrees.
    const double fits = 0.24 * survey.margin;
    const Result one2 = run(pts, 1, false, fits), many2 = run(pts, 2, false, fits);
    EXPECT_EQ(many2.threads_used, 2) << "kind " << kind;
    expect_same(one2, many2, "explicit radius kind " + std::to_string(kind));
  }
}

TEST(OutlineThreads, ConsumingThePointsGivesTheSameOutline) {
  // compute_outline(std::vector&&) lets the strips release the points once they hold their copies; when
  // the split then fails (a radius too wide for the margin) the points are restored for the one-thread
  // path. Both ways the result equals one thread's on the points kept by the caller; with non-finite
  // points in the cloud (restored as NaN: skipped, indices unchanged) too.
  for (int kind = 0; kind < 5; ++kind)
    for (std::uint64_t seed : {31u, 32u}) {
      std::vector<Vec2> pts = cloud(kind, seed);
      if (seed == 32) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        pts[7] = {nan, 1}, pts[pts.size() / 2] = {2, std::numeric_limits<double>::infinity()};
      }
      Options o;
      o.min_points_per_thread = 500;
      Result probe;
      StripSurvey survey;
      ASSERT_TRUE(run_threaded(pts, o, 2, probe, &survey));
      for (double radius : {0.0, 0.3 * survey.margin}) {
        const std::string what =
            "kind " + std::to_string(kind) + " seed " + std::to_string(seed) + (radius > 0 ? " fallback" : " split");
        const Result one = run(pts, 1, false, radius);
        Options c = o;
        c.threads = 2;
        c.alpha_radius = radius;
        std::vector<Vec2> given = pts;
        const Result many = compute_outline(std::move(given), c);
        EXPECT_EQ(many.threads_used, radius > 0 ? 1 : 2) << what;
        expect_same(one, many, what);
      }
      // run_threaded itself: the consumed vector is empty after a split that ran, as given after one
      // that fell back.
      std::vector<Vec2> given = pts;
      Result r;
      EXPECT_TRUE(run_threaded(pts, &given, o, 2, r));
      EXPECT_TRUE(given.empty());
      given = pts;
      o.alpha_radius = 0.3 * survey.margin;
      EXPECT_FALSE(run_threaded(pts, &given, o, 2, r));
      ASSERT_EQ(given.size(), pts.size());
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const bool finite = std::isfinite(pts[i].x) && std::isfinite(pts[i].y);
        EXPECT_TRUE(finite ? given[i].x == pts[i].x && given[i].y == pts[i].y : std::isnan(given[i].x)) << i;
      }
    }
}

TEST(OutlineThreads, OneThreadWhereTheSplitDoesNotApply) {
  const std::vector<Vec2> pts = cloud(2, 5);
  Options o;
  o.threads = 2;
  o.min_points_per_thread = 500;
  EXPECT_EQ(strips_for(o, pts.size()), 2);
  o.min_points_per_thread = pts.size();  // too small a cloud for two strips
  EXPECT_EQ(strips_for(o, pts.size()), 1);
  o.min_points_per_thread = 500;
  for (auto change : {+[](Options& x) { x.alpha_mode = AlphaMode::Local; }, +[](Options& x) { x.outer_only = true; },
                      +[](Options& x) { x.mode = Mode::DS; }, +[](Options& x) { x.threads = 1; }}) {
    Options c = o;
    change(c);
    EXPECT_EQ(strips_for(c, pts.size()), 1);
    EXPECT_EQ(compute_outline(pts, c).threads_used, 1);
  }
  o.threads = -1;
  EXPECT_THROW(compute_outline(pts, o), OutlineError);
}

}  // namespace
}  // namespace hg::outline
