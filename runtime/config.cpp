#include "runtime/config.hpp"

#include <fstream>
#include <sstream>

namespace hg::runtime {

Config Config::load(const std::string& path) {
  std::ifstream probe(path);
  if (!probe) throw ConfigError("config: cannot open '" + path + "'");
  std::stringstream text;
  text << probe.rdbuf();
  return from_string(text.str(), path);
}

namespace {
// OpenCV's YAML reader keeps "value  # comment" as the value. Drop comments that start at the beginning
// of a line or after a blank, outside quotes, so that ordinary YAML files read as people expect.
std::string strip_comments(const std::string& yaml) {
  std::string out;
  out.reserve(yaml.size());
  char quote = 0;
  bool comment = false;
  for (std::size_t i = 0; i < yaml.size(); ++i) {
    char ch = yaml[i];
    if (ch == '\n') {
      comment = false;
      quote = 0;
    } else if (comment) {
      continue;
    } else if (quote) {
      if (ch == quote) quote = 0;
    } else if (ch == '"' || ch == '\'') {
      quote = ch;
    } else if (ch == '#' && (i == 0 || yaml[i - 1] == ' ' || yaml[i - 1] == '\t' || yaml[i - 1] == '\n')) {
      if (!(i == 0 && yaml.rfind("%YAML", 0) == 0)) {
        comment = true;
        while (!out.empty() && (out.back() == ' ' || out.back() == '\t')) out.pop_back();
        continue;
      }
    }
    out += ch;
  }
  return out;
}
}  // namespace

Config Config::from_string(const std::string& yaml, const std::string& name) {
  Config c;
  c.source_ = name;
  std::string text = strip_comments(yaml);
  // FileStorage wants the YAML directive; accept plain YAML files without it.
  if (text.rfind("%YAML", 0) != 0 && text.find_first_not_of(" \t\r\n") != std::string::npos &&
      text[text.find_first_not_of(" \t\r\n")] != '{')
    text = "%YAML:1.0\n---\n" + text;
  try {
    c.fs_ = std::make_shared<cv::FileStorage>(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const cv::Exception& e) {
    throw ConfigError("config: cannot parse '" + name + "': " + e.msg);
  }
  if (!c.fs_->isOpened()) throw ConfigError("config: cannot parse '" + name + "'");
  return c;
}

cv::FileNode Config::node(const std::string& key) const {
  if (empty()) return {};
  cv::FileNode n = fs_->root();
  std::size_t start = 0;
  while (true) {
    std::size_t dot = key.find('.', start);
    std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!n.isMap()) return {};
    n = n[part];
    if (n.empty() || dot == std::string::npos) return n;
    start = dot + 1;
  }
}

bool Config::has(const std::string& key) const {
  cv::FileNode n = node(key);
  return !n.empty() && !n.isNone();
}

std::optional<std::string> Config::get_string(const std::string& key) const {
  cv::FileNode n = node(key);
  if (n.empty() || n.isNone()) return std::nullopt;
  if (n.isString()) return n.string();
  if (n.isInt()) return std::to_string(int(n));
  if (n.isReal()) {
    std::ostringstream s;
    s.precision(17);
    s << double(n);
    return s.str();
  }
  throw ConfigError("config: '" + source_ + "': key '" + key + "' is not a scalar");
}

std::optional<double> Config::get_double(const std::string& key) const {
  cv::FileNode n = node(key);
  if (n.empty() || n.isNone()) return std::nullopt;
  if (n.isInt() || n.isReal()) return double(n);
  if (n.isString()) {
    std::string s = n.string();
    char* end = nullptr;
    double v = std::strtod(s.c_str(), &end);
    if (!s.empty() && end && *end == '\0') return v;
  }
  throw ConfigError("config: '" + source_ + "': key '" + key + "' is not a number");
}

std::optional<std::vector<double>> Config::get_doubles(const std::string& key) const {
  cv::FileNode n = node(key);
  if (n.empty() || n.isNone()) return std::nullopt;
  if (!n.isSeq()) throw ConfigError("config: '" + source_ + "': key '" + key + "' is not a list of numbers");
  std::vector<double> out;
  for (auto it = n.begin(); it != n.end(); ++it) {
    cv::FileNode e = *it;
    if (!(e.isInt() || e.isReal()))
      throw ConfigError("config: '" + source_ + "': key '" + key + "' has a non-number element");
    out.push_back(double(e));
  }
  return out;
}

}  // namespace hg::runtime
