#include "sim/partgen/presets.hpp"

#include <numbers>
#include <stdexcept>

namespace hg::partgen {

namespace {
// Rotation of test piece k on the table (same in every table), degrees.
constexpr double kRotation[6] = {3.0, -5.0, 7.0, 2.0, 1.5, -3.0};

std::vector<Preset> build() {
  const char* shapes[6] = {"plate-hole-slot", "l-bracket",   "knee-scallop",
                           "collar-notch",    "ring-flange", "trapezoid-holes"};
  struct TableDef {
    const char* prefix;
    const char* table;
    std::size_t points[6];
    double pitch[6];  // fitted with `hg-gen --fit-presets`
  };
  const TableDef tables[3] = {
      {"low",
       "Table 1",
       {3716, 3161, 2179, 8258, 8828, 8696},
       {4.85971596e-03, 2.89212998e-03, 4.41568431e-03, 3.39708481e-03, 3.76348668e-03, 3.33120527e-03}},
      {"high",
       "Table 4",
       {763685, 513513, 406434, 1591649, 1015985, 997571},
       {3.38879337e-04, 2.26949359e-04, 3.23338382e-04, 2.44666524e-04, 3.51677350e-04, 3.10990648e-04}},
      {"down",
       "Table 6",
       {17604, 16295, 12263, 17130, 15531, 14809},
       {2.23205466e-03, 1.27400631e-03, 1.86188214e-03, 2.35796021e-03, 2.84346086e-03, 2.55311406e-03}},
  };
  std::vector<Preset> out;
  for (const TableDef& t : tables)
    for (int k = 0; k < 6; ++k)
      out.push_back({std::string(t.prefix) + "-" + std::to_string(k + 1), t.table, k + 1, shapes[k], 1.0, kRotation[k],
                     t.pitch[k], t.points[k]});
  return out;
}
}  // namespace

const std::vector<Preset>& presets() {
  static const std::vector<Preset> all = build();
  return all;
}

const Preset& find_preset(std::string_view name) {
  for (const Preset& p : presets())
    if (p.name == name) return p;
  throw std::invalid_argument("unknown preset '" + std::string(name) +
                              "' (valid: low-1..low-6, high-1..high-6, down-1..down-6)");
}

Scene preset_scene(const Preset& p) {
  return single_part_scene(make_shape(p.shape, p.scale), p.rotation_deg * std::numbers::pi / 180.0);
}

CloudOptions preset_options(const Preset& p) {
  CloudOptions o;
  o.pitch = p.pitch;
  return o;
}

}  // namespace hg::partgen
