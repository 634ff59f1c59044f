// Cell files for tests (docs/cell.md): the shipped config/cell.yaml, or a copy with some values changed,
// written where the test says. Link hg_cell.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

#include "cell/cell.hpp"

namespace hg::test {

inline std::string shipped_cell() { return std::string(HG_SOURCE_DIR) + "/config/cell.yaml"; }
inline std::string sim_cell() { return std::string(HG_SOURCE_DIR) + "/config/cell-sim.yaml"; }

// The cell files this process wrote: removed when it exits (their names are this process's own).
struct TestCellFiles {
  std::vector<std::string> paths;
  ~TestCellFiles() {
    std::error_code ec;
    for (const std::string& path : paths) std::filesystem::remove(path, ec);
  }
};
inline TestCellFiles& test_cell_files() {
  static TestCellFiles files;
  return files;
}

// config/cell.yaml with `edit` applied, written to `path` with this process's id before its extension
// (replacing that file); returns the path written. CTest runs the cases of one suite as processes side by
// side, and two of them writing one file race on its temporary copy (write_cell's .tmp, then a rename).
inline std::string write_test_cell(const std::string& path, const std::function<void(hg::cell::Cell&)>& edit) {
  const std::filesystem::path p(path);
  const std::string mine =
      (p.parent_path() / (p.stem().string() + "-" + std::to_string(getpid()) + p.extension().string())).string();
  hg::cell::Cell c = hg::cell::read_cell(shipped_cell());
  edit(c);
  std::filesystem::remove(mine);
  hg::cell::write_cell(mine, c);
  test_cell_files().paths.push_back(mine);
  return mine;
}

}  // namespace hg::test
