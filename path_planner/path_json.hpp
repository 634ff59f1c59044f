// The path file (docs/path_file.md) of a planned path, with the planner's coverage.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "path_planner/pipeline.hpp"

namespace hg::path_planner {

// The path file (path_file/path_file.hpp, docs/path_file.md) of a planned path, with the planner's
// "coverage": coverage_json (readers of paths ignore it).
nlohmann::ordered_json path_json(const std::string& job_id, const std::string& frame, const PlanResult& result,
                                 std::int64_t outline_seq = -1);
// {"tolerance", "unreached_length", "loops": [{"loop", "hole", "length", "reached_fraction", "unreached":
// [{"start", "length", "concave", "points": [[x, y, z], ...]}]}]}: metres; points in the path's (base) frame.
nlohmann::ordered_json coverage_json(const PlanResult& result);
const char* kind_name(std::int8_t kind);

}  // namespace hg::path_planner
