// The planner's messages: outline_t -> OutlineInput, PlanResult -> grind_path_t.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "path_planner/pipeline.hpp"

namespace hg::path_planner {

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
