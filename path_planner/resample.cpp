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

// A piece of the ring: `count` segments from vertex c0 (wrapping), with the arc length at each vertex.
struct Piece {
  const Ring& ring;
  std::size_t c0, count;
  std::vector<double> cum;  // cum[j]: arc length from c0 to vertex c0 + j, j = 0..count
  Piece(const Ring& r, std::size_t first, std::size_t segments)
      : ring(r), c0(first), count(segments), cum(segments + 1, 0) {
    for (std::size_t j = 0; j < count; ++j) cum[j + 1] = cum[j] + (at(j + 1) - at(j)).norm();
  }
  Vec2 at(std::size_t j) const { return ring[(c0 + j) % ring.size()]; }
  Vec2 point(double s) const {  // the point at arc length s
    const std::size_t j =
        std::min<std::size_t>(count - 1, std::size_t(std::upper_bound(cum.begin(), cum.end(), s) - cum.begin()) - 1);
    const double len = cum[j + 1] - cum[j];
    return len > 0 ? Vec2(at(j) + (at(j + 1) - at(j)) * std::clamp((s - cum[j]) / len, 0.0, 1.0)) : at(j);
  }
  // Largest distance of the piece's vertices strictly between arc lengths a and b from the chord a-b.
  double deviation(double a, double b) const {
    const Vec2 pa = point(a), pb = point(b);
    double worst = 0;
    for (std::size_t j = std::size_t(std::upper_bound(cum.begin(), cum.end(), a) - cum.begin());
         j < count && cum[j] < b; ++j)
      worst = std::max(worst, segment_distance(at(j), pa, pb));
    return worst;
  }
};

// Points at arc lengths from a (included) to b (excluded): halves the chord while it strays farther than
// chord_error from the piece (a chord's sagitta falls with the square of its length), only where it does.
void emit_chords(const Piece& piece, double a, double b, double chord_error, int depth, std::vector<Vec2>& out) {
  if (depth < 12 && chord_error > 0 && piece.deviation(a, b) > chord_error) {
    emit_chords(piece, a, 0.5 * (a + b), chord_error, depth + 1, out);
    emit_chords(piece, 0.5 * (a + b), b, chord_error, depth + 1, out);
    return;
  }
  out.push_back(piece.point(a));
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
    const std::size_t m = std::max<std::size_t>(1, std::size_t(std::ceil(length / step - 1e-9)));
    const Piece piece(ring, c0, count);
    pts.clear();
    for (std::size_t q = 0; q < m; ++q) emit_chords(piece, length * q / m, length * (q + 1) / m, chord_error, 0, pts);
    for (std::size_t q = 0; q < pts.size(); ++q) {
      out.points.push_back(pts[q]);
      out.corner.push_back(q == 0 && has_corners ? 1 : 0);
    }
  }
  return out;
}

}  // namespace hg::path_planner
