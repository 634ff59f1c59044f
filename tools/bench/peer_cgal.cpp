// CGAL peers of hg-bench: Delaunay_triangulation_2 + circumradius + loops, and Alpha_shape_2.
#include <CGAL/Alpha_shape_2.h>
#include <CGAL/Alpha_shape_face_base_2.h>
#include <CGAL/Alpha_shape_vertex_base_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "peers.hpp"

namespace hg::bench {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using Fb = CGAL::Triangulation_face_base_with_info_2<std::uint8_t, K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Dt = CGAL::Delaunay_triangulation_2<K, Tds>;

}  // namespace

PeerOutline cgal_dt_loops(std::span<const outline::Vec2> points, double R) {
  PeerOutline out;
  std::vector<std::pair<K::Point_2, std::uint32_t>> input;
  input.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    input.emplace_back(K::Point_2(points[i].x, points[i].y), static_cast<std::uint32_t>(i));
  Dt dt;
  dt.insert(input.begin(), input.end());  // spatial sort, then insertion (duplicates: first one kept)

  // Circumradius pass (the same rule as ours: r <= R is inside; inexact constructions, as a user would).
  const double R2 = R * R;
  const auto squared_radius = K().compute_squared_radius_2_object();
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    f->info() = squared_radius(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()) <= R2;
    ++out.triangles;
  }
  for (auto f = dt.all_face_handles().begin(); f != dt.all_face_handles().end(); ++f)
    if (dt.is_infinite(*f)) (*f)->info() = 0;

  // Free half-edges (inside face on the left, outside or infinite on the right), a -> b counter-clockwise
  // around the inside; chained through a per-vertex list of outgoing edges (pinches: any unused one).
  const std::size_t n = points.size();
  std::vector<std::uint32_t> edge_from, edge_to;
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    if (!f->info()) continue;
    for (int i = 0; i < 3; ++i)
      if (!f->neighbor(i)->info()) {
        edge_from.push_back(f->vertex(Dt::ccw(i))->info());
        edge_to.push_back(f->vertex(Dt::cw(i))->info());
      }
  }
  const std::size_t m = edge_from.size();
  out.boundary_edges = m;
  std::vector<std::uint32_t> head(n, UINT32_MAX), next_out(m, UINT32_MAX);
  for (std::uint32_t e = 0; e < m; ++e) {
    next_out[e] = head[edge_from[e]];
    head[edge_from[e]] = e;
  }
  std::vector<std::uint8_t> used(m, 0);
  for (std::uint32_t e0 = 0; e0 < m; ++e0) {
    if (used[e0]) continue;
    double twice_area = 0;
    std::uint32_t e = e0;
    while (e != UINT32_MAX && !used[e]) {
      used[e] = 1;
      const outline::Vec2 &a = points[edge_from[e]], &b = points[edge_to[e]];
      twice_area += a.x * b.y - a.y * b.x;
      // Next: an unused outgoing edge of the end vertex (pop used ones off the list).
      std::uint32_t& h = head[edge_to[e]];
      while (h != UINT32_MAX && used[h]) h = next_out[h];
      e = h;
    }
    if (twice_area > 0) ++out.outer_loops;
    else
      ++out.holes;
    out.area += twice_area / 2;
  }
  return out;
}

PeerOutline cgal_alpha_shape(std::span<const outline::Vec2> points, double R) {
  using AVb = CGAL::Alpha_shape_vertex_base_2<K>;
  using AFb = CGAL::Alpha_shape_face_base_2<K>;
  using ATds = CGAL::Triangulation_data_structure_2<AVb, AFb>;
  using ADt = CGAL::Delaunay_triangulation_2<K, ATds>;
  using Alpha = CGAL::Alpha_shape_2<ADt>;
  PeerOutline out;
  std::vector<K::Point_2> input;
  input.reserve(points.size());
  for (const auto& p : points) input.emplace_back(p.x, p.y);
  Alpha A(input.begin(), input.end(), K::FT(R * R), Alpha::REGULARIZED);
  out.triangles = A.number_of_faces();
  for (auto e = A.alpha_shape_edges_begin(); e != A.alpha_shape_edges_end(); ++e) ++out.boundary_edges;
  return out;
}

}  // namespace hg::bench
