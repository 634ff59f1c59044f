// Agreement with CGAL: for the same R, our boundary edges equal the REGULAR edges of CGAL's
// Alpha_shape_2 in REGULARIZED mode with alpha = R^2, computed with exact rational arithmetic on the
// same coordinates (as given). CGAL classifies a face interior when its squared radius <= alpha, the
// same convention as ours (r == R stays inside); the grid clouds make r == R happen on purpose.
#include <gtest/gtest.h>

#include <CGAL/Alpha_shape_2.h>
#include <CGAL/Alpha_shape_face_base_2.h>
#include <CGAL/Alpha_shape_vertex_base_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <set>

#include "clouds.hpp"
#include "outline_core/delaunay.hpp"

using namespace hg::outline;
using namespace hg::outline::testing;

namespace {

using K = CGAL::Simple_cartesian<CGAL::Exact_rational>;
using Vbi = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using Vb = CGAL::Alpha_shape_vertex_base_2<K, Vbi>;
using Fb = CGAL::Alpha_shape_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Dt = CGAL::Delaunay_triangulation_2<K, Tds>;
using AlphaShape = CGAL::Alpha_shape_2<Dt>;
using Edge = std::pair<std::uint32_t, std::uint32_t>;

Edge undirected(std::uint32_t a, std::uint32_t b) { return a < b ? Edge{a, b} : Edge{b, a}; }

std::set<Edge> cgal_boundary(const std::vector<Vec2>& pts, double R) {
  // CGAL gets the input coordinates as given (exact rationals of those doubles), with the input index of
  // each distinct point's first occurrence as info.
  const Triangulation T = triangulate(pts, Mode::DSHI, Order::AsIs);
  std::vector<std::pair<K::Point_2, std::uint32_t>> in;
  for (std::size_t v = 0; v < T.xy.size(); ++v)
    if (T.vrep[v] == v) in.push_back({K::Point_2(pts[T.ids[v]].x, pts[T.ids[v]].y), T.ids[v]});
  const CGAL::Exact_rational alpha = CGAL::Exact_rational(R) * CGAL::Exact_rational(R);
  AlphaShape as(in.begin(), in.end(), alpha, AlphaShape::REGULARIZED);
  std::set<Edge> out;
  for (auto it = as.alpha_shape_edges_begin(); it != as.alpha_shape_edges_end(); ++it) {
    const auto f = it->first;
    const int i = it->second;
    out.insert(undirected(f->vertex(AlphaShape::cw(i))->info(), f->vertex(AlphaShape::ccw(i))->info()));
  }
  return out;
}

// threads > 1: the strips of the threaded path (small clouds allowed); threads_used reports the path run.
std::set<Edge> our_boundary(const std::vector<Vec2>& pts, double R, Mode m, Order o, int threads = 1,
                            int* threads_used = nullptr) {
  Options opt;
  opt.alpha_radius = R;
  opt.mode = m;
  opt.order = o;
  opt.min_hole_spacings = 0;  // the raw alpha shape, as CGAL's: no hole rule
  opt.threads = threads;
  opt.min_points_per_thread = 300;
  const Result r = compute_outline(pts, opt);
  if (threads_used) *threads_used = r.threads_used;
  std::set<Edge> out;
  for (const Loop& L : r.loops)
    for (std::size_t i = 0; i < L.point_index.size(); ++i)
      out.insert(undirected(L.point_index[i], L.point_index[(i + 1) % L.point_index.size()]));
  return out;
}

void expect_agreement(const std::vector<Vec2>& pts, const std::vector<double>& radii) {
  for (double R : radii) {
    const auto want = cgal_boundary(pts, R);
    for (Mode m : {Mode::DS, Mode::DSHI})
      for (Order o : {Order::AsIs, Order::Hilbert}) {
        SCOPED_TRACE("R " + std::to_string(R) + " " + to_string(m) + " " + to_string(o));
        const auto got = our_boundary(pts, R, m, o);
        EXPECT_EQ(got.size(), want.size());
        EXPECT_TRUE(got == want);
      }
    for (int threads : {2, 3}) {  // the threaded path (vertical strips) against CGAL too
      SCOPED_TRACE("R " + std::to_string(R) + " threads " + std::to_string(threads));
      int used = 0;
      const auto got = our_boundary(pts, R, Mode::DSHI, Order::Brio, threads, &used);
      EXPECT_EQ(used, threads);
      EXPECT_TRUE(got == want);
    }
  }
}

}  // namespace

TEST(OutlineCgal, RandomCloud) { expect_agreement(random_cloud(2500, 41, 100), {1.5, 2.2, 3.0, 5.0}); }

TEST(OutlineCgal, GridWithHolesAndRadiusExactlyAtTheCellRadius) {
  // Unit grid with dropped points: cells have r^2 = 1/2 exactly, a missing point makes r = 1 exactly;
  // R = 1 and R = sqrt(1/2) rounded hit or straddle these ties.
  auto g = grid_cloud(40, 30);
  std::vector<Vec2> pts;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (const Vec2& p : g)
    if (u(rng) > 0.08 && !(std::hypot(p.x - 20, p.y - 15) < 6)) pts.push_back(p);
  expect_agreement(pts, {1.0, std::sqrt(0.5), std::nextafter(std::sqrt(0.5), 1.0), 1.25, 2.5});
}

TEST(OutlineCgal, JitteredPlateWithDropout) {
  auto g = grid_cloud(50, 40, 2.0, {3, -7}, 0.2, 9);
  std::vector<Vec2> pts;
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(0, 1);
  for (const Vec2& p : g)
    if (u(rng) > 0.02 && std::hypot(p.x - 50, p.y - 33) > 9) pts.push_back(p);
  expect_agreement(pts, {1.8, 2.6, 3.4});
}
