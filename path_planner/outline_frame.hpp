// The frame of an outline file's plane (hg-plan --outline-frame) and the transform it implies.
#pragma once

#include <string>

#include "path_planner/pipeline.hpp"

namespace hg::path_planner {

// Which frame an outline file's plane is taken to be in, and the camera-to-base transform that follows:
// `chosen` (the outline_frame parameter) if given, else what the file says. camera: the configured
// calibration; the base_frame: identity (the plane is in robot base coordinates already); cloud (hg-outline:
// the input cloud's own coordinates) or nothing: camera, with a note saying so. Anything else: ConfigError.
struct OutlineFrame {
  std::string declared;  // what the file says ("(none)" when it says nothing)
  std::string used;      // camera or the base_frame
  Eigen::Isometry3d camera_to_base = Eigen::Isometry3d::Identity();
  std::string note;  // set when the choice was a guess
};
OutlineFrame resolve_outline_frame(const std::string& file_frame, const std::string& chosen, const PlannerConfig& cfg);
// A 4x4 transform as "[r00 r01 r02 t0; ...; 0 0 0 1]" (the camera_to_base parameter's order, row-major).
std::string matrix_text(const Eigen::Isometry3d& T);

}  // namespace hg::path_planner
