// Which frame an outline file's plane is in, and the camera-to-base transform that follows.
#include "path_planner/outline_frame.hpp"

#include <cmath>
#include <cstdio>

#include "runtime/config.hpp"

namespace hg::path_planner {

using runtime::ConfigError;

OutlineFrame resolve_outline_frame(const std::string& file_frame, const std::string& chosen, const PlannerConfig& cfg) {
  OutlineFrame f;
  f.declared = file_frame.empty() ? "(none)" : file_frame;
  f.used = chosen.empty() ? file_frame : chosen;
  if (f.used.empty() || f.used == "cloud") {
    f.used = "camera";
    f.note = "an outline in its cloud's own coordinates is taken as the camera's view; give --outline-frame " +
             cfg.base_frame + " if the cloud is in robot base coordinates";
  }
  if (f.used == cfg.base_frame) {
    f.camera_to_base = Eigen::Isometry3d::Identity();
  } else if (f.used == "camera" && cfg.camera_to_flange) {
    throw ConfigError("the cell " + cfg.cell_file +
                      " is eye-in-hand (calibration.mounting): an outline file holds no flange pose to place a "
                      "camera-frame plane with; give the outline in " +
                      cfg.base_frame + " (--outline-frame " + cfg.base_frame + ")");
  } else if (f.used == "camera") {
    f.camera_to_base = cfg.camera_to_base;
  } else {
    throw ConfigError("outline frame '" + f.used + "' is neither camera nor " + cfg.base_frame +
                      " (the cell's frames.base); give --outline-frame camera or --outline-frame " + cfg.base_frame);
  }
  return f;
}

std::string matrix_text(const Eigen::Isometry3d& T) {
  std::string s = "[";
  char buf[40];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      std::snprintf(buf, sizeof buf, "%.6g%s", std::abs(T.matrix()(r, c)) < 1e-12 ? 0.0 : T.matrix()(r, c),
                    c < 3 ? " " : (r < 3 ? "; " : "]"));
      s += buf;
    }
  return s;
}

}  // namespace hg::path_planner
