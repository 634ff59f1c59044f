// Configuration, outline/path files and LCM conversions of the planner (shared by hg-path-planner and
// hg-plan).
#pragma once

#include "cell/cell_params.hpp"
#include "path_planner/pipeline.hpp"
#include "runtime/node.hpp"

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/outline_t.hpp"

namespace hg::path_planner {

// Every planner parameter (hg-path-planner and hg-plan read the same keys, config/path_planner.yaml), with
// --cell: the camera-to-base calibration, table, workspace, speed and acceleration limits, tool and home come
// from the cell file (docs/cell.md); their old keys are declared as moved and refused naming the cell's key.
std::vector<runtime::Param> planner_params();
// The keys that moved into the cell file (part of planner_params()): refused naming the cell's key.
std::vector<runtime::Param> moved_planner_keys();

// Where parameter values come from (command line > config file > default, runtime::Params), for the
// process, hg-plan and hg-overview alike.
struct ParamLookup {
  std::shared_ptr<const runtime::Params> params;  // owned (lookup_from(cli, config)) or not (the others)
};
ParamLookup lookup_from(const runtime::Node& node);
ParamLookup lookup_from(const runtime::Params& params);  // params must outlive the lookup
// For tests: `cli` (name -> value, lists as "a,b,c") > `config` > the default of planner_params(), through
// the same runtime::Params (every program parses its command line with runtime::Params itself).
ParamLookup lookup_from(const std::map<std::string, std::string>& cli, const runtime::Config& config);
// Reads the cell file (parameter cell) and the parameters. Throws runtime::ConfigError naming the parameter
// (and where it came from) when a value is unusable or contradicts the cell, or the cell file and its key.
PlannerConfig config_from(const ParamLookup& lookup);
PlannerConfig config_from(const ParamLookup& lookup, const cell::LoadedCell& cell);

// Outline JSON as hg-outline writes it: {"loops": [{"hole", "points": [[x, y], ...]}, ...], "plane"?:
// {"origin", "normal", "u", "v"}, "frame"?: the frame the plane is in, "spacing"?: the point spacing, m}. Without a
// plane, default_plane is used. Throws std::runtime_error naming the byte (parse errors) or the key, loop and point
// index.
OutlineInput read_outline_json(const std::string& text, const Plane& default_plane);

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

// The path file (path_file/path_file.hpp, docs/path_file.md) of a planned path, with the planner's
// "coverage": coverage_json (readers of paths ignore it).
nlohmann::ordered_json path_json(const std::string& job_id, const std::string& frame, const PlanResult& result,
                                 std::int64_t outline_seq = -1);
// {"tolerance", "unreached_length", "loops": [{"loop", "hole", "length", "reached_fraction", "unreached":
// [{"start", "length", "concave", "points": [[x, y, z], ...]}]}]}: metres; points in the path's (base) frame.
nlohmann::ordered_json coverage_json(const PlanResult& result);
const char* kind_name(std::int8_t kind);

OutlineInput from_lcm(const hullgrind::outline_t& msg);
// The camera-to-base this outline is planned with, set in cfg: eye-to-hand (cfg.camera_to_flange empty) the
// cell's, unchanged; eye-in-hand base<-flange at capture (the outline's flange fields) x camera-to-flange.
// Returns why not (no valid flange pose, not a unit quaternion), empty when placed. mounting.cpp.
std::string place_outline(const hullgrind::outline_t& msg, PlannerConfig& cfg);
// The path message with its revision (1 for a job's first plan, +1 per REPLAN), the coverage of every outline
// loop and every stretch of edge the plan leaves unground (unground_stretches).
hullgrind::grind_path_t to_lcm(const PlanResult& result, const std::string& job_id, std::int64_t outline_seq,
                               const std::string& frame, std::int64_t utime, std::int32_t revision = 1);
// Every stretch of edge the plan leaves unground, in loop order: a skipped loop whole (CAUSE_TOO_SMALL), each
// unreached stretch of a planned loop (CAUSE_CORNER at a concave corner or bend tighter than the tool, else
// CAUSE_UNREACHED), each with its measured numbers in the reason.
std::vector<hullgrind::edge_stretch_t> unground_stretches(const PlanResult& result);

}  // namespace hg::path_planner
