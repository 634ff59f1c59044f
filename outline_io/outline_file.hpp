// The outline file (docs/outline_file.md): one JSON format, one writer and one reader, for every program that
// writes or reads an outline: hg-outline, the job recorder's and hg-overview's outline.json (outline_writers.hpp
// and outline_message.hpp add their statistics to it), hg-calibrate's outline views, hg-plan.
//
//   {"frame"?: the frame the plane is in, "spacing"?: the point spacing (m), "plane"?: {"origin", "normal",
//    "u", "v"} ([x, y, z] each), "loops": [{"hole": true|false, "points": [[u, v], ...]}, ...]}
//
// The loops' points are plane coordinates (u, v) when there is a plane, else the cloud's own x, y. A writer may
// add keys (anywhere, also in a loop or the plane); the reader ignores keys it does not know.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "outline_io/cloud.hpp"

namespace hg::outline_io {

struct OutlineLoop {
  bool hole = false;
  std::vector<Vec2> points;
};

struct OutlineFile {
  std::string frame;           // "" when the file does not say
  double spacing = 0;          // the point spacing the outline was computed from, m; 0: not given
  std::optional<Plane> plane;  // the plane the loops lie in
  std::vector<OutlineLoop> loops;
};

// The file's keys in the order above; spacing only when > 0, frame only when not empty.
nlohmann::ordered_json outline_file_json(const OutlineFile& file);
// Throws ReadError "NAME: byte N: not JSON: ..." or "NAME: KEY: what is wrong" (KEY as loops[2].points[7]).
OutlineFile parse_outline_file(std::string_view text, const std::string& name);
OutlineFile read_outline_file(const std::string& path);  // ReadError "PATH: cannot open" too

}  // namespace hg::outline_io
