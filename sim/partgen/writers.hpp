// Writing a synthesized cloud and its ground truth. Files are written to a temporary name beside the
// target and renamed when complete, so a failed run never leaves half a file behind.
#pragma once

#include "sim/partgen/shapes.hpp"
#include "sim/partgen/synth.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace hg::partgen {

// `x y z` per line, metres, fixed 7 decimals (0.1 um), scan-line order.
void write_xyz(const Cloud& cloud, const std::string& path);
// PCD v0.7, FIELDS x y z, SIZE 4, TYPE F, unorganised (HEIGHT 1); binary = little-endian float32 records.
void write_pcd(const Cloud& cloud, const std::string& path, bool binary = true);

// Ground truth in the cloud's frame and units: every part's placed polygon (outer CCW, holes CW), exact
// and polygon areas/perimeters, thickness, pose, the pixel grid and the noise settings, point count.
nlohmann::json truth_json(const Scene& scene, const CloudOptions& options, const Cloud& cloud);
// Pretty-printed JSON written atomically.
void write_json(const nlohmann::json& j, const std::string& path);

}  // namespace hg::partgen
