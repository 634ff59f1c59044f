// Step 3: resample a closed ring at a fixed step along the path, keeping corners as waypoints.
#include "path_planner/pipeline.hpp"

#include <algorithm>
#include <cmath>

namespace hg::path_planner {

namespace {

double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// The piece of `count` segments from vertex c0 (wrapping), of total `length`, at m equal sub-steps:
// the points at 0, h, ..., (m-1) h, and the largest distance of a piece vertex from the chord it falls in.
double sample_piece(const Ring& ring, std::size_t c0, std::size_t count, double length, std::size_t m,
                    std::vector<Vec2>& pts) {
  const std::size_t n = ring.size();
  auto at = [&](std::size_t j) { return ring[(c0 + j) % n]; };
  const double h = length / double(m);
  pts.assign(1, at(0));
  std::size_t seg = 0;
  double seg_start = 0;
  for (std::size_t q = 1; q < m; ++q) {
    const double target = h * double(q);
    while (seg + 1 < count) {
      const double len = (at(seg + 1) - at(seg)).norm();
      if (seg_start + len >= target) break;
      seg_start += len;
      ++seg;
    }
    const Vec2 a = at(seg), b = at(seg + 1);
    const double len = (b - a).norm();
    const double f = len > 0 ? std::min(1.0, (target - seg_start) / len) : 0.0;
    pts.push_back(a + f * (b - a));
  }
  // Vertex j (1..count-1) lies at arc length s_j, inside chord floor(s_j / h).
  double worst = 0, s = 0;
  for (std::size_t j = 1; j < count; ++j) {
    s += (at(j) - at(j - 1)).norm();
    const std::size_t q = std::min(m - 1, std::size_t(s / h));
    const Vec2 end = q + 1 < m ? pts[q + 1] : at(count);
    worst = std::max(worst, segment_distance(at(j), pts[q], end));
  }
  return worst;
}

}  // namespace

SampledRing resample_ring(const Ring& ring, double step, double corner_angle, double chord_error) {
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
  std::vector<Vec2> pts;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const std::size_t c0 = corners[k];
    const std::size_t c1 = corners[(k + 1) % corners.size()];
    // Vertices of this piece: c0, c0+1, ..., c1 (wrapping; a single corner means the whole ring).
    std::size_t count = (c1 + n - c0) % n;
    if (count == 0) count = n;
    double length = 0;
    for (std::size_t j = 0; j < count; ++j) length += (ring[(c0 + j + 1) % n] - ring[(c0 + j) % n]).norm();
    std::size_t m = std::max<std::size_t>(1, std::size_t(std::ceil(length / step - 1e-9)));
    double dev = sample_piece(ring, c0, count, length, m, pts);
    // Finer until the chords hug the piece (a chord's sagitta falls with the square of its length); bounded,
    // since sub-steps far below the ring's own vertex spacing cannot help.
    for (int round = 0; chord_error > 0 && dev > chord_error && m < 64 * count && round < 16; ++round) {
      m = std::max(m + 1, std::size_t(std::ceil(double(m) * std::min(4.0, std::sqrt(dev / chord_error) * 1.05))));
      dev = sample_piece(ring, c0, count, length, m, pts);
    }
    for (std::size_t q = 0; q < pts.size(); ++q) {
      out.points.push_back(pts[q]);
      out.corner.push_back(q == 0 && has_corners ? 1 : 0);
    }
  }
  return out;
}

}  // namespace hg::path_planner
