// hullgrind outline I/O: results out. Outline JSON, triangle list, SVG and PNG pictures, and files that
// are written whole or not at all (temp file in the same folder, then rename).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "outline_io/cloud.hpp"
#include "outline_core/outline.hpp"

namespace hg::outline_io {

struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct RunInfo {
  std::string input;   // file name as given
  std::string format;  // Cloud::format
  bool has_z = false;
  double read_ms = 0;     // parsing the file
  double project_ms = 0;  // plane fit + projection (part of time_ms.total)
  // The frame the input's coordinates (and so the plane and the loops) are in: "cloud" for a file (its own
  // coordinates, whatever they are), "camera" for the camera bridge's plate cloud.
  std::string frame = "cloud";
};

// Keys: frame (RunInfo::frame), points_read, points_used, duplicates_merged, alpha_radius, mode, order, triangles,
// search_cost = search_cost_locate (point location) + search_cost_cavity (cavity search), time_ms {read, triangulate,
// alpha, loops, total}, loops [{hole, area, perimeter, points}], plus input, alpha_automatic, alpha_mode, spacing,
// nn_spacing_median, holes_dropped, incircle_tests, orient_tests, time_ms.project; for 3-D input also plane {origin,
// normal, u, v, rms_distance, max_distance} and per loop points_3d. time_ms.total is everything after reading:
// projection + compute_outline.
nlohmann::ordered_json outline_json(const Result& result, const PlanarPoints& planar, const RunInfo& info);

// One triangle per line "i j k", 0-based indices into the points as read.
std::string triangles_text(const Result& result);

// Pictures fitted to about 1200 px, y up: points, outer loops (blue), holes (red), optionally triangles.
std::string render_svg(std::span<const Vec2> points, const Result& result, bool draw_triangles);
std::vector<unsigned char> render_png(std::span<const Vec2> points, const Result& result, bool draw_triangles);

// Writes `content` to a temp file beside `path`; commit() renames every staged file into place.
// Files not committed are removed when the object dies, so an error leaves no output behind.
class StagedFiles {
 public:
  StagedFiles() = default;
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles();
  void stage(const std::string& path, const void* data, std::size_t size);  // throws WriteError
  void stage(const std::string& path, const std::string& content) { stage(path, content.data(), content.size()); }
  void commit();  // throws WriteError

 private:
  struct Entry {
    std::string final_path, temp_path;
  };
  std::vector<Entry> entries_;
};

}  // namespace hg::outline_io
