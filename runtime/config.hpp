// One configuration format for every process: a YAML (or JSON) file read with OpenCV's FileStorage.
// Keys may be nested; "robot.workspace_min" reads key workspace_min inside map robot.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <memory>

#include <opencv2/core.hpp>

namespace hg::runtime {

struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Config {
 public:
  Config() = default;                          // empty: every lookup falls back to its default
  static Config load(const std::string& path); // throws ConfigError naming the file
  static Config from_string(const std::string& yaml, const std::string& name = "<string>");

  bool empty() const { return !fs_ || !fs_->isOpened(); }
  const std::string& source() const { return source_; }
  bool has(const std::string& key) const;

  // Typed lookups; a key present with the wrong type throws ConfigError naming the file and key.
  std::optional<std::string> get_string(const std::string& key) const;
  std::optional<double> get_double(const std::string& key) const;
  std::optional<std::vector<double>> get_doubles(const std::string& key) const;

 private:
  cv::FileNode node(const std::string& key) const;
  std::shared_ptr<cv::FileStorage> fs_;
  std::string source_;
};

}  // namespace hg::runtime
