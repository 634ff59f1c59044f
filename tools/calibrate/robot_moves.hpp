// hg-calibrate's moves of the robot over the bus: HG_ROBOT_MOVE out, the move's HG_JOB_STATUS and the
// robot's HG_ROBOT_STATUS back (docs/CHANNELS.md).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <Eigen/Geometry>

namespace hg::calibrate {

struct MoveResult {
  bool done = false;
  std::string message;                            // the bridge's last word on the move
  Eigen::Vector3d tcp = Eigen::Vector3d::Zero();  // HG_ROBOT_STATUS after the move
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

class RobotMoves {
 public:
  explicit RobotMoves(const std::string& lcm_url);  // throws std::runtime_error when LCM cannot start
  ~RobotMoves();
  // Sends the move and waits (at most timeout_s) for DONE or another final state, then for a fresh status.
  MoveResult move_to(const std::string& move_id, const Eigen::Vector3d& position, const Eigen::Quaterniond& q,
                     double speed, double timeout_s);
  // The TCP position of the next HG_ROBOT_STATUS (nullopt when none came within timeout_s).
  std::optional<Eigen::Vector3d> current_tcp(double timeout_s);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hg::calibrate
