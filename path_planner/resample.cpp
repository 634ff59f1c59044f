// Step 3: resample a closed ring at a fixed step along the path, keeping corners as waypoints.
#include "path_planner/pipeline.hpp"

#include <cmath>

namespace hg::path_planner {

SampledRing resample_ring(const Ring& ring, double step, double corner_angle) {
  SampledRing out;
  const std::size_t n = ring.size();
  if (n < 3 || !(step > 0)) {
    out.points = ring;
    out.corner.assign(n, 0);
    return out;
  }
  std::vector<std::size_t> corners;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = ring[i] - ring[(i + n - 1) % n], b = ring[(i + 1) % n] - ring[i];
    if (a.squaredNorm() == 0 || b.squaredNorm() == 0) continue;
    const double t = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    if (std::abs(t) > corner_angle) corners.push_back(i);
  }
  const bool has_corners = !corners.empty();
  if (!has_corners) corners.push_back(0);
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const std::size_t c0 = corners[k];
    const std::size_t c1 = corners[(k + 1) % corners.size()];
    // Vertices of this piece: c0, c0+1, ..., c1 (wrapping; a single corner means the whole ring).
    std::size_t count = (c1 + n - c0) % n;
    if (count == 0) count = n;
    double length = 0;
    for (std::size_t j = 0; j < count; ++j) length += (ring[(c0 + j + 1) % n] - ring[(c0 + j) % n]).norm();
    const std::size_t m = std::max<std::size_t>(1, std::size_t(std::ceil(length / step - 1e-9)));
    const double h = length / double(m);
    out.points.push_back(ring[c0]);
    out.corner.push_back(has_corners ? 1 : 0);
    // Walk the piece and emit points at h, 2h, ..., (m-1)h.
    std::size_t seg = 0;
    double seg_start = 0;
    for (std::size_t q = 1; q < m; ++q) {
      const double target = h * double(q);
      while (seg + 1 < count) {
        const double len = (ring[(c0 + seg + 1) % n] - ring[(c0 + seg) % n]).norm();
        if (seg_start + len >= target) break;
        seg_start += len;
        ++seg;
      }
      const Vec2 a = ring[(c0 + seg) % n], b = ring[(c0 + seg + 1) % n];
      const double len = (b - a).norm();
      const double f = len > 0 ? std::min(1.0, (target - seg_start) / len) : 0.0;
      out.points.push_back(a + f * (b - a));
      out.corner.push_back(0);
    }
  }
  return out;
}

}  // namespace hg::path_planner
