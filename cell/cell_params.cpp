#include "cell/cell_params.hpp"

#include <charconv>

#include "runtime/config.hpp"

namespace hg::cell {
namespace {

std::string number_text(double v) {  // the shortest text that reads back as v (as the parameters print it)
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

runtime::Param cell_param() {
  return runtime::text_param("cell", kDefaultCellFile,
                             "the cell file: camera-to-base, table, workspace, limits, tool, home (docs/cell.md)");
}

std::vector<runtime::Param> moved_to_cell(const std::vector<std::pair<std::string, std::string>>& old_to_cell_key) {
  std::vector<runtime::Param> out;
  for (const auto& [old_key, cell_key] : old_to_cell_key)
    out.push_back(runtime::moved_param(
        old_key, "the cell file (--cell, default " + std::string(kDefaultCellFile) + "), key " + cell_key));
  return out;
}

LoadedCell load_cell(const std::string& file) {
  try {
    return {file, read_cell(file)};
  } catch (const CellError& e) {
    throw runtime::ConfigError(std::string("cell file ") + e.what());
  }
}

LoadedCell load_cell(const runtime::Params& params) {
  // The default cell file is found from any working directory (next to the executable, or HG_CONFIG_DIR).
  return load_cell(params.given("cell") ? params.text("cell") : runtime::default_file(params.text("cell")));
}

motion::Limits limits_of(const Cell& c) {
  motion::Limits l;
  l.workspace_min = c.workspace_min;
  l.workspace_max = c.workspace_max;
  l.table_z = c.table_z;
  l.max_speed = c.max_speed;
  l.max_accel = c.max_accel;
  return l;
}

std::string cell_value_text(const LoadedCell& cell, const std::string& cell_key, double value) {
  return cell.file + " " + cell_key + " " + number_text(value);
}

void refuse_above(const runtime::Params& params, const std::string& name, double value, const LoadedCell& cell,
                  const std::string& cell_key, double limit) {
  if (value > limit)
    throw params.error(name, number_text(value) + " exceeds " + cell_value_text(cell, cell_key, limit));
}

void refuse_unequal(const runtime::Params& params, const std::string& name, double value, const LoadedCell& cell,
                    const std::string& cell_key, double cell_value) {
  if (params.given(name) && value != cell_value)
    throw params.error(name, number_text(value) + " contradicts " + cell_value_text(cell, cell_key, cell_value));
}

}  // namespace hg::cell
