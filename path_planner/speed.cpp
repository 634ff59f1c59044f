// Step 6b: corner speeds. The robot bridge refuses a path whose corners need more lateral acceleration than
// its limit (robot_bridge/path.cpp check_path: v^2 / r <= max_accel at every waypoint but the last, v the
// lower of the two segment speeds, r the circle through the waypoint and its neighbours). The path's
// geometry is the grinding result, so it is kept exactly and the feed is lowered instead (docs).
#include "path_planner/pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hg::path_planner {

double corner_radius(const Vec3& a, const Vec3& b, const Vec3& c) {
  // Same expression, in the same order, as the bridge's, so both round alike.
  const Vec3 u = b - a, v = c - b;
  const double cross = u.cross(v).norm();
  if (cross == 0) return u.dot(v) >= 0 ? std::numeric_limits<double>::infinity() : 0.0;
  return u.norm() * v.norm() * (c - a).norm() / (2 * cross);
}

double corner_speed_limit(double radius, double max_accel) {
  if (!(radius > 0) || !(max_accel > 0)) return 0;
  if (std::isinf(radius)) return std::numeric_limits<double>::infinity();
  // A hair under the limit: another build of the bridge may round r or v^2 / r differently in the last bit.
  const double target = max_accel * (1 - 1e-9);
  double v = std::sqrt(target * radius);
  while (v > 0 && v * v / radius > target) v = std::nextafter(v, 0.0);
  return v;
}

int limit_corner_speeds(std::vector<Waypoint>& path, const Vec3& start, double max_accel) {
  const std::size_t n = path.size();
  std::vector<double> limit(n, std::numeric_limits<double>::infinity());  // per waypoint (corner)
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Vec3& a = i == 0 ? start : path[i - 1].position;
    const Vec3& b = path[i].position;
    const Vec3& c = path[i + 1].position;
    if ((b - a).squaredNorm() == 0 || (c - b).squaredNorm() == 0) continue;  // the bridge sees no corner here
    const double v = corner_speed_limit(corner_radius(a, b, c), max_accel);
    if (v > 0) limit[i] = v;  // a reversal (0) cannot be slowed into shape: validate names it
  }
  // Both segments at a corner run at the corner's speed (the bridge takes the lower of the two; slowing
  // both keeps the tool slow while it enters and leaves a concave corner, where its engagement is highest).
  int lowered = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double cap = std::min(limit[i], i > 0 ? limit[i - 1] : std::numeric_limits<double>::infinity());
    if (path[i].speed > cap) {
      path[i].speed = cap;
      ++lowered;
    }
  }
  return lowered;
}

}  // namespace hg::path_planner
