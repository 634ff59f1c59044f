// What the hg-calibrate tests share: a scratch folder per test, running a command line with its stderr
// captured, and reading a row-major 4x4 from a report.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

namespace hg::test {

// An empty folder TMP/<suite>_<pid>/<name>.
inline std::filesystem::path scratch_dir(const std::string& suite, const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / (suite + "_" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// Runs a command line (stdout discarded); returns its exit status, its stderr in *err.
inline int run_command(const std::string& suite, const std::string& cmd, std::string* err = nullptr) {
  const std::string log =
      (std::filesystem::temp_directory_path() / (suite + "_err_" + std::to_string(::getpid()))).string();
  const int status = std::system((cmd + " 2>" + log + " >/dev/null").c_str());
  if (err) {
    std::ifstream f(log);
    *err = std::string((std::istreambuf_iterator<char>(f)), {});
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline Eigen::Isometry3d row_major_4x4(const nlohmann::json& v) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) t.matrix()(r, c) = v.at(4 * r + c).get<double>();
  return t;
}

}  // namespace hg::test
