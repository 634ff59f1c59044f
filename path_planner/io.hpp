// Configuration, outline/path files and LCM conversions of the planner (shared by hg-path-planner and
// hg-plan).
#pragma once

#include "path_planner/pipeline.hpp"
#include "runtime/node.hpp"

#include <functional>
#include <nlohmann/json.hpp>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/outline_t.hpp"

namespace hg::path_planner {

// Every planner parameter with its default and help text (the process adds its own job-handling ones).
std::vector<runtime::Param> planner_params();

// Where parameter values come from (command line > config file > default, as runtime::Node does).
struct ParamLookup {
  std::function<std::string(const std::string&)> text;
  std::function<std::vector<double>(const std::string&)> list;
};
ParamLookup lookup_from(const runtime::Node& node);
// Throws runtime::ConfigError naming the parameter when a value is unusable.
PlannerConfig config_from(const ParamLookup& lookup);

// Outline JSON as hg-outline writes it: {"loops": [{"hole", "points": [[x, y], ...]}, ...], "plane"?:
// {"origin", "normal", "u", "v"}}. Without a plane, default_plane is used. Throws std::runtime_error
// naming the byte (parse errors) or the loop and point index.
OutlineInput read_outline_json(const std::string& text, const Plane& default_plane);

// {"job_id", "frame", "waypoints": [{"position", "orientation" [w, x, y, z], "speed", "kind"}], "tool_radius",
// "tilt", "flipped", "coverage": coverage_json}
nlohmann::ordered_json path_json(const std::string& job_id, const std::string& frame, const PlanResult& result);
// {"tolerance", "unreached_length", "loops": [{"loop", "hole", "length", "reached_fraction", "unreached":
// [{"start", "length", "concave", "points": [[x, y, z], ...]}]}]}: metres; points in the path's (base) frame.
nlohmann::ordered_json coverage_json(const PlanResult& result);
const char* kind_name(std::int8_t kind);

OutlineInput from_lcm(const hullgrind::outline_t& msg);
hullgrind::grind_path_t to_lcm(const PlanResult& result, const std::string& job_id, std::int64_t outline_seq,
                               const std::string& frame, std::int64_t utime);

}  // namespace hg::path_planner
