// The planner's input from an outline file (outline_io/outline_file.hpp, docs/outline_file.md: the one reader).
#pragma once

#include <string>

#include "outline_io/outline_file.hpp"
#include "path_planner/pipeline.hpp"

namespace hg::path_planner {

// The file's loops, plane (default_plane when it has none), frame and spacing.
OutlineInput outline_input(const outline_io::OutlineFile& file, const Plane& default_plane);
// An outline file by its path, or its text (named `name` in errors). Throws outline_io::ReadError naming the
// file and the byte (not JSON) or the key (loops[0].points[2]).
OutlineInput read_outline_file(const std::string& path, const Plane& default_plane);
OutlineInput read_outline_json(const std::string& text, const Plane& default_plane,
                               const std::string& name = "outline");

}  // namespace hg::path_planner
