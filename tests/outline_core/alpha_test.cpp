// Alpha shape and loops: known shapes with analytic loops, pinches, outer-only, and on random clouds an
// independent reconstruction of the free edges from an exact (GMP) circumradius classification.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <map>
#include <set>

#include "clouds.hpp"
#include "exact_checker.hpp"
#include "outline_core/alpha.hpp"
#include "outline_core/delaunay.hpp"

using namespace hg::outline;
using namespace hg::outline::testing;

namespace {

double signed_area(const Loop& L) {
  double a = 0;
  for (std::size_t i = 0; i < L.points.size(); ++i) {
    const Vec2 &p = L.points[i], &q = L.points[(i + 1) % L.points.size()];
    a += p.x * q.y - q.x * p.y;
  }
  return a / 2;
}

// Square [0,20]^2 of unit grid points without the points strictly inside (5,15)^2.
std::vector<Vec2> square_with_hole() {
  std::vector<Vec2> p;
  for (int y = 0; y <= 20; ++y)
    for (int x = 0; x <= 20; ++x)
      if (!(x > 5 && x < 15 && y > 5 && y < 15)) p.push_back({double(x), double(y)});
  return p;
}

std::vector<Vec2> square(int x0, int y0, int size) {
  std::vector<Vec2> p;
  for (int y = 0; y <= size; ++y)
    for (int x = 0; x <= size; ++x) p.push_back({double(x0 + x), double(y0 + y)});
  return p;
}

// Circular plate holes, uniform in-plane noise of +-amp spacings, dropout (docs/outline-auto-radius.md).
std::vector<Vec2> noisy_plate(int W, int H, const std::vector<double>& diam, double amp, double drop,
                              std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), v(0, 1);
  std::vector<Vec2> p;
  const int nh = static_cast<int>(diam.size());
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      bool in_hole = false;
      for (int k = 0; k < nh; ++k) {
        const double cx = (k + 1.0) * W / (nh + 1), cy = H / 2.0 + 0.37 * k, r = diam[k] / 2;
        if ((x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r) in_hole = true;
      }
      if (in_hole || v(rng) < drop) continue;
      p.push_back({x + amp * u(rng), y + amp * u(rng)});
    }
  return p;
}

}  // namespace

TEST(OutlineAlpha, SquareWithSquareHole) {
  const auto pts = square_with_hole();
  for (Mode m : {Mode::Ordinary, Mode::DS, Mode::DSHI})
    for (Order o : {Order::AsIs, Order::Hilbert, Order::Brio}) {
      SCOPED_TRACE(std::string(to_string(m)) + " " + to_string(o));
      Options opt;
      opt.alpha_radius = 1;  // grid cells: r = 0.707; inside the hole every triangle spans >= sqrt(5)
      opt.mode = m;
      opt.order = o;
      const Result r = compute_outline(pts, opt);
      ASSERT_EQ(r.loops.size(), 2u);
      const Loop &outer = r.loops[0], &hole = r.loops[1];
      EXPECT_FALSE(outer.hole);
      EXPECT_TRUE(hole.hole);
      EXPECT_EQ(outer.area, 400.0);
      EXPECT_GT(signed_area(outer), 0);  // counter-clockwise
      EXPECT_EQ(outer.points.size(), 80u);
      EXPECT_DOUBLE_EQ(outer.perimeter, 80.0);
      // The hole is the 10 x 10 square with its four corner cells cut diagonally (the half-cell at each
      // corner, e.g. (5,5)-(6,5)-(5,6), has r = 0.707 and is inside).
      EXPECT_EQ(hole.area, 98.0);
      EXPECT_LT(signed_area(hole), 0);  // clockwise
      EXPECT_EQ(hole.points.size(), 36u);
      EXPECT_NEAR(hole.perimeter, 32 + 4 * std::sqrt(2.0), 1e-12);
      for (std::size_t i = 0; i < hole.points.size(); ++i) {
        const Vec2 p = hole.points[i];
        EXPECT_EQ(pts[hole.point_index[i]].x, p.x);
        EXPECT_EQ(pts[hole.point_index[i]].y, p.y);
        EXPECT_TRUE(p.x == 5 || p.x == 15 || p.y == 5 || p.y == 15);
      }
      EXPECT_EQ(r.points_read, pts.size());
      EXPECT_EQ(r.points_used, pts.size());
      EXPECT_EQ(r.duplicates_merged, 0u);
      EXPECT_FALSE(r.alpha_automatic);
      EXPECT_EQ(r.alpha_radius, 1.0);
    }
}

TEST(OutlineAlpha, OuterOnlyKeepsTheHoleFilled) {
  Options opt;
  opt.alpha_radius = 1;
  opt.outer_only = true;
  const Result r = compute_outline(square_with_hole(), opt);
  ASSERT_EQ(r.loops.size(), 1u);
  EXPECT_FALSE(r.loops[0].hole);
  EXPECT_EQ(r.loops[0].area, 400.0);
}

TEST(OutlineAlpha, OuterOnlyStillCutsNotchesOpenToTheOutside) {
  // A U shape: the notch's big triangles connect to the outside, so the paper's BFS removes them.
  std::vector<Vec2> p;
  for (int y = 0; y <= 20; ++y)
    for (int x = 0; x <= 20; ++x)
      if (!(x > 6 && x < 14 && y > 6)) p.push_back({double(x), double(y)});
  Options opt;
  opt.alpha_radius = 1;
  opt.outer_only = true;
  const Result r = compute_outline(p, opt);
  ASSERT_EQ(r.loops.size(), 1u);
  // Area of the U: 400 minus the notch (x in (6,14), y in (6,20]) with its two bottom corner half-cells kept.
  EXPECT_EQ(r.loops[0].area, 400.0 - 8 * 14 + 1.0);
}

TEST(OutlineAlpha, TwoSeparateSquaresGiveTwoOuterLoops) {
  auto p = square(0, 0, 5);
  const auto q = square(10, 3, 5);
  p.insert(p.end(), q.begin(), q.end());
  Options opt;
  opt.alpha_radius = 1;
  const Result r = compute_outline(p, opt);
  ASSERT_EQ(r.loops.size(), 2u);
  for (const Loop& L : r.loops) {
    EXPECT_FALSE(L.hole);
    EXPECT_EQ(L.area, 25.0);
    EXPECT_EQ(L.points.size(), 20u);
  }
}

TEST(OutlineAlpha, BowtiePinchGivesTwoSimpleTriangles) {
  // Delaunay: 4 triangles around P; left/right have r = 1.25, top/bottom r = 2.5. R = 2 keeps left and
  // right, which touch only at P.
  const std::vector<Vec2> p{{0, 0}, {-2, 1}, {-2, -1}, {2, 1}, {2, -1}};
  Options opt;
  opt.alpha_radius = 2;
  const Result r = compute_outline(p, opt);
  ASSERT_EQ(r.loops.size(), 2u);
  for (const Loop& L : r.loops) {
    EXPECT_FALSE(L.hole);
    EXPECT_EQ(L.points.size(), 3u);
    EXPECT_EQ(L.area, 2.0);
    EXPECT_EQ(L.point_index[0], 0u);  // each loop starts at its smallest index: the pinch P
  }
  EXPECT_EQ(std::set<std::uint32_t>(r.loops[0].point_index.begin(), r.loops[0].point_index.end()),
            (std::set<std::uint32_t>{0, 1, 2}));
}

TEST(OutlineAlpha, HoleTouchingTheOuterBoundaryIsSplitIntoSimpleLoops) {
  // Square plate whose diamond-shaped hole touches the bottom edge at one vertex (10, 0): the free edges
  // form one closed chain through (10, 0) twice; it must come out as an outer loop and a hole.
  std::vector<Vec2> p;
  for (int y = 0; y <= 20; ++y)
    for (int x = 0; x <= 20; ++x)
      if (!(std::abs(x - 10) + std::abs(y - 6) < 6 && y > 0)) p.push_back({double(x), double(y)});
  // R = 0.9: grid cells (r = 0.707) stay, the triangles across the diamond's corners (r = 1) go.
  Options opt;
  opt.alpha_radius = 0.9;
  const Result r = compute_outline(p, opt);
  ASSERT_EQ(r.loops.size(), 2u);
  EXPECT_FALSE(r.loops[0].hole);
  EXPECT_TRUE(r.loops[1].hole);
  EXPECT_EQ(r.loops[1].area, 72.0);  // the diamond (10,0) (16,6) (10,12) (4,6)
  for (const Loop& L : r.loops) {
    EXPECT_EQ(std::set<std::uint32_t>(L.point_index.begin(), L.point_index.end()).size(), L.point_index.size());
    EXPECT_NE(std::find_if(L.points.begin(), L.points.end(), [](const Vec2& q) { return q.x == 10 && q.y == 0; }),
              L.points.end());
  }
  EXPECT_EQ(r.loops[0].area, 400.0);
}

TEST(OutlineAlpha, LoopsAreExactlyTheFreeEdgesOfAnExactClassification) {
  // Independent reconstruction: classify every Delaunay triangle with GMP (r^2 <= R^2 inside), collect
  // directed edges with inside on the left and outside/hull on the right; the loops' edges must be
  // exactly those, each loop a simple polygon (no repeated vertex, >= 3 vertices), and the signed loop
  // areas must add up to the inside area.
  std::size_t pinches = 0, loops_seen = 0;
  for (std::uint64_t seed : {1, 2, 3, 4}) {
    auto pts = random_cloud(1500, 100 + seed, 100);
    const auto extra = grid_cloud(20, 20, 2.5, {10, 10});  // some cocircular structure too
    pts.insert(pts.end(), extra.begin(), extra.end());
    for (double R : {1.6, 2.0, 2.6, 3.5, 6.0})
      for (bool outer_only : {false, true}) {
        SCOPED_TRACE("seed " + std::to_string(seed) + " R " + std::to_string(R) + (outer_only ? " outer-only" : ""));
        Options opt;
        opt.alpha_radius = R;
        opt.outer_only = outer_only;
        opt.keep_triangles = true;
        opt.min_hole_spacings = 0;  // every free edge: the raw alpha shape, no hole rule
        const Result r = compute_outline(pts, opt);
        const Triangulation T = triangulate(pts, Mode::DSHI, Order::AsIs);
        // Independent classification on the same translated coordinates.
        std::vector<Q2> q(T.xy.size());
        for (std::size_t v = 0; v < q.size(); ++v) q[v] = exact(T.xy[v]);
        const mpq_class R2 = mpq_class(R) * mpq_class(R);
        std::vector<char> in(T.slots(), 0);
        for (std::size_t t = 0; t < T.slots(); ++t)
          if (!T.is_ghost(t)) in[t] = circumradius2_q(q[T.tri[3 * t]], q[T.tri[3 * t + 1]], q[T.tri[3 * t + 2]]) <= R2;
        if (outer_only) {  // flood from the ghosts through big triangles; big ones not reached are inside
          std::vector<char> out(T.slots(), 0);
          std::vector<std::size_t> st;
          for (std::size_t t = 0; t < T.slots(); ++t)
            if (T.is_ghost(t)) st.push_back(t), out[t] = 1;
          while (!st.empty()) {
            const std::size_t t = st.back();
            st.pop_back();
            for (int i = 0; i < 3; ++i) {
              const std::size_t nb = T.twin[3 * t + i] / 3;
              if (!out[nb] && !in[nb]) out[nb] = 1, st.push_back(nb);
            }
          }
          for (std::size_t t = 0; t < T.slots(); ++t) in[t] = !T.is_ghost(t) && !out[t];
        }
        std::multiset<std::pair<std::uint32_t, std::uint32_t>> want, got;
        double inside_area = 0;
        for (std::size_t t = 0; t < T.slots(); ++t) {
          if (!in[t]) continue;
          const Vec2 &a = T.xy[T.tri[3 * t]], &b = T.xy[T.tri[3 * t + 1]], &c = T.xy[T.tri[3 * t + 2]];
          inside_area += ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)) / 2;
          for (int i = 0; i < 3; ++i)
            if (!in[T.twin[3 * t + i] / 3]) want.insert({T.ids[T.tri[3 * t + i]], T.ids[T.tri[3 * t + (i + 1) % 3]]});
        }
        double loop_area = 0;
        std::map<std::uint32_t, int> uses;
        bool holes_started = false;
        for (const Loop& L : r.loops) {
          ASSERT_GE(L.point_index.size(), 3u);
          EXPECT_EQ(std::set<std::uint32_t>(L.point_index.begin(), L.point_index.end()).size(), L.point_index.size());
          EXPECT_EQ(L.hole, signed_area(L) < 0);
          if (L.hole) holes_started = true;
          else
            EXPECT_FALSE(holes_started) << "outer loops come first";
          loop_area += L.hole ? -L.area : L.area;
          for (std::size_t i = 0; i < L.point_index.size(); ++i) {
            got.insert({L.point_index[i], L.point_index[(i + 1) % L.point_index.size()]});
            ++uses[L.point_index[i]];
          }
        }
        EXPECT_TRUE(got == want) << got.size() << " vs " << want.size();
        EXPECT_NEAR(loop_area, inside_area, 1e-9 * 1e4);
        for (const auto& [v, k] : uses) pinches += k > 1;
        loops_seen += r.loops.size();
        // The kept Delaunay triangles are the triangulation's, in input indices.
        EXPECT_EQ(r.delaunay_triangles.size(), T.finite_count());
        EXPECT_EQ(r.stats.triangles, T.finite_count());
      }
  }
  EXPECT_GT(pinches, 0u) << "the clouds should exercise pinch vertices";
  EXPECT_GT(loops_seen, 40u);
}

TEST(OutlineAlpha, AutomaticRadiusFindsRealHolesAndNoSpuriousOnes) {
  // Noisy scan grids with 2 % dropout (seeds differ from those used to choose k): every hole wider than
  // 3 spacings is found, dropout makes no hole, the plate is one outer loop. The 3.2-spacing hole removes
  // exactly the 9 points of a 3x3 block, which the default hole rule drops as dropout
  // (docs/outline-auto-radius.md): this test checks the radius alone, with the hole rule off.
  for (double amp : {0.0, 0.1, 0.2})
    for (std::uint64_t seed : {11, 12}) {
      SCOPED_TRACE("amp " + std::to_string(amp) + " seed " + std::to_string(seed));
      const auto pts = noisy_plate(240, 160, {3.2, 4.0, 6.0, 12.0}, amp, 0.02, seed);
      Options opt;
      opt.min_hole_spacings = 0;
      const Result r = compute_outline(pts, opt);
      EXPECT_TRUE(r.alpha_automatic);
      EXPECT_NEAR(r.alpha_radius, kDefaultAutoFactor * r.spacing, 1e-12);
      EXPECT_EQ(r.holes_dropped, 0u);
      EXPECT_GT(r.nn_spacing_median, 1 - 2 * amp - 0.05);
      EXPECT_LE(r.nn_spacing_median, 1.0 + 1e-12);
      std::size_t outers = 0, holes = 0;
      for (const Loop& L : r.loops) (L.hole ? holes : outers)++;
      EXPECT_EQ(outers, 1u);
      EXPECT_EQ(holes, 4u);
    }
}

TEST(OutlineAlpha, DuplicatesAreMergedAndTrianglesReferToFirstOccurrences) {
  auto pts = square(0, 0, 6);
  const std::size_t distinct = pts.size();
  for (std::size_t i = 0; i < distinct; i += 3) pts.push_back(pts[i]);
  Options opt;
  opt.alpha_radius = 1;
  opt.keep_triangles = true;
  opt.order = Order::Hilbert;
  const Result r = compute_outline(pts, opt);
  EXPECT_EQ(r.points_read, pts.size());
  EXPECT_EQ(r.points_used, distinct);
  EXPECT_EQ(r.duplicates_merged, pts.size() - distinct);
  for (const auto& t : r.delaunay_triangles)
    for (std::uint32_t i : t) EXPECT_LT(i, distinct);
  ASSERT_EQ(r.loops.size(), 1u);
  EXPECT_EQ(r.loops[0].area, 36.0);
  for (std::uint32_t i : r.loops[0].point_index) EXPECT_LT(i, distinct);
}

TEST(OutlineAlpha, ExtremeRadii) {
  const auto pts = random_cloud(500, 77, 10);
  Options opt;
  opt.alpha_radius = 1e-6;  // every triangle is big: nothing inside, no loop
  EXPECT_TRUE(compute_outline(pts, opt).loops.empty());
  opt.alpha_radius = 1e6;  // nothing is big: one loop, the convex hull
  const Result r = compute_outline(pts, opt);
  ASSERT_EQ(r.loops.size(), 1u);
  std::vector<Q2> q;
  for (const Vec2& p : pts) q.push_back(exact(p));
  EXPECT_NEAR(r.loops[0].area, hull_area2_q(q).get_d() / 2, 1e-9);
  opt.alpha_radius = std::nan("");
  EXPECT_THROW(compute_outline(pts, opt), OutlineError);
}

TEST(OutlineAlpha, CoordinatesBeyondTheExactRangeAreRefused) {
  auto pts = random_cloud(50, 78, 10);
  pts[9] = {1e70, 0};
  try {
    compute_outline(pts);
    FAIL() << "no error";
  } catch (const OutlineError& e) {
    EXPECT_NE(std::string(e.what()).find("point 9 "), std::string::npos) << e.what();
  }
}

TEST(OutlineAlpha, ConsumingOverloadGivesTheSameOutlineAndReleasesThePoints) {
  // A jittered plate with a hole, coordinates on a 2^-20 grid (like float32 data): the translation to the
  // rounded origin is exact, so triangulate_releasing empties the vector, and the loops (coordinates
  // rebuilt from xy + origin) equal those computed from the points themselves.
  auto plate = grid_cloud(60, 40, 1, {1000, -500}, 0.2, 8);
  std::vector<Vec2> pts;
  for (Vec2 p : plate)
    if (std::hypot(p.x - 1030, p.y + 480) > 6)
      pts.push_back({std::round(p.x * 0x1p20) * 0x1p-20, std::round(p.y * 0x1p20) * 0x1p-20});
  {
    std::vector<Vec2> copy = pts;
    const Triangulation T = triangulate_releasing(copy, Mode::DSHI, Order::Brio);
    EXPECT_TRUE(copy.empty());
    for (std::size_t v = 0; v < T.xy.size(); ++v) {
      ASSERT_EQ(T.xy[v].x + T.origin.x, pts[T.ids[v]].x);
      ASSERT_EQ(T.xy[v].y + T.origin.y, pts[T.ids[v]].y);
    }
  }
  // Full-precision coordinates in [0, 1000]: translating those near zero to the origin (about 500) would
  // round away their low bits, so they are triangulated untranslated, and released all the same.
  const auto far = random_cloud(500, 3, 1000);
  const std::vector<Vec2>* clouds[] = {&pts, &far};
  for (const std::vector<Vec2>* cloud : clouds) {
    Options o;
    o.alpha_radius = cloud == &pts ? 1.2 : 60;
    const Result a = compute_outline(std::span<const Vec2>(*cloud), o);
    if (cloud == &far) {
      std::vector<Vec2> copy = far;
      const Triangulation T = triangulate_releasing(copy, Mode::DSHI, Order::Brio);
      EXPECT_TRUE(copy.empty());
      EXPECT_EQ(T.origin.x, 0.0);
      EXPECT_EQ(T.origin.y, 0.0);
      for (std::size_t v = 0; v < T.xy.size(); ++v) {
        ASSERT_EQ(T.xy[v].x, far[T.ids[v]].x);
        ASSERT_EQ(T.xy[v].y, far[T.ids[v]].y);
      }
    }
    const Result b = compute_outline(std::vector<Vec2>(*cloud), o);
    ASSERT_EQ(a.loops.size(), b.loops.size());
    if (cloud == &pts) {
      EXPECT_EQ(a.loops.size(), 2u);  // the plate and its hole
    }
    for (std::size_t k = 0; k < a.loops.size(); ++k) {
      EXPECT_EQ(a.loops[k].point_index, b.loops[k].point_index);
      EXPECT_EQ(a.loops[k].area, b.loops[k].area);
      ASSERT_EQ(a.loops[k].points.size(), b.loops[k].points.size());
      for (std::size_t i = 0; i < a.loops[k].points.size(); ++i) {
        EXPECT_EQ(a.loops[k].points[i].x, (*cloud)[a.loops[k].point_index[i]].x);
        EXPECT_EQ(b.loops[k].points[i].x, a.loops[k].points[i].x);
        EXPECT_EQ(b.loops[k].points[i].y, a.loops[k].points[i].y);
      }
    }
  }
}

TEST(OutlineAlpha, CircumradiusClassesGiveTheSameDecisionsAsThePredicateAlone) {
  // scan_triangles' coarse classes may only skip the exact predicate where it is certain: on clouds with
  // exact ties (grid cells r = sqrt(1/2), a missing point r = 1), noise, far offsets and tiny scales the
  // classification with the classes equals the one by the exact predicate for every triangle.
  std::vector<std::vector<Vec2>> clouds{grid_cloud(40, 30), grid_cloud(50, 40, 2.0, {3, -7}, 0.2, 9),
                                        random_cloud(3000, 5, 100), random_cloud(2000, 6, 1e-7, {1e6, -2e6})};
  std::mt19937_64 rng(3);
  for (std::size_t k = 0; k < clouds.size(); ++k) {
    auto& c = clouds[k];
    if (k == 0) std::erase_if(c, [&](const Vec2&) { return rng() % 20 == 0; });
    const Triangulation T = triangulate(c, Mode::DSHI, Order::Brio);
    const TriangleScan scan = scan_triangles(T);
    for (double f : {0.5, std::sqrt(0.5), 0.75, 1.0, 1.3, 1.7, 2.5, 10.0})
      for (bool outer_only : {false, true}) {
        const double R = k < 2 ? f * (k == 1 ? 2.0 : 1.0) : f * scan.spacing;
        SCOPED_TRACE("cloud " + std::to_string(k) + " R " + std::to_string(R));
        EXPECT_EQ(classify_alpha(T, R, outer_only, scan), classify_alpha(T, R, outer_only));
      }
  }
}

TEST(OutlineAlpha, TriangleMeasuresAreThoseOfTheThreePivotFormulaInEveryPass) {
  // measure_triangle and scan_triangles (two triangles a step) against the formulas written out here:
  // twice the signed area with each vertex as orient2d's pivot, the middle one halved; N the product of
  // the squared edge lengths; the class of N / (4 D^2 scale2) where D (pivot c) is far above its rounding
  // bound. Bit for bit (signs of zero included), on grids (exact ties, zero differences), noise, and full
  // precision far from the origin at tiny and large scales.
  auto bits = [](double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, 8);
    return b;
  };
  auto twice_area = [](const Vec2& p, const Vec2& q, const Vec2& pivot) {
    return (p.x - pivot.x) * (q.y - pivot.y) - (p.y - pivot.y) * (q.x - pivot.x);
  };
  const std::vector<std::vector<Vec2>> clouds{grid_cloud(40, 30), grid_cloud(50, 40, 2.0, {3, -7}, 0.2, 9),
                                              random_cloud(3001, 5, 100), random_cloud(2000, 6, 1e-7, {1e6, -2e6}),
                                              random_cloud(1500, 7, 1e9, {-3e12, 5e11})};
  for (std::size_t k = 0; k < clouds.size(); ++k) {
    const Triangulation T = triangulate(clouds[k], Mode::DSHI, Order::Brio);
    const double scale2 = class_scale(T);
    const TriangleScan by_selection = scan_triangles(T), by_histogram = scan_triangles(T, 0);
    std::vector<std::pair<std::size_t, TriangleMeasure>> expected;  // finite slot, its figures
    for (std::size_t t = 0; t < T.slots(); ++t) {
      if (T.is_ghost(t)) continue;
      const Vec2 &a = T.xy[T.tri[3 * t]], &b = T.xy[T.tri[3 * t + 1]], &c = T.xy[T.tri[3 * t + 2]];
      const double da = twice_area(b, c, a), db = twice_area(c, a, b), dc = twice_area(a, b, c);
      const double area = std::fabs(std::max(std::min(da, db), std::min(std::max(da, db), dc))) / 2;
      const double N = ((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y)) *
                       ((b.x - c.x) * (b.x - c.x) + (b.y - c.y) * (b.y - c.y)) *
                       ((c.x - a.x) * (c.x - a.x) + (c.y - a.y) * (c.y - a.y));
      const double errD =
          pred::kOrientBound * (std::fabs((a.x - c.x) * (b.y - c.y)) + std::fabs((a.y - c.y) * (b.x - c.x)));
      const double den = 4 * (dc * dc) * scale2;
      std::uint8_t rclass = kUndecidedClass;
      if (std::fabs(dc) > 1e6 * errD && std::isnormal(N) && std::isnormal(den) && std::isnormal(N / den))
        rclass = r2_class(N / den);
      expected.push_back({t, {area, rclass, N, dc}});
    }
    auto points = [&](std::size_t t) {
      return std::array<const Vec2*, 3>{&T.xy[T.tri[3 * t]], &T.xy[T.tri[3 * t + 1]], &T.xy[T.tri[3 * t + 2]]};
    };
    auto expect_same = [&](const TriangleMeasure& m, const TriangleMeasure& e, const char* what, std::size_t t) {
      SCOPED_TRACE(std::string(what) + ", cloud " + std::to_string(k) + ", triangle " + std::to_string(t));
      EXPECT_EQ(bits(m.area), bits(e.area));
      EXPECT_EQ(bits(m.N), bits(e.N));
      EXPECT_EQ(bits(m.D), bits(e.D));
      EXPECT_EQ(m.rclass, e.rclass);
    };
    for (std::size_t i = 0; i < expected.size(); ++i) {
      const auto& [t, e] = expected[i];
      const auto p = points(t);
      expect_same(measure_triangle(*p[0], *p[1], *p[2], scale2), e, "one", t);
      EXPECT_EQ(by_selection.rclass[t], e.rclass) << "cloud " << k << " triangle " << t;
      EXPECT_EQ(by_histogram.rclass[t], e.rclass) << "cloud " << k << " triangle " << t;
      // Two at a time: with the next finite triangle (each in either lane), and with itself.
      const auto& [u, f] = expected[(i + 1) % expected.size()];
      const auto q = points(u);
      TriangleMeasure m0, m1;
      measure_pair(p.data(), q.data(), scale2, m0, m1);
      expect_same(m0, e, "pair, lane 0", t);
      expect_same(m1, f, "pair, lane 1", u);
      measure_pair(q.data(), p.data(), scale2, m0, m1);
      expect_same(m1, e, "pair, lane 1", t);
      measure_pair(p.data(), p.data(), scale2, m0, m1);
      expect_same(m0, e, "pair with itself", t);
    }
    if (::testing::Test::HasFailure()) return;
    const std::size_t checked = expected.size();
    EXPECT_GT(checked, clouds[k].size());  // about two triangles a point
  }
}

TEST(OutlineAlpha, RadixSelectionEqualsNthElement) {
  // select_rank against std::nth_element on keys with many ties, narrow and full 32-bit ranges, with and
  // without common high bits, every size from a handful (the nth_element path) to tens of thousands.
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    std::mt19937_64 rng(seed);
    const std::size_t n = 1 + rng() % (seed < 30 ? 200 : 40000);
    const std::uint32_t mask = seed % 3 == 0 ? 0xffffffffu : (seed % 3 == 1 ? 0x3ffu : 0x7ff00fffu);
    std::vector<std::uint32_t> keys(n);
    // Half the seeds share high bits (as the areas of one cloud share their exponent).
    const std::uint32_t common = seed % 2 == 0 ? 0x5a5a5a5au & ~mask : 0;
    for (auto& k : keys) k = common | (static_cast<std::uint32_t>(rng()) & mask);
    for (std::size_t rank : {std::size_t{0}, n / 2, n - 1, static_cast<std::size_t>(rng() % n)}) {
      std::vector<std::uint32_t> a = keys, b = keys;
      std::nth_element(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(rank), b.end());
      EXPECT_EQ(select_rank(a, rank), b[rank]) << "seed " << seed << " n " << n << " rank " << rank;
    }
  }
}

TEST(OutlineAlpha, MedianSpacingIsTheSameBySelectionAndByHistogram) {
  // The spacing is the bucket of the median triangle area whichever way it is found (the small clouds'
  // selection, the large ones' 2 MB histogram), and equals the bucket of the median of the areas computed
  // here independently (triangle_area, sorted). Clouds with exact ties (grids), noise and random sets.
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    std::vector<Vec2> c = seed % 3 == 0   ? grid_cloud(30 + static_cast<int>(seed), 25)
                          : seed % 3 == 1 ? grid_cloud(40, 30, 2.0, {3, -7}, 0.2, seed)
                                          : random_cloud(1000 + 300 * seed, seed, 50);
    const Triangulation T = triangulate(c, Mode::DSHI, Order::Brio);
    std::vector<double> areas;
    for (std::size_t t = 0; t < T.slots(); ++t)
      if (!T.is_ghost(t))
        areas.push_back(triangle_area(T.xy[T.tri[3 * t]], T.xy[T.tri[3 * t + 1]], T.xy[T.tri[3 * t + 2]]));
    std::sort(areas.begin(), areas.end());
    std::uint32_t expected_bucket = 0;
    ASSERT_TRUE(AreaHistogram::bucket_of(areas[areas.size() / 2], expected_bucket));
    const double expected = AreaHistogram::spacing_of(expected_bucket);
    EXPECT_EQ(scan_triangles(T, 0).spacing, expected) << "seed " << seed;              // histogram
    EXPECT_EQ(scan_triangles(T, T.slots() + 1).spacing, expected) << "seed " << seed;  // selection
    EXPECT_EQ(scan_triangles(T, 0).rclass, scan_triangles(T, T.slots() + 1).rclass) << "seed " << seed;
    // The nearest-neighbour median: selection (median_nn_spacing on a small cloud), the 256 KB radix
    // histogram (median_distance) and a sort agree exactly.
    std::vector<float> nn2;
    for (std::size_t v = 0; v < T.nn2.size(); ++v)
      if (T.vrep[v] == v) nn2.push_back(T.nn2[v]);
    std::vector<float> sorted = nn2;
    std::sort(sorted.begin(), sorted.end());
    const double nn = std::sqrt(static_cast<double>(sorted[sorted.size() / 2]));
    EXPECT_EQ(median_nn_spacing(T), nn) << "seed " << seed;
    EXPECT_EQ(median_distance(nn2), nn) << "seed " << seed;
  }
}
