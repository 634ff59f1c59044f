// delaunator-cpp peer of hg-bench: delaunator::Delaunator (header-only, fetched outside the repository;
// docs/BENCHMARKS.md) + the same circumradius pass and loops as the CGAL DT peer.
#include <delaunator.hpp>

#include <cstdint>
#include <vector>

#include "peers.hpp"

namespace hg::bench {

PeerOutline delaunator_dt_loops(std::span<const outline::Vec2> points, double R) {
  std::vector<double> coords;
  coords.reserve(2 * points.size());
  for (const auto& p : points) {
    coords.push_back(p.x);
    coords.push_back(p.y);
  }
  const delaunator::Delaunator d(coords);  // duplicates are left out of the triangles
  const std::vector<std::size_t>& tri = d.triangles;
  const std::size_t nt = tri.size() / 3;

  // Circumradius pass (r <= R inside, floating point as a user would: delaunator's own circumradius,
  // which returns r^2).
  const double R2 = R * R;
  std::vector<std::uint8_t> inside(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const std::size_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
    inside[t] = delaunator::circumradius(coords[2 * a], coords[2 * a + 1], coords[2 * b], coords[2 * b + 1],
                                         coords[2 * c], coords[2 * c + 1]) <= R2;
  }

  // Free half-edges: inside triangle on one side, outside or nothing (hull) on the other, directed
  // counter-clockwise around the inside. delaunator's triangles turn one way throughout; which way is
  // read off the first one.
  bool ccw = true;
  if (nt > 0) {
    const outline::Vec2 &a = points[tri[0]], &b = points[tri[1]], &c = points[tri[2]];
    ccw = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x) > 0;
  }
  std::vector<std::uint32_t> edge_from, edge_to;
  for (std::size_t e = 0; e < tri.size(); ++e) {
    if (!inside[e / 3]) continue;
    const std::size_t twin = d.halfedges[e];
    if (twin != delaunator::INVALID_INDEX && inside[twin / 3]) continue;
    const std::size_t next = e % 3 == 2 ? e - 2 : e + 1;
    edge_from.push_back(static_cast<std::uint32_t>(ccw ? tri[e] : tri[next]));
    edge_to.push_back(static_cast<std::uint32_t>(ccw ? tri[next] : tri[e]));
  }
  PeerOutline out = free_edge_loops(points, edge_from, edge_to);
  out.triangles = nt;
  return out;
}

}  // namespace hg::bench
