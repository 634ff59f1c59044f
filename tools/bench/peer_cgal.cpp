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
  std::vector<std::pair<K::Point_2, std::uint32_t>> input;
  input.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    input.emplace_back(K::Point_2(points[i].x, points[i].y), static_cast<std::uint32_t>(i));
  Dt dt;
  dt.insert(input.begin(), input.end());  // spatial sort, then insertion (duplicates: first one kept)

  // Circumradius pass (the same rule as ours: r <= R is inside; inexact constructions, as a user would).
  const double R2 = R * R;
  const auto squared_radius = K().compute_squared_radius_2_object();
  std::size_t triangles = 0;
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    f->info() = squared_radius(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()) <= R2;
    ++triangles;
  }
  for (auto f = dt.all_face_handles().begin(); f != dt.all_face_handles().end(); ++f)
    if (dt.is_infinite(*f)) (*f)->info() = 0;

  // Free half-edges (inside face on the left, outside or infinite on the right), a -> b counter-clockwise
  // around the inside.
  std::vector<std::uint32_t> edge_from, edge_to;
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    if (!f->info()) continue;
    for (int i = 0; i < 3; ++i)
      if (!f->neighbor(i)->info()) {
        edge_from.push_back(f->vertex(Dt::ccw(i))->info());
        edge_to.push_back(f->vertex(Dt::cw(i))->info());
      }
  }
  PeerOutline out = free_edge_loops(points, edge_from, edge_to);
  out.triangles = triangles;
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
