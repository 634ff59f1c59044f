#include "cell/cell.hpp"

#include <cctype>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <tuple>

#include <yaml-cpp/yaml.h>

#include "runtime/quantities.hpp"

namespace hg::cell {
namespace {

[[noreturn]] void fail(const std::string& where, const std::string& key, const std::string& what) {
  throw CellError(where + ": " + key + ": " + what);
}

// Refuses keys the schema does not know (a typo must not silently fall back to a default) and keys given
// twice (yaml-cpp keeps the first silently).
void only_keys(const YAML::Node& map, const std::set<std::string>& known, const std::string& where,
               const std::string& prefix) {
  if (!map.IsMap()) fail(where, prefix.empty() ? "(top level)" : prefix, "expected a mapping");
  std::set<std::string> seen;
  for (const auto& kv : map) {
    const std::string key = kv.first.as<std::string>();
    if (!seen.insert(key).second) fail(where, prefix + key, "given twice");
    if (!known.count(key)) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      fail(where, prefix + key, "unknown key (known: " + list + ")");
    }
  }
}

YAML::Node need(const YAML::Node& map, const std::string& key, const std::string& where, const std::string& prefix) {
  const YAML::Node n = map[key];
  if (!n) fail(where, prefix + key, "missing");
  return n;
}

double number(const YAML::Node& n, const std::string& where, const std::string& key) {
  if (!n.IsScalar()) fail(where, key, "expected a number");
  double v = 0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(where, key, "expected a number, got '" + n.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail(where, key, "not a finite number");
  return v;
}

std::string text(const YAML::Node& n, const std::string& where, const std::string& key) {
  if (!n.IsScalar()) fail(where, key, "expected a string");
  return n.Scalar();
}

Eigen::Vector3d vec3(const YAML::Node& n, const std::string& where, const std::string& key) {
  if (!n.IsSequence() || n.size() != 3) fail(where, key, "expected a list of 3 numbers");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = number(n[i], where, key + "[" + std::to_string(i) + "]");
  return v;
}

// 4 rows of 4 numbers, row-major; the last row must be 0 0 0 1.
Eigen::Isometry3d transform(const YAML::Node& n, const std::string& where, const std::string& key) {
  if (!n.IsSequence() || n.size() != 4) fail(where, key, "expected 4 rows of 4 numbers");
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    const std::string row = key + "[" + std::to_string(r) + "]";
    if (!n[r].IsSequence() || n[r].size() != 4) fail(where, row, "expected a row of 4 numbers");
    for (int c = 0; c < 4; ++c) m(r, c) = number(n[r][c], where, row + "[" + std::to_string(c) + "]");
  }
  if (m.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) fail(where, key, "last row must be [0, 0, 0, 1]");
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.matrix() = m;
  return t;
}

Mounting mounting(const YAML::Node& n, const std::string& where, const std::string& key) {
  if (!n) return Mounting::EyeToHand;
  const std::string m = text(n, where, key);
  if (m == to_string(Mounting::EyeToHand)) return Mounting::EyeToHand;
  if (m == to_string(Mounting::EyeInHand)) return Mounting::EyeInHand;
  fail(where, key, "'" + m + "' is neither eye-to-hand nor eye-in-hand");
}

Calibration read_calibration(const YAML::Node& n, const std::string& where) {
  const std::string p = "calibration.";
  only_keys(n, {"mounting", "camera-to-base", "camera-to-flange", "date", "method", "rms-mm", "worst-mm", "features"},
            where, p);
  Calibration c;
  c.mounting = mounting(n["mounting"], where, p + "mounting");
  c.camera_to_base = transform(need(n, "camera-to-base", where, p), where, p + "camera-to-base");
  if (n["camera-to-flange"]) c.camera_to_flange = transform(n["camera-to-flange"], where, p + "camera-to-flange");
  c.date = text(need(n, "date", where, p), where, p + "date");
  c.method = text(need(n, "method", where, p), where, p + "method");
  c.rms_mm = number(need(n, "rms-mm", where, p), where, p + "rms-mm");
  c.worst_mm = number(need(n, "worst-mm", where, p), where, p + "worst-mm");
  const double f = number(need(n, "features", where, p), where, p + "features");
  if (f != std::floor(f) || f < 0) fail(where, p + "features", "expected a whole number >= 0");
  c.features = static_cast<int>(f);
  return c;
}

// Section `outline` (optional; each key optional, defaults in OutlineRules).
OutlineRules read_outline_rules(const YAML::Node& n, const std::string& where) {
  OutlineRules o;
  if (!n) return o;
  const std::string p = "outline.";
  only_keys(n, {"min-part-area", "max-edge-dropout", "max-edge-gap"}, where, p);
  if (n["min-part-area"]) o.min_part_area = number(n["min-part-area"], where, p + "min-part-area");
  if (n["max-edge-dropout"]) o.max_edge_dropout = number(n["max-edge-dropout"], where, p + "max-edge-dropout");
  if (n["max-edge-gap"]) o.max_edge_gap = number(n["max-edge-gap"], where, p + "max-edge-gap");
  return o;
}

// A frame name as messages carry it (header.frame_id): letters, digits, _ - . and /, not empty.
bool valid_frame_name(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-' && ch != '.' && ch != '/') return false;
  return true;
}

Frames read_frames(const YAML::Node& n, const std::string& where) {
  Frames f;
  if (!n) return f;
  only_keys(n, {"base"}, where, "frames.");
  if (n["base"]) f.base = text(n["base"], where, "frames.base");
  return f;
}

YAML::Node seq(const Eigen::Vector3d& v) {
  YAML::Node n;
  for (int i = 0; i < 3; ++i) n.push_back(v[i]);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

YAML::Node rows(const Eigen::Isometry3d& t) {
  YAML::Node out;
  for (int r = 0; r < 4; ++r) {
    YAML::Node row;
    for (int k = 0; k < 4; ++k) row.push_back(t.matrix()(r, k));
    row.SetStyle(YAML::EmitterStyle::Flow);
    out.push_back(row);
  }
  return out;
}

std::string stamp_for_file() {
  std::string iso = utc_now_iso();  // 2026-12-01T20:30:00Z -> 20261201T203000Z
  std::string out;
  for (char ch : iso)
    if (ch != '-' && ch != ':') out += ch;
  return out;
}

}  // namespace

const char* to_string(Mounting m) { return m == Mounting::EyeInHand ? "eye-in-hand" : "eye-to-hand"; }

std::string utc_now_iso() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

bool is_rotation(const Eigen::Matrix3d& R) {
  return R.allFinite() && (R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-6 &&
         R.determinant() > 0;
}

void validate(const Cell& c, const std::string& where) {
  if (!is_rotation(c.calibration.camera_to_base.linear()))
    fail(where, "calibration.camera-to-base", "rotation part is not a proper orthonormal matrix");
  if (c.calibration.camera_to_flange && !is_rotation(c.calibration.camera_to_flange->linear()))
    fail(where, "calibration.camera-to-flange", "rotation part is not a proper orthonormal matrix");
  if (c.calibration.mounting == Mounting::EyeInHand && !c.calibration.camera_to_flange)
    fail(where, "calibration.camera-to-flange", "missing: calibration.mounting eye-in-hand needs it");
  if (c.calibration.rms_mm < 0 || c.calibration.worst_mm < c.calibration.rms_mm)
    fail(where, "calibration.rms-mm", "residuals must satisfy 0 <= rms-mm <= worst-mm");
  for (int i = 0; i < 3; ++i)
    if (!(c.workspace_min[i] < c.workspace_max[i]))
      fail(where, "workspace.min", "must be below workspace.max on every axis");
  if (!(c.table_z >= c.workspace_min.z() && c.table_z < c.workspace_max.z()))
    fail(where, "table-z", "must lie in the workspace's z range");
  if (!(c.max_speed > 0)) fail(where, "max-speed", "must be > 0");
  if (!(c.max_accel > 0)) fail(where, "max-accel", "must be > 0");
  // The tool's ranges are the job quantities' (runtime/quantities.hpp), which every reader of a job checks.
  for (const auto& [key, q, v] : {std::tuple{"tool.radius", &quantity::kToolRadius, c.tool.radius},
                                  std::tuple{"tool.tilt", &quantity::kTilt, c.tool.tilt}})
    if (!q->contains(v)) fail(where, key, "must be within " + quantity::range_text(*q));
  if (!valid_frame_name(c.frames.base)) fail(where, "frames.base", "'" + c.frames.base + "' is no frame name");
  if ((c.home.array() < c.workspace_min.array()).any() || (c.home.array() > c.workspace_max.array()).any() ||
      !(c.home.z() > c.table_z))
    fail(where, "home", "must lie inside the workspace and above the table");
  if (!(c.outline.min_part_area >= 0)) fail(where, "outline.min-part-area", "must be >= 0");
  if (!(c.outline.max_edge_dropout >= 0 && c.outline.max_edge_dropout <= 1))
    fail(where, "outline.max-edge-dropout", "must be within [0, 1]");
  if (!(c.outline.max_edge_gap >= 0)) fail(where, "outline.max-edge-gap", "must be >= 0");
}

Cell read_cell(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw CellError(path + ": cannot open");
  } catch (const YAML::Exception& e) {
    throw CellError(path + ": line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  only_keys(root,
            {"calibration", "table-z", "workspace", "max-speed", "max-accel", "tool", "home", "approval", "outline",
             "frames"},
            path, "");
  Cell c;
  c.calibration = read_calibration(need(root, "calibration", path, ""), path);
  c.table_z = number(need(root, "table-z", path, ""), path, "table-z");
  const YAML::Node ws = need(root, "workspace", path, "");
  only_keys(ws, {"min", "max"}, path, "workspace.");
  c.workspace_min = vec3(need(ws, "min", path, "workspace."), path, "workspace.min");
  c.workspace_max = vec3(need(ws, "max", path, "workspace."), path, "workspace.max");
  c.max_speed = number(need(root, "max-speed", path, ""), path, "max-speed");
  c.max_accel = number(need(root, "max-accel", path, ""), path, "max-accel");
  const YAML::Node tool = need(root, "tool", path, "");
  only_keys(tool, {"radius", "tilt"}, path, "tool.");
  c.tool.radius = number(need(tool, "radius", path, "tool."), path, "tool.radius");
  c.tool.tilt = number(need(tool, "tilt", path, "tool."), path, "tool.tilt");
  c.home = vec3(need(root, "home", path, ""), path, "home");
  if (const YAML::Node a = root["approval"]) {
    const std::string v = text(a, path, "approval");
    if (v != "auto" && v != "operator") fail(path, "approval", "'" + v + "' is not one of auto | operator");
    c.approval = v == "auto" ? Approval::Auto : Approval::Operator;
  }
  c.outline = read_outline_rules(root["outline"], path);
  c.frames = read_frames(root["frames"], path);
  validate(c, path);
  return c;
}

std::string write_cell(const std::string& path, const Cell& c) {
  validate(c, path);
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::Comment("hullgrind cell file (docs/cell.md): metres, radians, seconds; robot base frame.")
      << YAML::Newline;
  YAML::Node root;
  YAML::Node cal;
  cal["mounting"] = to_string(c.calibration.mounting);
  cal["camera-to-base"] = rows(c.calibration.camera_to_base);
  if (c.calibration.camera_to_flange) cal["camera-to-flange"] = rows(*c.calibration.camera_to_flange);
  cal["date"] = c.calibration.date;
  cal["method"] = c.calibration.method;
  cal["rms-mm"] = c.calibration.rms_mm;
  cal["worst-mm"] = c.calibration.worst_mm;
  cal["features"] = c.calibration.features;
  root["calibration"] = cal;
  root["table-z"] = c.table_z;
  root["workspace"]["min"] = seq(c.workspace_min);
  root["workspace"]["max"] = seq(c.workspace_max);
  root["max-speed"] = c.max_speed;
  root["max-accel"] = c.max_accel;
  root["tool"]["radius"] = c.tool.radius;
  root["tool"]["tilt"] = c.tool.tilt;
  root["home"] = seq(c.home);
  root["approval"] = c.approval == Approval::Auto ? "auto" : "operator";
  root["outline"]["min-part-area"] = c.outline.min_part_area;
  root["outline"]["max-edge-dropout"] = c.outline.max_edge_dropout;
  root["outline"]["max-edge-gap"] = c.outline.max_edge_gap;
  root["frames"]["base"] = c.frames.base;
  out << root;

  namespace fs = std::filesystem;
  std::string backup;
  std::error_code ec;
  if (fs::exists(path, ec)) {
    backup = path + "." + stamp_for_file() + ".bak";
    fs::copy_file(path, backup, fs::copy_options::overwrite_existing, ec);
    if (ec) throw CellError(path + ": cannot keep the backup " + backup + ": " + ec.message());
  }
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    f << out.c_str() << "\n";
    if (!f) throw CellError(path + ": cannot write " + tmp);
  }
  fs::rename(tmp, path, ec);
  if (ec) throw CellError(path + ": cannot replace: " + ec.message());
  return backup;
}

}  // namespace hg::cell
