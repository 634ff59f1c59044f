// The peers hg-bench compares against, each behind a plain interface so the main program needs none of
// CGAL's, delaunator-cpp's or PCL's headers (they are optional: HG_BENCH_CGAL / HG_BENCH_DELAUNATOR /
// HG_BENCH_PCL say which were built in).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "outline_core/outline.hpp"

namespace hg::bench {

// What a peer found, for a sanity check against our outline (same points, same R).
struct PeerOutline {
  std::size_t triangles = 0;       // finite Delaunay triangles (0 when the peer does not say)
  std::size_t boundary_edges = 0;  // edges of the outline
  std::size_t outer_loops = 0, holes = 0;
  double area = 0;  // enclosed area (outer minus holes), 0 when the peer does not give it
};

// CGAL Delaunay_triangulation_2 (Epick, range insertion with CGAL's spatial sort) + a circumradius pass
// (a face is inside when its squared circumradius <= R^2) + chaining the free edges into loops.
PeerOutline cgal_dt_loops(std::span<const outline::Vec2> points, double R);
// delaunator-cpp (github delfrrr/delaunator-cpp, header-only) + the same circumradius pass and loops.
PeerOutline delaunator_dt_loops(std::span<const outline::Vec2> points, double R);
// The loops of the free half-edges edge_from[e] -> edge_to[e] (inside on their left; indices into
// points), chained through the outgoing edges of each vertex (a pinch: any unused one); the Delaunay peers
// share it. Fills boundary_edges, outer_loops, holes, area.
PeerOutline free_edge_loops(std::span<const outline::Vec2> points, const std::vector<std::uint32_t>& edge_from,
                            const std::vector<std::uint32_t>& edge_to);
// CGAL Alpha_shape_2 in REGULARIZED mode with alpha = R^2; counts the REGULAR edges.
PeerOutline cgal_alpha_shape(std::span<const outline::Vec2> points, double R);
// PCL ConcaveHull, dimension 2, setAlpha(R) (PCL keeps a Delaunay triangle when its circumradius <= alpha).
PeerOutline pcl_concave_hull(std::span<const outline::Vec2> points, double R);

}  // namespace hg::bench
