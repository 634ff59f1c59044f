// The loop chaining every Delaunay peer of hg-bench shares (peers.hpp: free_edge_loops).
#include <cstdint>
#include <vector>

#include "peers.hpp"

namespace hg::bench {

PeerOutline free_edge_loops(std::span<const outline::Vec2> points, const std::vector<std::uint32_t>& edge_from,
                            const std::vector<std::uint32_t>& edge_to) {
  // Chained through a per-vertex list of outgoing edges (pinches: any unused one).
  PeerOutline out;
  const std::size_t n = points.size();
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

}  // namespace hg::bench
