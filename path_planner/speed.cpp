// Step 6b: corner speeds. The robot bridge refuses a path whose corners need more lateral acceleration than
// its limit (the corner rule of motion/motion.hpp). The path's geometry is the grinding result, so it is
// kept exactly and the feed is lowered instead (docs).
#include "path_planner/pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hg::path_planner {

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
