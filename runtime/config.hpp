// One configuration format for every process: a YAML file read with yaml-cpp (real booleans, lists,
// nested maps). Keys may be nested; "robot.workspace-min" reads key workspace-min inside map robot.
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace hg::runtime {

struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Config {
 public:
  Config() = default;                           // empty: every lookup falls back to its default
  static Config load(const std::string& path);  // throws ConfigError naming the file (and line)
  static Config from_string(const std::string& yaml, const std::string& name = "<string>");

  bool empty() const { return !root_; }
  const std::string& source() const { return source_; }
  bool has(const std::string& key) const;
  // Every key whose value is not a map, nested ones dotted ("robot.speed"), in file order.
  std::vector<std::string> keys() const;
  // The line (1-based) a key is written on, 0 if unknown.
  int line_of(const std::string& key) const;

  // Typed lookups; a key present with the wrong type throws ConfigError naming the file and key.
  std::optional<std::string> get_string(const std::string& key) const;
  std::optional<double> get_double(const std::string& key) const;
  std::optional<bool> get_bool(const std::string& key) const;
  std::optional<std::vector<double>> get_doubles(const std::string& key) const;
  std::optional<std::vector<std::string>> get_strings(const std::string& key) const;  // a list of scalars
  // True when the key holds a YAML list (rather than a scalar).
  bool is_list(const std::string& key) const;

  // "config 'FILE': key 'KEY': WHAT" — the one shape of every configuration error.
  ConfigError error(const std::string& key, const std::string& what) const;

 private:
  struct Root;
  std::shared_ptr<const Root> root_;
  std::string source_;
};

// A default file of the tree ("config/cell.yaml", "config/path_planner.yaml") as every program finds it,
// whatever its working directory: $HG_CONFIG_DIR/cell.yaml when HG_CONFIG_DIR is set; else next to the
// executable, EXE_DIR/../../config/cell.yaml (the build tree: build/bin) or
// EXE_DIR/../share/hullgrind/config/cell.yaml (an install), the first that exists; else as given (relative to
// the working directory, so the message names the file the program looked for). Not for a file a user named.
std::string default_file(const std::string& tree_path);

}  // namespace hg::runtime
