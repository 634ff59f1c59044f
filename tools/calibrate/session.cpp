#include "tools/calibrate/session.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "camera_bridge/sources.hpp"
#include "cell/cell.hpp"
#include "outline_io/cloud.hpp"
#include "outline_io/outline_file.hpp"
#include "runtime/config.hpp"

namespace hg::calibrate {

using nlohmann::json;

std::vector<double> to_row_major(const Eigen::Isometry3d& t) {
  std::vector<double> v;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) v.push_back(t.matrix()(r, c));
  return v;
}

Eigen::Isometry3d from_row_major(const std::vector<double>& v, const std::string& where) {
  if (v.size() != 16) throw std::runtime_error(where + ": expected 16 numbers (4x4 row-major)");
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) t.matrix()(r, c) = v[4 * r + c];
  if (!cell::is_rotation(t.linear()))
    throw std::runtime_error(where + ": rotation part is not a rotation (orthonormal, determinant +1)");
  return t;
}

namespace {

Eigen::Vector3d vec3(const json& j, const char* key) {
  const auto v = j.at(key).get<std::vector<double>>();
  if (v.size() != 3) throw std::runtime_error(std::string(key) + ": expected [x, y, z]");
  return {v[0], v[1], v[2]};
}

json vec3_json(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

camera::Intrinsics intrinsics_from(const json& in) {
  return {in.at("width").get<int>(),        in.at("height").get<int>(), in.at("fx").get<double>(),
          in.at("fy").get<double>(),        in.at("cx").get<double>(),  in.at("cy").get<double>(),
          in.at("depth_unit").get<double>()};
}

// The view's data: a depth PNG, a cloud through the intrinsics, or an outline file. `key` follows what is read.
void read_view_data(const std::string& dir, const json& v, SessionView& sv, std::string& key, const std::string& at,
                    bool load) {
  for (const char* kind : {"depth", "cloud", "outline"})
    if (v.contains(kind)) sv.kind = kind;
  key = at + sv.kind;
  sv.file = v.at(sv.kind).get<std::string>();
  const std::string path = dir + "/" + sv.file;
  if (sv.kind == "outline") {
    if (load) read_outline_view(path, sv);
    return;
  }
  key = at + "intrinsics";
  sv.intrinsics = intrinsics_from(v.at("intrinsics"));
  key = at + sv.kind;
  if (!load) return;
  if (sv.kind == "cloud") {
    sv.depth = camera_bridge::cloud_to_depth(outline_io::read_cloud_file(path).xyz, sv.intrinsics);
  } else {
    sv.depth = cv::imread(path, cv::IMREAD_UNCHANGED);
    if (sv.depth.empty() || sv.depth.type() != CV_16UC1) throw std::runtime_error("not a 16-bit depth PNG");
  }
}

SessionView read_view(const std::string& dir, const json& v, const std::string& mode, std::string& key,
                      const std::string& at, bool load) {
  SessionView sv;
  read_view_data(dir, v, sv, key, at, load);
  if (v.contains("flange_to_base")) {
    key = at + "flange_to_base";
    sv.flange_to_base = from_row_major(v["flange_to_base"].get<std::vector<double>>(), "flange_to_base");
  }
  if (v.contains("tcp_at_hole"))
    for (const auto& [id, p] : v["tcp_at_hole"].items()) {
      key = at + "tcp_at_hole." + id;
      const auto xyz = p.get<std::vector<double>>();
      if (xyz.size() != 3) throw std::runtime_error("expected [x, y, z]");
      sv.tcp_at_hole[id] = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
    }
  if (mode == "eye-in-hand" && !sv.flange_to_base) throw std::runtime_error("missing flange_to_base");
  return sv;
}

}  // namespace

json outline_view_json(const calibration::PlatePlane& plane, const std::vector<calibration::HoleLoop>& loops) {
  outline_io::OutlineFile f;
  f.frame = "camera";
  auto arr = [](const Eigen::Vector3d& p) { return std::array<double, 3>{p.x(), p.y(), p.z()}; };
  f.plane = outline_io::Plane{arr(plane.origin), arr(plane.u_axis.cross(plane.v_axis).normalized()), arr(plane.u_axis),
                              arr(plane.v_axis)};
  for (const auto& loop : loops) {
    outline_io::OutlineLoop l{true, {}};
    for (const auto& p : loop) l.points.push_back({p.x(), p.y()});
    f.loops.push_back(std::move(l));
  }
  return json(outline_io::outline_file_json(f));
}

void read_outline_view(const std::string& path, SessionView& v) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw runtime::ConfigError(path + ": cannot open");  // a bad input file: exit 2
  std::ostringstream text;
  text << in.rdbuf();
  const outline_io::OutlineFile f = outline_io::parse_outline_file(text.str(), path);
  if (!f.plane) throw outline_io::ReadError(path + ": plane: missing (an outline view needs the plate plane)");
  auto vec = [](const std::array<double, 3>& a) { return Eigen::Vector3d(a[0], a[1], a[2]); };
  v.plane = {vec(f.plane->origin), vec(f.plane->u), vec(f.plane->v)};
  v.loops.clear();
  for (const outline_io::OutlineLoop& l : f.loops) {
    if (!l.hole) continue;  // the drilled holes are the features; the plate's outer edge is none
    calibration::HoleLoop loop;
    for (const auto& p : l.points) loop.emplace_back(p.x, p.y);
    v.loops.push_back(std::move(loop));
  }
  v.outline_record = json::parse(text.str());  // the file as read (parse_outline_file took it as JSON)
}

Session read_session(const std::string& dir, bool load_data) {
  const std::string path = dir + "/session.json";
  std::ifstream f(path);
  if (!f) throw runtime::ConfigError(path + ": cannot open");  // a bad input file: exit 2
  json j;
  try {
    j = json::parse(f);
  } catch (const json::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  Session s;
  std::string key = "mode";
  try {
    s.mode = j.at("mode").get<std::string>();
    if (s.mode != "eye-to-hand" && s.mode != "eye-in-hand") throw std::runtime_error("unknown mode '" + s.mode + "'");
    for (std::size_t i = 0; i < j.at("views").size(); ++i)
      s.views.push_back(read_view(dir, j["views"][i], s.mode, key, "views[" + std::to_string(i) + "].", load_data));
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + key + ": " + e.what());
  }
  return s;
}

void write_session(const std::string& dir, const Session& s) {
  std::filesystem::create_directories(dir);
  json j{{"mode", s.mode}, {"views", json::array()}};
  for (const SessionView& v : s.views) {
    json jv{{v.kind, v.file}};
    const std::string path = dir + "/" + v.file;
    // A view read without its data keeps its file untouched.
    if (v.kind == "depth" && !v.depth.empty() && !cv::imwrite(path, v.depth))
      throw std::runtime_error(path + ": cannot write");
    if (v.kind == "outline" && !v.outline_record.is_null() &&
        !(std::ofstream(path) << v.outline_record.dump(1) << "\n"))
      throw std::runtime_error(path + ": cannot write");
    if (v.kind != "outline") {
      const auto& in = v.intrinsics;
      jv["intrinsics"] = {
          {"width", in.width}, {"height", in.height},        {"fx", in.fx}, {"fy", in.fy}, {"cx", in.cx},
          {"cy", in.cy},       {"depth_unit", in.depth_unit}};
    }
    if (v.flange_to_base) jv["flange_to_base"] = to_row_major(*v.flange_to_base);
    for (const auto& [id, p] : v.tcp_at_hole) jv["tcp_at_hole"][id] = vec3_json(p);
    j["views"].push_back(jv);
  }
  if (!(std::ofstream(dir + "/session.json") << j.dump(1) << "\n"))
    throw std::runtime_error(dir + "/session.json: cannot write");
}

calibration::PlateView detect_view(const SessionView& v, const calibration::Drawing& d) {
  if (v.kind == "outline") return calibration::plate_from_loops(v.plane, v.loops, d);
  return calibration::detect_plate(v.depth, v.intrinsics, d);
}

}  // namespace hg::calibrate
