// Presets reproducing the sizes of the paper's clouds: Table 1 (low density, Percipio 1280x960),
// Table 4 (high density, Mech-Eye 2048x1536) and Table 6 (the high-density clouds down-sampled).
// Test piece k of every table is the same physical part (shape k of the catalogue, same size and
// rotation on the table); only the pixel pitch differs, fitted so the noise-free, dropout-free,
// non-jagged point count lands on the paper's count.
#pragma once

#include "sim/partgen/shapes.hpp"
#include "sim/partgen/synth.hpp"

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace hg::partgen {

struct Preset {
  std::string name;   // low-1..6, high-1..6, down-1..6
  std::string table;  // "Table 1", "Table 4", "Table 6"
  int piece = 0;      // test piece number 1..6
  std::string shape;  // catalogue name
  double scale = 1.0;
  double rotation_deg = 0;   // rotation of the part against the camera's pixel grid
  double pitch = 0;          // metres, fitted (hg-gen --fit-presets prints fresh values)
  std::size_t paper_points;  // the point count printed in the paper
};

const std::vector<Preset>& presets();
// Throws std::invalid_argument listing the valid names when unknown.
const Preset& find_preset(std::string_view name);
Scene preset_scene(const Preset& preset);
CloudOptions preset_options(const Preset& preset);  // pitch set, no noise, no dropout, not jagged

}  // namespace hg::partgen
