// Where an outline's plane is in the base frame: the cell's mounting (cell file calibration.mounting).
#include <cmath>
#include <string>

#include "path_planner/lcm.hpp"

namespace hg::path_planner {

std::string place_outline(const hullgrind::outline_t& m, PlannerConfig& cfg) {
  if (!cfg.camera_to_flange) return "";  // eye-to-hand: the cell's camera-to-base, the same for every outline
  const std::string where = "outline " + std::to_string(m.header.seq) + " (cloud " + std::to_string(m.cloud_seq) + ")";
  if (!m.flange_valid)
    return where +
           ": no robot flange pose at capture (the camera bridge heard no IDLE HG_ROBOT_STATUS within 1 s)"
           "; the eye-in-hand cell " +
           cfg.cell_file + " needs it";
  const Eigen::Vector3d t(m.flange_position[0], m.flange_position[1], m.flange_position[2]);
  const Eigen::Quaterniond q(m.flange_orientation[0], m.flange_orientation[1], m.flange_orientation[2],
                             m.flange_orientation[3]);
  if (!t.allFinite() || !q.coeffs().allFinite() || std::abs(q.norm() - 1) > 1e-6)
    return where + ": flange pose is not a finite position and unit quaternion";
  Eigen::Isometry3d base_from_flange = Eigen::Isometry3d::Identity();
  base_from_flange.linear() = q.toRotationMatrix();
  base_from_flange.translation() = t;
  cfg.camera_to_base = base_from_flange * *cfg.camera_to_flange;
  return "";
}

}  // namespace hg::path_planner
