// hg-calibrate capture --from-bus: one view of the calibration plate from the product's own pipeline on a
// live bus: the camera bridge's next plate cloud (HG_PLATE_CLOUD), the outline service's outline of that
// cloud (HG_OUTLINE, matched by cloud_seq) or the outline core run here on the cloud, and the robot's pose
// (HG_ROBOT_STATUS) after the cloud came.
#pragma once

#include <optional>
#include <string>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "calibration/target.hpp"

namespace hg::calibrate {

struct CaptureOptions {
  std::string lcm_url;
  std::string job_id;          // non-empty: ask for the frame with a job_request_t START of this id
  bool local_outline = false;  // run the outline core on the cloud here instead of waiting for HG_OUTLINE
  bool robot_pose = false;     // wait for an HG_ROBOT_STATUS after the cloud (eye-in-hand)
  double timeout_s = 10;
};

struct Captured {
  calibration::PlatePlane plane;
  std::vector<calibration::HoleLoop> loops;      // hole loops, plate-plane coordinates
  nlohmann::json record;                         // what goes into the view's outline file
  std::optional<Eigen::Isometry3d> tcp_to_base;  // with robot_pose
  std::string text;                              // what was captured, for the log
};

// Throws std::runtime_error with the reason (nothing within the timeout, the bridge's or the service's
// error status, the robot moving or in FAULT).
Captured capture_from_bus(const CaptureOptions& options);

}  // namespace hg::calibrate
