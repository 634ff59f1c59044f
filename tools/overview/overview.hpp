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
// {"job_id", "frame", "waypoints": [{"position": [x, y, z], "orientation": [w, x, y, z], "speed", "kind"}]}
nlohmann::ordered_json path_json(const hullgrind::grind_path_t& path);
// Stage timings (milliseconds) and the job's outcome.
nlohmann::ordered_json summary_json(const JobTrace& job);
// Top view in the plate plane: cloud, outline (holes in red), grind path by segment kind, edge out of the
// tool's reach (magenta, when `planner` is given: the planner's coverage check redone on the job's outline
// and path with that config), and a legend. camera_to_base brings the path (robot base frame) back onto the
// plate. Returns PNG bytes.
std::vector<unsigned char> overview_png(const JobTrace& job, const Eigen::Isometry3d& camera_to_base,
                                        const hg::path_planner::PlannerConfig* planner = nullptr);
// The job's unreached edge stretches in the robot base frame, from path_coverage (empty without a path and
// an outline).
std::vector<std::vector<Eigen::Vector3d>> unreached_stretches(const JobTrace& job,
                                                              const hg::path_planner::PlannerConfig& planner);

}  // namespace hg::overview
