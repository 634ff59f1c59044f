// Ground-truth geometry shared by the path planner's tests: distances to exact rings, their corners, and
// dense sampling of a result polyline so that a straight run given by its two end points is checked along
// its whole length. Written independently of path_planner/geometry.cpp (the code under test).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Core>

namespace hg::path_planner::test {

using Vec2 = Eigen::Vector2d;
using Ring = std::vector<Vec2>;

inline double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Distance from p to the closed ring.
inline double ring_distance(const Vec2& p, const Ring& r) {
  double d = 1e300;
  for (std::size_t i = 0; i < r.size(); ++i) d = std::min(d, segment_distance(p, r[i], r[(i + 1) % r.size()]));
  return d;
}

// Turn from direction a to direction b, radians, left positive.
inline double turn(const Vec2& a, const Vec2& b) { return std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b)); }

// Vertices of the rings where the boundary turns by at least min_turn (radians): the true corners.
inline std::vector<Vec2> corners_of(const std::vector<Ring>& rings, double min_turn) {
  std::vector<Vec2> out;
  for (const Ring& r : rings)
    for (std::size_t i = 0, n = r.size(); i < n; ++i)
      if (std::abs(turn(r[i] - r[(i + n - 1) % n], r[(i + 1) % n] - r[i])) >= min_turn) out.push_back(r[i]);
  return out;
}

// The closed polyline sampled every `step` along its segments (vertices included).
inline Ring densify(const Ring& r, double step) {
  Ring o;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const Vec2 a = r[i], b = r[(i + 1) % r.size()];
    const int m = std::max(1, int(std::ceil((b - a).norm() / step)));
    for (int k = 0; k < m; ++k) o.push_back(a + (b - a) * (double(k) / m));
  }
  return o;
}

}  // namespace hg::path_planner::test
