// Cell files for tests (docs/cell.md): the shipped config/cell.yaml, or a copy with some values changed,
// written where the test says. Link hg_cell.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "cell/cell.hpp"

namespace hg::test {

inline std::string shipped_cell() { return std::string(HG_SOURCE_DIR) + "/config/cell.yaml"; }
inline std::string sim_cell() { return std::string(HG_SOURCE_DIR) + "/config/cell-sim.yaml"; }

// config/cell.yaml with `edit` applied, written to `path` (replacing it); returns path.
inline std::string write_test_cell(const std::string& path, const std::function<void(hg::cell::Cell&)>& edit) {
  hg::cell::Cell c = hg::cell::read_cell(shipped_cell());
  edit(c);
  std::filesystem::remove(path);
  hg::cell::write_cell(path, c);
  return path;
}

}  // namespace hg::test
