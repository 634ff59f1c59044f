// A calibration session on disk: DIR/session.json lists the views (16-bit depth PNG, intrinsics, the robot's
// reading at that view) and, for a simulated session only, DIR/truth.json holds the renderer's ground truth.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "camera_types/depth_source.hpp"

namespace hg::calibrate {

struct SessionView {
  std::string depth_file;  // relative to the session folder
  cv::Mat depth;           // CV_16UC1
  camera::Intrinsics intrinsics;
  std::optional<Eigen::Isometry3d> flange_to_base;     // eye-in-hand: the robot pose at this view
  std::map<std::string, Eigen::Vector3d> tcp_at_hole;  // eye-to-hand: drawing hole id -> TCP position (base)
};

struct Session {
  std::string mode;  // "eye-to-hand" | "eye-in-hand"
  std::vector<SessionView> views;
};

// Throws std::runtime_error naming the file and the key.
Session read_session(const std::string& dir);
void write_session(const std::string& dir, const Session& s);

std::vector<double> to_row_major(const Eigen::Isometry3d& t);
Eigen::Isometry3d from_row_major(const std::vector<double>& v, const std::string& where);

}  // namespace hg::calibrate
