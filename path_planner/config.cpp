// The planner's configuration from its parameters and the cell file (docs/cell.md).
#include "path_planner/config.hpp"

#include "path_planner/modifiers.hpp"

namespace hg::path_planner {

namespace {

Vec3 vec3(const runtime::Params& P, const std::string& key) {
  const std::vector<double> v = P.numbers(key);
  if (v.size() != 3) throw P.error(key, "expected 3 numbers");
  return Vec3(v[0], v[1], v[2]);
}

// The job defaults: the tool is the cell's, speeds within the cell's max-speed.
JobParams job_defaults(const runtime::Params& P, const cell::LoadedCell& cell) {
  const cell::Cell& c = cell.cell;
  JobParams d;
  // The tool is the cell's (tool.radius, tool.tilt, in their ranges by the cell's own check): no parameter.
  d.tool_radius = c.tool.radius;
  d.tilt = c.tool.tilt;
  d.grind_speed = P.number("grind-speed");
  d.travel_speed = P.number("travel-speed");
  for (const char* speed : {"grind-speed", "travel-speed", "approach-speed"})
    cell::refuse_above(P, speed, P.number(speed), cell, "max-speed", c.max_speed);
  d.step = P.number("step");
  d.safe_height = P.number("safe-height");
  d.direction = job::direction_from_name(P.text("direction")).value_or(Direction::Climb);  // one of its choices
  d.flipped = P.flag("flipped");
  return d;
}

}  // namespace

PlannerConfig config_from(const ParamLookup& L) { return config_from(L, cell::load_cell(*L.params)); }

PlannerConfig config_from(const ParamLookup& L, const cell::LoadedCell& cell) {
  const runtime::Params& P = *L.params;
  PlannerConfig c;
  c.defaults = job_defaults(P, cell);
  c.spindle_clockwise = P.flag("spindle-clockwise");
  c.approach_speed = P.number("approach-speed");
  c.lead_radius = P.number("lead-radius");
  c.lead_angle = P.number("lead-angle");
  c.modifiers = P.names("path-modifiers");
  if (const std::string why = check_modifier_list(c.modifiers); !why.empty()) throw P.error("path-modifiers", why);
  c.z_offset = P.number("z-offset");
  c.smooth.pitch = P.number("pixel-pitch");
  c.smooth.window_pitches = P.number("smooth-window");
  c.smooth.corner_scale_pitches = P.number("corner-scale");
  c.smooth.corner_angle = P.number("corner-angle");
  c.smooth.edge_compensation = P.flag("edge-compensation");
  c.arc_tolerance = P.number("arc-tolerance");
  c.resample_corner_angle = P.number("resample-corner-angle");
  c.coverage_tolerance = P.number("coverage-tolerance");
  c.resample_chord_error = P.number("resample-chord-error");
  c.small_hole = P.text("small-hole") == "skip" ? SmallHolePolicy::Skip : SmallHolePolicy::Fail;
  c.camera_to_base = cell.cell.calibration.camera_to_base;
  if (cell.cell.calibration.mounting == cell::Mounting::EyeInHand)
    c.camera_to_flange = cell.cell.calibration.camera_to_flange;
  c.default_plane = {vec3(P, "plane-origin"), vec3(P, "plane-u"), vec3(P, "plane-v"), vec3(P, "plane-normal")};
  c.base_frame = cell.cell.frames.base;
  c.home = cell.cell.home;
  c.limits = cell::limits_of(cell.cell);
  c.cell_file = cell.file;
  return c;
}

}  // namespace hg::path_planner
