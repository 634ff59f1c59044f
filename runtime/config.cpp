#include "runtime/config.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace hg::runtime {

struct Config::Root {
  YAML::Node node;
};

namespace {

// Walks "a.b.c" through nested maps; an undefined node when any part is missing. Only const lookups
// (a non-const operator[] inserts the key) and reset(), never operator= (which would overwrite content).
YAML::Node find(const YAML::Node& root, const std::string& key) {
  YAML::Node n;
  n.reset(root);
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!n.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& map = n;
    const YAML::Node next = map[part];
    // A missing key gives an invalid ("zombie") node that throws on every question but IsDefined().
    if (!next.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
    if (dot == std::string::npos) return next;
    n.reset(next);
    start = dot + 1;
  }
}

bool parse_number(const std::string& s, double& out) {
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return !s.empty() && end && *end == '\0' && std::isfinite(out);
}

void collect_keys(const YAML::Node& map, const std::string& prefix, std::vector<std::string>& out) {
  for (const auto& kv : map) {
    const std::string key = prefix + kv.first.as<std::string>();
    if (kv.second.IsMap()) collect_keys(kv.second, key + ".", out);
    else
      out.push_back(key);
  }
}

}  // namespace

Config Config::load(const std::string& path) {
  std::ifstream probe(path);
  if (!probe) throw ConfigError("config '" + path + "': cannot open");
  std::stringstream text;
  text << probe.rdbuf();
  return from_string(text.str(), path);
}

Config Config::from_string(const std::string& yaml, const std::string& name) {
  Config c;
  c.source_ = name;
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    throw ConfigError("config '" + name + "': line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (root.IsNull() || !root.IsDefined()) root = YAML::Node(YAML::NodeType::Map);  // an empty file
  if (!root.IsMap()) throw ConfigError("config '" + name + "': the top level is not a map of keys");
  c.root_ = std::make_shared<const Root>(Root{root});
  return c;
}

ConfigError Config::error(const std::string& key, const std::string& what) const {
  const int line = line_of(key);
  return ConfigError("config '" + source_ + "'" + (line > 0 ? " line " + std::to_string(line) : std::string()) +
                     ": key '" + key + "': " + what);
}

bool Config::has(const std::string& key) const {
  if (!root_) return false;
  const YAML::Node n = find(root_->node, key);
  return n.IsDefined() && !n.IsNull();
}

std::vector<std::string> Config::keys() const {
  std::vector<std::string> out;
  if (root_) collect_keys(root_->node, "", out);
  return out;
}

int Config::line_of(const std::string& key) const {
  if (!root_) return 0;
  const YAML::Node n = find(root_->node, key);
  return n.IsDefined() && n.Mark().line >= 0 ? n.Mark().line + 1 : 0;
}

bool Config::is_list(const std::string& key) const {
  if (!root_) return false;
  return find(root_->node, key).IsSequence();
}

std::optional<std::string> Config::get_string(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  const YAML::Node n = find(root_->node, key);
  if (!n.IsScalar()) throw error(key, "expected a single value, not a list or map");
  return n.Scalar();
}

std::optional<double> Config::get_double(const std::string& key) const {
  const std::optional<std::string> s = get_string(key);
  if (!s) return std::nullopt;
  double v = 0;
  if (!parse_number(*s, v)) throw error(key, "'" + *s + "' is not a number");
  return v;
}

std::optional<bool> Config::get_bool(const std::string& key) const {
  const std::optional<std::string> s = get_string(key);
  if (!s) return std::nullopt;
  if (*s == "true") return true;
  if (*s == "false") return false;
  throw error(key, "'" + *s + "' is not true or false");
}

std::optional<std::vector<double>> Config::get_doubles(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  const YAML::Node n = find(root_->node, key);
  if (!n.IsSequence()) throw error(key, "expected a list of numbers, as [1, 2, 3]");
  std::vector<double> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    double v = 0;
    if (!n[i].IsScalar() || !parse_number(n[i].Scalar(), v))
      throw error(key, "element " + std::to_string(i) + " is not a number");
    out.push_back(v);
  }
  return out;
}

std::optional<std::vector<std::string>> Config::get_strings(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  const YAML::Node n = find(root_->node, key);
  if (!n.IsSequence()) throw error(key, "expected a list, as [a, b, c]");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    if (!n[i].IsScalar()) throw error(key, "element " + std::to_string(i) + " is not a single value");
    out.push_back(n[i].Scalar());
  }
  return out;
}

std::string default_file(const std::string& tree_path) {
  namespace fs = std::filesystem;
  const std::string prefix = "config/";
  if (tree_path.compare(0, prefix.size(), prefix) != 0) return tree_path;
  const std::string rest = tree_path.substr(prefix.size());
  if (const char* dir = std::getenv("HG_CONFIG_DIR"); dir && *dir) return (fs::path(dir) / rest).string();
  std::error_code ec;
  const fs::path exe_dir = fs::read_symlink("/proc/self/exe", ec).parent_path();
  if (ec) return tree_path;
  for (const fs::path& dir :
       {exe_dir.parent_path().parent_path() / "config", exe_dir.parent_path() / "share/hullgrind/config"})
    if (fs::exists(dir / rest, ec)) return (dir / rest).string();
  return tree_path;
}

}  // namespace hg::runtime
