// The grind path file (path.json): one schema, one writer, one reader, used by every tool that writes or
// reads paths (hg-plan, hg-overview, hg-robot-bridge --export). The in-memory form is the bus message
// grind_path_t, which every process already converts to and from. Schema (docs/path_file.md), snake_case
// keys like every hullgrind file schema:
//   {"job_id", "frame", "outline_seq", "tool_radius", "tilt", "flipped",
//    "waypoints": [{"position" [x, y, z], "orientation" [w, x, y, z], "speed", "kind", "loop"}]}
// kind is a name: approach | lead_in | grind | lead_out | retract | travel (the reader also takes the
// KIND_* number 0..5).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "hullgrind/grind_path_t.hpp"

namespace hg::path_file {

// Name of a grind_path_t::KIND_* value ("unknown" outside 0..5).
const char* kind_name(std::int8_t kind);
// The KIND_* value of a name, or nothing.
std::optional<std::int8_t> kind_from_name(const std::string& name);

nlohmann::ordered_json to_json(const hullgrind::grind_path_t& path);
// The JSON text as written to a file (indented, ends with a newline).
std::string to_text(const hullgrind::grind_path_t& path);

// Throws std::runtime_error "NAME: where: why" (NAME: the file name or what the text came from), naming the
// key and the waypoint index. Checks the schema only (keys, types, sizes, kinds), not whether the path is
// fit to run (robot_bridge::check_path does that).
hullgrind::grind_path_t from_json_text(const std::string& text, const std::string& name);
hullgrind::grind_path_t read_file(const std::string& file);

}  // namespace hg::path_file
