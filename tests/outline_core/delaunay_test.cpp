// Delaunay triangulation: exactness proven by an independent GMP checker on many clouds, for every
// point-location mode and insertion order; errors; search cost. The predicates: predicates_test.cpp.
#include <gtest/gtest.h>

#include <array>
#include <set>

#include "clouds.hpp"
#include "exact_checker.hpp"
#include "outline_core/delaunay.hpp"

using namespace hg::outline;
using namespace hg::outline::testing;

namespace {

void check_all_modes(const std::vector<Vec2>& pts, std::size_t ordinary_limit = 2500) {
  for (Mode m : {Mode::Ordinary, Mode::DS, Mode::DSHI}) {
    if (m == Mode::Ordinary && pts.size() > ordinary_limit) continue;
    for (Order o : {Order::AsIs, Order::Hilbert, Order::Brio}) {
      SCOPED_TRACE(std::string(to_string(m)) + " " + to_string(o));
      const Triangulation T = triangulate(pts, m, o);
      EXPECT_EQ(check_delaunay(pts, T), "");
      EXPECT_EQ(T.stats.walk_fallbacks, 0u);
    }
  }
}

// Triangles as sorted index triples of the input (canonical, for comparing triangulations).
std::set<std::array<std::uint32_t, 3>> triangle_set(const Triangulation& T) {
  std::set<std::array<std::uint32_t, 3>> s;
  for (std::size_t t = 0; t < T.slots(); ++t) {
    if (T.is_ghost(t)) continue;
    std::array<std::uint32_t, 3> a{T.ids[T.tri[3 * t]], T.ids[T.tri[3 * t + 1]], T.ids[T.tri[3 * t + 2]]};
    std::sort(a.begin(), a.end());
    s.insert(a);
  }
  return s;
}

}  // namespace

TEST(OutlineDelaunay, RandomClouds) {
  check_all_modes(random_cloud(2000, 7));
  check_all_modes(random_cloud(3, 8));
  check_all_modes(random_cloud(10, 9));
}

TEST(OutlineDelaunay, RandomCloudSameTriangulationInEveryModeAndOrder) {
  // No four points cocircular (almost surely): the Delaunay triangulation is unique.
  const auto pts = random_cloud(1500, 11);
  const auto ref = triangle_set(triangulate(pts, Mode::Ordinary, Order::AsIs));
  EXPECT_EQ(ref.size(), triangulate(pts, Mode::DSHI, Order::AsIs).finite_count());
  for (Mode m : {Mode::DS, Mode::DSHI})
    for (Order o : {Order::AsIs, Order::Hilbert, Order::Brio}) EXPECT_TRUE(triangle_set(triangulate(pts, m, o)) == ref);
}

TEST(OutlineDelaunay, ExactGridsAreCocircularEverywhere) {
  check_all_modes(grid_cloud(40, 35));
  check_all_modes(grid_cloud(1, 50, 1, {}, 0).size() ? grid_cloud(3, 60) : grid_cloud(3, 60));  // thin strip
  check_all_modes(grid_cloud(45, 45, 0.1));  // 0.1 is not exact: rounded rows
}

TEST(OutlineDelaunay, JitteredScanGrid) { check_all_modes(grid_cloud(60, 50, 1, {}, 0.2)); }

TEST(OutlineDelaunay, Float32CameraGridsInMetres) {
  // What the camera gives: a pixel grid in scan order, in metres, stored as float32, around a centre
  // near the coordinate origin (so the floats' ulps differ across the cloud), noise-free (rows exactly
  // straight, every cell a cocircular rectangle) and with 0.05-pixel noise. The few-bits exact paths
  // decide most degenerate tests here.
  auto f32 = [](double v) {
    volatile float f = static_cast<float>(v);  // volatile: GCC 12 -O3 may drop a float round trip
    return static_cast<double>(f);
  };
  const double pitch = 2.4467e-4;
  for (double noise : {0.0, 0.05}) {
    std::mt19937_64 rng(31);
    std::normal_distribution<double> g(0, noise > 0 ? noise * pitch : 1);
    std::vector<Vec2> pts;
    for (int row = 0; row < 60; ++row)
      for (int col = 0; col < 70; ++col) {
        const double x = -0.004 + col * pitch + (noise > 0 ? g(rng) : 0),
                     y = 0.003 - row * pitch + (noise > 0 ? g(rng) : 0);
        pts.push_back({f32(x), f32(y)});
      }
    SCOPED_TRACE(noise);
    check_all_modes(pts, 0);
  }
}

TEST(OutlineDelaunay, CollinearHeavy) { check_all_modes(collinear_heavy(3)); }

TEST(OutlineDelaunay, Cocircular) {
  const auto pts = cocircular_cloud();
  ASSERT_GT(pts.size(), 30u);
  check_all_modes(pts);
}

TEST(OutlineDelaunay, DuplicateHeavy) {
  const auto pts = duplicate_heavy(5);
  check_all_modes(pts);
  const Triangulation T = triangulate(pts, Mode::DSHI, Order::Hilbert);
  EXPECT_EQ(T.inserted, 12u * 12u + 200u);
  EXPECT_EQ(T.duplicates, pts.size() - T.inserted);
}

TEST(OutlineDelaunay, HugeAndTinyCoordinates) {
  check_all_modes(grid_cloud(30, 30, 1e9));
  check_all_modes(grid_cloud(30, 30, 1, {1e9, -3e9}, 0.3));  // far from the origin, unit spacing
  check_all_modes(random_cloud(800, 21, 1e3, {1e9, 1e9}));
  check_all_modes(grid_cloud(30, 30, 1e-9, {}, 0.2));
  check_all_modes(random_cloud(800, 22, 1e-9, {1.0, 2.0}));  // tiny spread far away: translation rounds
  check_all_modes(grid_cloud(25, 25, 1e-9, {1.0, 1.0}));     // and rows/columns collapse or not
}

TEST(OutlineDelaunay, NonFinitePointsAreSkippedAndCounted) {
  // NaN or infinite coordinates: the point is left out (no vertex), the others keep their input indices.
  auto pts = random_cloud(40, 1);
  pts[7].y = std::nan("");
  pts[13].x = -INFINITY;
  pts[21] = {INFINITY, std::nan("")};
  for (Mode m : {Mode::Ordinary, Mode::DS, Mode::DSHI})
    for (Order o : {Order::AsIs, Order::Hilbert, Order::Brio}) {
      const Triangulation T = triangulate(pts, m, o);
      EXPECT_EQ(T.skipped, 3u);
      EXPECT_EQ(T.inserted, 37u);
      EXPECT_EQ(check_delaunay(pts, T), "");  // checks ids map one-to-one onto the finite points
    }
  std::vector<std::uint32_t> custom(pts.size());
  for (std::size_t i = 0; i < custom.size(); ++i) custom[i] = static_cast<std::uint32_t>(custom.size() - 1 - i);
  const Triangulation T = triangulate(pts, Mode::DSHI, Order::AsIs, custom);
  EXPECT_EQ(check_delaunay(pts, T), "");
  // Fewer than 3 finite points: an error saying so.
  const std::vector<Vec2> two{{0, 0}, {std::nan(""), 1}, {1, 1}, {INFINITY, 2}, {2, -INFINITY}};
  try {
    triangulate(two, Mode::DSHI, Order::AsIs);
    FAIL() << "no error";
  } catch (const OutlineError& e) {
    EXPECT_NE(std::string(e.what()).find("got 2 finite points (3 non-finite skipped)"), std::string::npos) << e.what();
  }
}

TEST(OutlineDelaunay, ComputeOutlineSkipsNonFinitePointsAndKeepsInputIndices) {
  // The same cloud with NaN/Inf points spread among its points: the outline and the triangles are those
  // of the finite points, their indices positions in the input with the skipped points included.
  const auto base = grid_cloud(30, 24, 1, {3, -2}, 0.3, 5);
  std::mt19937_64 rng(9);
  std::vector<Vec2> mixed;
  std::vector<std::uint32_t> where;  // base index -> index in mixed
  std::size_t bad = 0;
  for (const Vec2& p : base) {
    while (rng() % 4 == 0) {
      const double kinds[3] = {std::nan(""), INFINITY, -INFINITY};
      mixed.push_back(rng() % 2 ? Vec2{kinds[rng() % 3], p.y} : Vec2{p.x, kinds[rng() % 3]});
      ++bad;
    }
    where.push_back(static_cast<std::uint32_t>(mixed.size()));
    mixed.push_back(p);
  }
  ASSERT_GT(bad, 50u);
  Options opt;
  opt.alpha_radius = 1.2;
  opt.keep_triangles = true;
  const Result a = compute_outline(base, opt);
  for (bool consume : {false, true}) {
    std::vector<Vec2> copy = mixed;
    const Result b = consume ? compute_outline(std::move(copy), opt) : compute_outline(mixed, opt);
    EXPECT_EQ(b.points_read, mixed.size());
    EXPECT_EQ(b.points_skipped, bad);
    EXPECT_EQ(b.points_used, a.points_used);
    ASSERT_EQ(b.loops.size(), a.loops.size());
    ASSERT_GE(a.loops.size(), 1u);
    for (std::size_t l = 0; l < a.loops.size(); ++l) {
      ASSERT_EQ(b.loops[l].point_index.size(), a.loops[l].point_index.size());
      for (std::size_t k = 0; k < a.loops[l].point_index.size(); ++k) {
        EXPECT_EQ(b.loops[l].point_index[k], where[a.loops[l].point_index[k]]);
        EXPECT_EQ(b.loops[l].points[k].x, base[a.loops[l].point_index[k]].x);
        EXPECT_EQ(b.loops[l].points[k].y, base[a.loops[l].point_index[k]].y);
      }
    }
    ASSERT_EQ(b.delaunay_triangles.size(), a.delaunay_triangles.size());
    for (std::size_t t = 0; t < a.delaunay_triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(b.delaunay_triangles[t][k], where[a.delaunay_triangles[t][k]]);
  }
  // Fewer than 3 finite points: the core's error.
  EXPECT_THROW(compute_outline(std::vector<Vec2>{{0, 0}, {1, std::nan("")}, {1, 1}}), OutlineError);
}

TEST(OutlineDelaunay, BadInputIsRejectedWithTheIndex) {
  auto pts = random_cloud(20, 1);
  pts[7] = {1e70, 0.5};  // the span limit (1e60)
  try {
    triangulate(pts, Mode::DSHI, Order::AsIs);
    FAIL() << "no error";
  } catch (const OutlineError& e) {
    EXPECT_NE(std::string(e.what()).find("point 7 "), std::string::npos) << e.what();
  }
  pts[7] = {0.5, 0.5};
  pts[13].x = 0.25 + 1e-60;  // 0.25 + 1e-60 rounds to 0.25: fine
  EXPECT_NO_THROW(triangulate(pts, Mode::DSHI, Order::AsIs));
  pts[13].x = 3e-60;  // a set bit below 2^-170: the predicates could underflow
  try {
    triangulate(pts, Mode::DSHI, Order::AsIs);
    FAIL() << "no error";
  } catch (const OutlineError& e) {
    EXPECT_NE(std::string(e.what()).find("point 13 "), std::string::npos) << e.what();
  }
  EXPECT_THROW(triangulate(std::vector<Vec2>{}, Mode::DSHI, Order::AsIs), OutlineError);
  EXPECT_THROW(triangulate(std::vector<Vec2>{{1, 2}, {3, 4}}, Mode::DSHI, Order::AsIs), OutlineError);
  // Many points, two distinct.
  std::vector<Vec2> two(50, Vec2{1, 1});
  two[30] = {2, 5};
  try {
    triangulate(two, Mode::DS, Order::Hilbert);
    FAIL() << "no error";
  } catch (const OutlineError& e) {
    EXPECT_NE(std::string(e.what()).find("3 distinct points, got 2"), std::string::npos) << e.what();
  }
  // All collinear (with duplicates).
  std::vector<Vec2> line;
  for (int i = 0; i < 100; ++i) line.push_back({i * 0.5, 3.0 * i * 0.5 - 2});
  line.push_back(line[4]);
  try {
    triangulate(line, Mode::DSHI, Order::AsIs);
    FAIL() << "no error";
  } catch (const OutlineError& e) {
    EXPECT_NE(std::string(e.what()).find("collinear"), std::string::npos) << e.what();
  }
  // compute_outline reports the same errors.
  EXPECT_THROW(compute_outline(line), OutlineError);
}

TEST(OutlineDelaunay, SearchCostDshiBelowDsBelowOrdinaryOnScanGrid) {
  const auto pts = grid_cloud(50, 40, 1, {}, 0.2);
  const auto ord = triangulate(pts, Mode::Ordinary, Order::AsIs).stats;
  const auto ds = triangulate(pts, Mode::DS, Order::AsIs).stats;
  const auto dshi = triangulate(pts, Mode::DSHI, Order::AsIs).stats;
  EXPECT_LT(dshi.search_cost(), ds.search_cost());
  EXPECT_LT(ds.search_cost(), ord.search_cost());
  // Ordinary tests every live triangle at each insertion: triangles (with ghosts) grow by 2 per point,
  // starting at 4, so the total is sum over insertions k of (4 + 2k).
  const std::uint64_t n = pts.size(), inserts = n - 3;
  EXPECT_EQ(ord.locate_visits, 4 * inserts + inserts * (inserts - 1));
  EXPECT_EQ(ord.cavity_visits, 0u);
  // The same cavities in every mode (same order, same Delaunay test): same cavity sizes.
  EXPECT_EQ(ord.cavity_triangles, dshi.cavity_triangles);
  EXPECT_EQ(ds.cavity_triangles, dshi.cavity_triangles);
  // DSHI walks a few triangles per insertion on scan order.
  EXPECT_LT(static_cast<double>(dshi.locate_visits) / n, 20.0);
}

TEST(OutlineDelaunay, OptionNames) {
  for (Mode m : {Mode::Ordinary, Mode::DS, Mode::DSHI}) EXPECT_EQ(parse_mode(to_string(m)), m);
  for (Order o : {Order::AsIs, Order::Hilbert, Order::Brio}) EXPECT_EQ(parse_order(to_string(o)), o);
  EXPECT_THROW(parse_mode("fast"), OutlineError);
  EXPECT_THROW(parse_order("random"), OutlineError);
}

TEST(OutlineDelaunay, CheckerRejectsAFlippedEdge) {
  // The checker must not pass everything: flip one interior edge of a valid triangulation (keeping the
  // mesh consistent) and it must report the non-Delaunay edge.
  const auto pts = random_cloud(300, 3);
  Triangulation T = triangulate(pts, Mode::DSHI, Order::AsIs);
  ASSERT_EQ(check_delaunay(pts, T), "");
  bool flipped = false;
  for (std::uint32_t h = 0; h < T.tri.size() && !flipped; ++h) {
    const std::uint32_t t = h / 3, o = T.twin[h], t2 = o / 3;
    if (T.is_ghost(t) || T.is_ghost(t2)) continue;
    const std::uint32_t a = T.tri[h], b = T.tri[Triangulation::next(h)], c = T.tri[Triangulation::prev(h)];
    const std::uint32_t d = T.tri[Triangulation::prev(o)];
    const Q2 qa = exact(T.xy[a]), qb = exact(T.xy[b]), qc = exact(T.xy[c]), qd = exact(T.xy[d]);
    if (sgn(orient_q(qc, qa, qd)) <= 0 || sgn(orient_q(qd, qb, qc)) <= 0) continue;  // quad not convex
    const std::uint32_t ei1 = T.twin[Triangulation::next(h)], ei2 = T.twin[Triangulation::prev(h)];
    const std::uint32_t eo1 = T.twin[Triangulation::next(o)], eo2 = T.twin[Triangulation::prev(o)];
    auto link = [&](std::uint32_t x, std::uint32_t y) {
      T.twin[x] = y;
      T.twin[y] = x;
    };
    T.tri[3 * t] = c, T.tri[3 * t + 1] = a, T.tri[3 * t + 2] = d;
    T.tri[3 * t2] = d, T.tri[3 * t2 + 1] = b, T.tri[3 * t2 + 2] = c;
    link(3 * t, ei2);
    link(3 * t + 1, eo1);
    link(3 * t2, eo2);
    link(3 * t2 + 1, ei1);
    link(3 * t + 2, 3 * t2 + 2);
    flipped = true;
  }
  ASSERT_TRUE(flipped);
  EXPECT_NE(check_delaunay(pts, T).find("not locally Delaunay"), std::string::npos) << check_delaunay(pts, T);
}

TEST(OutlineDelaunay, NearestNeighbourDistancesMatchBruteForce) {
  auto pts = random_cloud(600, 12, 10);
  const auto g = grid_cloud(15, 15, 0.7, {2, 2});
  pts.insert(pts.end(), g.begin(), g.end());
  pts.push_back(pts[5]);  // a duplicate: its distance 0 must not count
  for (Order o : {Order::AsIs, Order::Brio}) {
    const Triangulation T = triangulate(pts, Mode::DSHI, o);
    for (std::size_t v = 0; v < T.xy.size(); ++v) {
      if (T.vrep[v] != v) continue;
      double best = INFINITY;
      for (std::size_t w = 0; w < T.xy.size(); ++w) {
        if (T.vrep[w] != w || w == v) continue;
        const double dx = T.xy[v].x - T.xy[w].x, dy = T.xy[v].y - T.xy[w].y;
        best = std::min(best, dx * dx + dy * dy);
      }
      ASSERT_EQ(T.nn2[v], static_cast<float>(best)) << v;
    }
  }
}

TEST(OutlineDelaunay, ResultReportsTheSearchCounters) {
  const auto pts = grid_cloud(30, 20, 1, {}, 0.2);
  // The default options: DSHI, BRIO order.
  const Triangulation T = triangulate(pts, Mode::DSHI, Order::Brio);
  const Result r = compute_outline(pts);
  const TriangulationStats& s = r.stats;
  EXPECT_EQ(s.search_cost, s.search_cost_locate + s.search_cost_cavity);
  EXPECT_EQ(s.search_cost_locate, T.stats.locate_visits);
  EXPECT_EQ(s.search_cost_cavity, T.stats.cavity_visits);
  EXPECT_EQ(s.cavity_triangles, T.stats.cavity_triangles);
  EXPECT_EQ(s.incircle_tests, T.stats.incircle_tests);
  // Every insertion deletes at least one triangle and locates with at least one visit.
  EXPECT_GE(s.cavity_triangles, pts.size() - 3);
  EXPECT_GE(s.search_cost_locate, pts.size() - 3);
  // Each cavity triangle but the located one, and each triangle across the cavity's boundary, was tested.
  EXPECT_GE(s.search_cost_cavity, s.cavity_triangles - (pts.size() - 3));
  EXPECT_EQ(r.mode, Mode::DSHI);
  EXPECT_EQ(r.order, Order::Brio);
  EXPECT_EQ(r.stats.triangles, T.finite_count());
  EXPECT_GE(r.time.total_ms, r.time.triangulate_ms);
}
