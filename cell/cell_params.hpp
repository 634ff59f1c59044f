// The cell file as the processes and tools take it: the one --cell parameter, the keys that moved into the
// cell file (refused where they used to be, naming where they live now), the cell's motion limits, and the
// contradiction rule (docs/cell.md): a value given to a process that contradicts the cell refuses to start and
// names both. Library hg_cell_params (hg_cell + hg_params + hg_motion, no LCM).
#pragma once

#include <string>
#include <vector>

#include "cell/cell.hpp"
#include "motion/motion.hpp"
#include "runtime/params.hpp"

namespace hg::cell {

inline constexpr const char* kDefaultCellFile = "config/cell.yaml";

// --cell FILE [default config/cell.yaml], declared once for every reader of the cell.
runtime::Param cell_param();

// moved_param(old, "the cell file (--cell), key NEW") for each {old, cell key} pair.
std::vector<runtime::Param> moved_to_cell(const std::vector<std::pair<std::string, std::string>>& old_to_cell_key);

// A cell read for a program: the file as named (for messages) and its content.
struct LoadedCell {
  std::string file;
  Cell cell;
};
// Reads the file named by parameter `cell` of `params`. A missing or broken file is a bad parameter:
// runtime::ConfigError with the cell's own message (file and key).
LoadedCell load_cell(const runtime::Params& params);
LoadedCell load_cell(const std::string& file);  // the same, for a file named directly

// The cell's limits as the motion rule checks them (workspace, table, max speed and acceleration).
motion::Limits limits_of(const Cell& cell);

// The contradiction rule. `value` is parameter `name` of `params`; `cell_key` names the cell's value.
// Throws params.error(name, "V exceeds FILE KEY LIMIT") when value > limit.
void refuse_above(const runtime::Params& params, const std::string& name, double value, const LoadedCell& cell,
                  const std::string& cell_key, double limit);
// Throws params.error(name, "V contradicts FILE KEY CELL_VALUE") when the parameter is given and differs.
void refuse_unequal(const runtime::Params& params, const std::string& name, double value, const LoadedCell& cell,
                    const std::string& cell_key, double cell_value);

// "config/cell.yaml max-speed 0.25": the cell's value as messages name it.
std::string cell_value_text(const LoadedCell& cell, const std::string& cell_key, double value);

}  // namespace hg::cell
