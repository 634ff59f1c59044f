// The calibration plate seen by the camera: hole centres from the product's own pipeline (segmentation of
// the depth frame -> plate points in the plate plane -> outline core loops -> circle fit per hole loop),
// matched to the drawing (partgen::calibration_plate_holes, docs/calibration.md) by diameter and pattern.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "calibration/geometry.hpp"
#include "camera_types/depth_source.hpp"
#include "camera_bridge/segment.hpp"

namespace hg::calibration {

struct DrawingHole {
  std::string id;
  Eigen::Vector3d centre;  // plate frame (partgen's x, y; z up from the table), on the top face, metres
  double diameter = 0;     // metres
};

struct Drawing {
  std::string name = "calibration-plate";
  double thickness = 0;
  std::vector<DrawingHole> holes;
};
Drawing calibration_plate_drawing();

struct SeenHole {
  Eigen::Vector3d centre_camera = Eigen::Vector3d::Zero();  // on the plate's top plane, camera frame
  double diameter = 0;
  double fit_rms = 0;      // metres
  int points = 0;          // loop vertices of the fit
  int drawing_index = -1;  // matched hole of the drawing, -1 none
};

struct PlateView {
  std::vector<SeenHole> holes;  // matched ones only, in drawing order
  Eigen::Isometry3d plate_to_camera = Eigen::Isometry3d::Identity();
  RigidFit pattern_fit;  // drawing -> camera of the matched holes
  std::string text;      // what was found
};

struct DetectOptions {
  camera_bridge::SegmentParams segment;
  double diameter_tolerance = 0.004;  // m: a loop matches a drawing hole within this of its diameter
  double pattern_tolerance = 0.003;   // m: worst residual of the pattern fit accepted
};

// The plate's top plane in the camera frame: p = origin + u * u_axis + v * v_axis (the plane of a
// plate_cloud_t / outline_t, or of camera_bridge::segment).
struct PlatePlane {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero(), u_axis = Eigen::Vector3d::UnitX(),
                  v_axis = Eigen::Vector3d::UnitY();
};

// One hole loop of the outline core, in plate-plane coordinates (u, v), metres.
using HoleLoop = std::vector<Eigen::Vector2d>;

// The hole loops of the outline core's result on plate-plane points (u, v): automatic radius, as the outline
// service runs it by default.
std::vector<HoleLoop> hole_loops(const std::vector<float>& u, const std::vector<float>& v);

// Circle fit on each hole loop (loops of fewer than 8 vertices skipped), matching to the drawing by diameter
// and pattern. Throws CalibrationError (fewer than 3 holes matched, pattern not the drawing's).
PlateView plate_from_loops(const PlatePlane& plane, const std::vector<HoleLoop>& loops, const Drawing& drawing,
                           const DetectOptions& options = {});

// A depth frame through the camera bridge's segmentation, the outline core and plate_from_loops.
// Throws CalibrationError (why: no plate, fewer than 3 holes matched, pattern not the drawing's).
PlateView detect_plate(const cv::Mat& depth, const camera::Intrinsics& in, const Drawing& drawing,
                       const DetectOptions& options = {});

}  // namespace hg::calibration
