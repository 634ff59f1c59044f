#include "motion/motion.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hg::motion {

bool inside_workspace(const Vec3& p, const Limits& lim) {
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= lim.workspace_min[a] && p[a] <= lim.workspace_max[a])) return false;
  return true;
}

bool above_table(const Vec3& p, const Limits& lim) { return p.z() > lim.table_z; }

double corner_radius(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = b - a, v = c - b;
  const double cross = u.cross(v).norm();
  if (cross == 0) return u.dot(v) >= 0 ? std::numeric_limits<double>::infinity() : 0.0;
  return u.norm() * v.norm() * (c - a).norm() / (2 * cross);
}

double corner_speed_limit(double radius, double max_accel) {
  if (!(radius > 0) || !(max_accel > 0)) return 0;
  if (std::isinf(radius)) return std::numeric_limits<double>::infinity();
  const double target = max_accel * (1 - 1e-9);
  double v = std::sqrt(target * radius);
  while (v > 0 && v * v / radius > target) v = std::nextafter(v, 0.0);
  return v;
}

std::optional<CornerFault> first_corner_fault(const std::vector<Vec3>& position, const std::vector<double>& speed,
                                              const Vec3& start, double max_accel) {
  for (std::size_t i = 0; i + 1 < position.size(); ++i) {
    const Vec3& a = i == 0 ? start : position[i - 1];
    const Vec3& b = position[i];
    const Vec3& c = position[i + 1];
    if ((b - a).squaredNorm() == 0 || (c - b).squaredNorm() == 0) continue;  // duplicate point: no corner here
    const double v = std::min(speed[i], speed[i + 1]);
    const double r = corner_radius(a, b, c);
    const double lateral = r == 0 ? std::numeric_limits<double>::infinity() : v * v / r;
    if (lateral > max_accel) return CornerFault{i, r, v, lateral};
  }
  return std::nullopt;
}

}  // namespace hg::motion
