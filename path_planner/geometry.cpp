// Geometry helpers, input checks, up-normalisation and the mirror for flipped parts.
#include "path_planner/pipeline.hpp"

#include <algorithm>
#include <cmath>

namespace hg::path_planner {

void make_canonical(std::vector<Loop>& loops) {
  for (Loop& l : loops) {
    const double a = signed_area(l.points);
    if ((!l.hole && a < 0) || (l.hole && a > 0)) std::reverse(l.points.begin(), l.points.end());
  }
}

AreaMoments area_moments(const std::vector<Loop>& loops) {
  // Green's theorem over canonical rings: holes (clockwise) subtract by themselves. Moments about the first
  // vertex for precision.
  AreaMoments m;
  const auto first = std::find_if(loops.begin(), loops.end(), [](const Loop& l) { return !l.points.empty(); });
  if (first == loops.end()) return m;
  polygon::MomentSum sum(first->points[0]);
  for (const Loop& l : loops) sum.add(l.points);
  const polygon::AreaMoments pm = sum.moments();
  m.area = pm.area;
  if (pm.area == 0) return m;
  m.centroid = pm.centroid;
  m.major_axis = pm.principal_axis();  // largest spread = the part's long axis
  return m;
}

std::string check_outline(const OutlineInput& in) {
  auto finite3 = [](const Vec3& v) { return v.allFinite(); };
  if (!finite3(in.plane.origin) || !finite3(in.plane.u) || !finite3(in.plane.v) || !finite3(in.plane.normal))
    return "plane has a non-finite value";
  const double nu = in.plane.u.norm(), nv = in.plane.v.norm(), nn = in.plane.normal.norm();
  if (std::abs(nu - 1) > 1e-3 || std::abs(nv - 1) > 1e-3 || std::abs(nn - 1) > 1e-3)
    return "plane axes are not unit vectors";
  if (std::abs(in.plane.u.dot(in.plane.v)) > 1e-3 || std::abs(in.plane.u.dot(in.plane.normal)) > 1e-3 ||
      std::abs(in.plane.v.dot(in.plane.normal)) > 1e-3)
    return "plane axes are not orthogonal";
  if (in.plane.u.cross(in.plane.v).dot(in.plane.normal) < 0) return "plane axes (u, v, normal) are not right-handed";
  if (in.loops.empty()) return "outline has no loops";
  bool outer = false;
  for (std::size_t k = 0; k < in.loops.size(); ++k) {
    const Loop& l = in.loops[k];
    if (l.points.size() < 3) return "loop " + std::to_string(k) + " has fewer than 3 points";
    for (std::size_t i = 0; i < l.points.size(); ++i)
      if (!l.points[i].allFinite())
        return "loop " + std::to_string(k) + " point " + std::to_string(i) + " is not finite";
    if (signed_area(l.points) == 0) return "loop " + std::to_string(k) + " has zero area";
    outer |= !l.hole;
  }
  if (!outer) return "outline has holes but no outer loop";
  return "";
}

void normalize_up(OutlineInput& in, const Eigen::Isometry3d& camera_to_base) {
  if ((camera_to_base.linear() * in.plane.normal).z() >= 0) return;
  in.plane.normal = -in.plane.normal;
  in.plane.v = -in.plane.v;  // keeps (u, v, normal) right-handed; the point p = o + x u + y v needs y -> -y
  for (Loop& l : in.loops) {
    for (Vec2& p : l.points) p.y() = -p.y();
    std::reverse(l.points.begin(), l.points.end());  // a mirror flips orientation; restore canonical
  }
}

std::vector<Loop> mirror_for_flip(const std::vector<Loop>& loops) {
  const AreaMoments m = area_moments(loops);
  const Eigen::Matrix2d reflect = 2 * m.major_axis * m.major_axis.transpose() - Eigen::Matrix2d::Identity();
  std::vector<Loop> out = loops;
  for (Loop& l : out) {
    for (Vec2& p : l.points) p = m.centroid + reflect * (p - m.centroid);
    std::reverse(l.points.begin(), l.points.end());
  }
  return out;
}

}  // namespace hg::path_planner
