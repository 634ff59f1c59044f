// Step 6: plate frame -> camera frame (the outline's plane) -> robot base frame (hand-eye calibration).
#include "path_planner/pipeline.hpp"

namespace hg::path_planner {

Eigen::Isometry3d plate_to_base(const Plane& plane, const Eigen::Isometry3d& camera_to_base) {
  Eigen::Isometry3d plate_to_camera = Eigen::Isometry3d::Identity();
  plate_to_camera.linear().col(0) = plane.u;
  plate_to_camera.linear().col(1) = plane.v;
  plate_to_camera.linear().col(2) = plane.normal;
  plate_to_camera.translation() = plane.origin;
  return camera_to_base * plate_to_camera;
}

std::vector<Waypoint> to_base(const std::vector<PlateWaypoint>& path, const Eigen::Isometry3d& T) {
  std::vector<Waypoint> out;
  out.reserve(path.size());
  const Eigen::Quaterniond R(T.linear());
  for (const PlateWaypoint& w : path) {
    Eigen::Quaterniond q = (R * w.orientation).normalized();
    if (q.w() < 0) q.coeffs() = -q.coeffs();
    out.push_back({T * w.position, q, w.speed, w.kind, w.loop});
  }
  return out;
}

Eigen::Isometry3d pose_from_xyz_rpy(const Vec3& xyz, const Vec3& rpy) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
                Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
                   .toRotationMatrix();
  T.translation() = xyz;
  return T;
}

}  // namespace hg::path_planner
