// What make run leaves in out/: outline.json (hg-outline's schema), path.json, overview.png and the
// per-stage timings of one job, all from the recorded bus.
#pragma once

#include <string>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "path_planner/pipeline.hpp"
#include "tools/overview/run_log.hpp"

namespace hg::overview {

// hg-outline's JSON for the job's outline, with the plate cloud as the points.
nlohmann::ordered_json outline_json(const JobTrace& job);
// Stage timings (milliseconds) and the job's outcome.
nlohmann::ordered_json summary_json(const JobTrace& job);
// The path (robot base frame) brought back into the outline's plate plane with camera_to_base: (u, v) per
// waypoint, and each waypoint's height above the plane (the planner's z_offset for grind waypoints when
// camera_to_base is the calibration the planner used).
struct PlatePath {
  std::vector<Eigen::Vector2d> uv;
  std::vector<double> height;
  std::vector<int> kind;
  // Median |height| of the grind waypoints, m (0 without any).
  double grind_height_median() const;
};
PlatePath path_on_plate(const JobTrace& job, const Eigen::Isometry3d& camera_to_base);
// A grind path further than this from the outline's plane was planned with another calibration.
constexpr double kOffPlaneWarning = 0.005;

// Top view in the plate plane: cloud, outline (holes in red), grind path by segment kind, edge out of the
// tool's reach (magenta, when `planner` is given: the planner's coverage check redone on the job's outline
// and path with that config), a scale bar in millimetres, the frames, and a legend. camera_to_base brings
// the path back onto the plate; the planner's base_frame names the path's frame in the caption. Returns PNG
// bytes.
std::vector<unsigned char> overview_png(const JobTrace& job, const Eigen::Isometry3d& camera_to_base,
                                        const hg::path_planner::PlannerConfig* planner = nullptr);
// The job's unreached edge stretches in the robot base frame, from path_coverage (empty without a path and
// an outline).
std::vector<std::vector<Eigen::Vector3d>> unreached_stretches(const JobTrace& job,
                                                              const hg::path_planner::PlannerConfig& planner);
// The length of the scale bar for a picture `span` metres wide: 1, 2 or 5 x 10^k mm, at most span / 4.
double scale_bar_mm(double span);

}  // namespace hg::overview
