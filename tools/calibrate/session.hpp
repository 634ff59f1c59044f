// A calibration session on disk: DIR/session.json lists the views and the robot's reading at each view;
// DIR/truth.json (a simulated session only) holds the renderer's ground truth. A view is one of:
//   "depth":   a 16-bit depth PNG with its intrinsics (segmented by hg-calibrate, as the camera bridge does),
//   "cloud":   a .pcd/.ply cloud in the camera frame (metres), rendered into a depth image through the
//              view's intrinsics as the camera bridge's files source does, then as a depth PNG,
//   "outline": the camera bridge's plate plane and the outline service's hole loops captured from the bus
//              (hg-calibrate capture --from-bus), an outline file (docs/outline_file.md) beside session.json.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "calibration/target.hpp"
#include "camera_types/depth_source.hpp"

namespace hg::calibrate {

struct SessionView {
  std::string kind = "depth";  // "depth" | "cloud" | "outline"
  std::string file;            // relative to the session folder
  cv::Mat depth;               // CV_16UC1 (depth and cloud views)
  camera::Intrinsics intrinsics;
  calibration::PlatePlane plane;                       // outline views
  std::vector<calibration::HoleLoop> loops;            // outline views: hole loops in plate-plane coordinates
  nlohmann::json outline_record;                       // outline views: the file's content, written back as read
  std::optional<Eigen::Isometry3d> flange_to_base;     // eye-in-hand: the robot pose at this view
  std::map<std::string, Eigen::Vector3d> tcp_at_hole;  // eye-to-hand: drawing hole id -> TCP position (base)
};

struct Session {
  std::string mode;  // "eye-to-hand" | "eye-in-hand"
  std::vector<SessionView> views;
};

// Throws std::runtime_error naming the file and the key. Without load_data the views' files are not read
// (capture, touch: only session.json changes; write_session then keeps those files as they are).
Session read_session(const std::string& dir, bool load_data = true);
void write_session(const std::string& dir, const Session& s);

// The plate in one view: the product's pipeline on the view's data (calibration::detect_plate for depth and
// cloud views, calibration::plate_from_loops for outline views). Throws calibration::CalibrationError.
calibration::PlateView detect_view(const SessionView& v, const calibration::Drawing& d);

// An outline view's file: the outline file (outline_io/outline_file.hpp, docs/outline_file.md) of the plate
// plane (camera frame) and its hole loops; and back (the plane and the hole loops: outer loops are no
// features). read_outline_view throws naming the file and the key.
nlohmann::json outline_view_json(const calibration::PlatePlane& plane, const std::vector<calibration::HoleLoop>& loops);
void read_outline_view(const std::string& path, SessionView& v);

std::vector<double> to_row_major(const Eigen::Isometry3d& t);
Eigen::Isometry3d from_row_major(const std::vector<double>& v, const std::string& where);

}  // namespace hg::calibrate
