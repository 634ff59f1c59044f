// The planner's parameter table (config/path_planner.yaml, hg-plan --help) and where values are looked up.
#include "path_planner/params.hpp"

#include <limits>
#include <memory>

#include "cell/cell_params.hpp"
#include "path_planner/modifiers.hpp"

namespace hg::path_planner {

using runtime::Param;

std::vector<Param> planner_params() {
  using runtime::flag_param;
  using runtime::integer_param;
  using runtime::number_param;
  using runtime::numbers_param;
  using runtime::text_param;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const bool open = true;  // the range's lower end is excluded: the value must be > min
  std::vector<Param> params = {
      cell::cell_param(),
      runtime::quantity_param(quantity::kGrindSpeed, "0.02", "job default; <= the cell's max-speed"),
      runtime::quantity_param(quantity::kTravelSpeed, "0.2", "job default; <= the cell's max-speed"),
      runtime::quantity_param(quantity::kStep, "0.002", "job default"),
      runtime::quantity_param(quantity::kSafeHeight, "0.05", "job default"),
      text_param("direction", "climb", "hg-plan; a job request carries its own", job::direction_names()),
      flag_param("flipped", "plan for the flipped part (hg-plan; a job request carries its own)"),
      Param{"spindle-clockwise", "true", "spindle turns clockwise seen from above (decides what climb means)", false,
            runtime::ParamType::Flag},
      number_param("approach-speed", "0.05",
                   "speed of the vertical approach and retract, m/s (capped by travel-speed; <= the cell's max-speed)",
                   0, inf, open),
      number_param("lead-radius", "0.01", "radius of the lead-in/lead-out arcs, m (smaller in small holes)", 0, inf,
                   open),
      number_param("lead-angle", "1.5707963267948966", "sweep of the lead arcs, rad", 0, inf, open),
      runtime::names_param("path-modifiers", "leads,approach,retract,corner-speeds",
                           "the passes after sequencing, in this order, each at most once: leads (lead-in/out arcs), "
                           "approach (from safe-height), retract (to safe-height), corner-speeds (the cell's corner "
                           "rule); docs/path_planner.md"),
      number_param("z-offset", "0", "height of the grind points above the plate's top surface, m"),
      number_param("pixel-pitch", "0",
                   "pixel pitch of the outline, m; 0 (normal): the outline's point spacing, else estimated from its "
                   "loops",
                   0),
      number_param("smooth-window", "4", "residual windows of the smoothing fits are 2x this many vertices", 0, inf,
                   open),
      number_param(
          "corner-scale", "8",
          "length of the corner detector's line fits, in pixel pitches (at least 60 noise levels of a window mean)", 0,
          inf, open),
      number_param("corner-angle", "0.5235987755982988", "smallest turn treated as a corner, rad (30 deg)", 0,
                   3.141592653589793),
      Param{"edge-compensation", "true", "move loops from the outermost pixel centres to the edge (half a pitch)",
            false, runtime::ParamType::Flag},
      number_param("arc-tolerance", "1e-5", "Clipper round-join tolerance, m", 0, inf, open),
      number_param("resample-corner-angle", "0.17453292519943295", "turn kept as a waypoint when resampling, rad", 0,
                   3.141592653589793),
      text_param("small-hole", "fail",
                 "a hole too small for the tool, or edge out of its reach: fail (job FAILED), skip (planned, warning)",
                 {"fail", "skip"}),
      number_param("coverage-tolerance", "0.0002",
                   "every edge point must be within the tool radius + this of the grind path, m", 0, inf, open),
      number_param("resample-chord-error", "1e-5", "largest distance of a resampled chord from the offset ring, m", 0,
                   inf, open),
      numbers_param("plane-origin", "0,0,1.19",
                    "plate plane in the camera frame for outline files without one: origin"),
      numbers_param("plane-u", "1,0,0", "... u axis"),
      numbers_param("plane-v", "0,-1,0", "... v axis"),
      numbers_param("plane-normal", "0,0,-1", "... normal (u, v, normal right-handed)"),
      text_param("outline-frame", "",
                 "hg-plan: frame of the outline file's plane: camera (the cell's camera-to-base applied), robot_base "
                 "(the cell's frames.base: none applied); default: the file's \"frame\" (cloud or none: camera)"),
      number_param(
          "outline-max-age", "2.0",
          "hg-path-planner: a job starts on the latest outline if it arrived at most this long ago (s), else on the next",
          0),
      number_param("outline-timeout", "10.0", "hg-path-planner: a job with no outline after this long fails, s", 0, inf,
                   open),
      number_param("path-resend-period", "0.5",
                   "hg-path-planner: a path the robot bridge has not acknowledged is published again after this "
                   "long, s (checked every 0.1 s)",
                   0.1),
      integer_param("path-resends", "20",
                    "hg-path-planner: copies of an unacknowledged path at most (then a warning; the robot bridge's "
                    "path-timeout ends the job); 0 = never re-sent",
                    0, 1000),
  };
  for (Param& p : moved_planner_keys()) params.push_back(std::move(p));
  return params;
}

ParamLookup lookup_from(const runtime::Params& params) {
  return {std::shared_ptr<const runtime::Params>(std::shared_ptr<void>(), &params)};  // not owned
}

ParamLookup lookup_from(const runtime::Node& node) { return lookup_from(node.params()); }

ParamLookup lookup_from(const std::map<std::string, std::string>& cli, const runtime::Config& config) {
  // The one precedence rule (runtime::Params), over the planner's declarations; shared so the lookup owns it.
  auto params = std::make_shared<runtime::Params>(planner_params());
  params->use_config(config);
  for (const auto& [k, v] : cli) params->set(k, v);
  return {params};
}

std::vector<Param> moved_planner_keys() {
  return cell::moved_to_cell({{"camera-to-base", "calibration.camera-to-base"},
                              {"camera-xyz", "calibration.camera-to-base"},
                              {"camera-rpy", "calibration.camera-to-base"},
                              {"home", "home"},
                              {"workspace-min", "workspace.min"},
                              {"workspace-max", "workspace.max"},
                              {"table-z", "table-z"},
                              {"max-speed", "max-speed"},
                              {"max-accel", "max-accel"},
                              {"tool-radius", "tool.radius"},
                              {"base-frame", "frames.base"}});
}

}  // namespace hg::path_planner
