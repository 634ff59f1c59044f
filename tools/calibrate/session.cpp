#include "tools/calibrate/session.hpp"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

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
  const Eigen::Matrix3d R = t.linear();
  if ((R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6)
    throw std::runtime_error(where + ": rotation part is not orthonormal");
  return t;
}

Session read_session(const std::string& dir) {
  const std::string path = dir + "/session.json";
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot open");
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
    for (std::size_t i = 0; i < j.at("views").size(); ++i) {
      const json& v = j["views"][i];
      const std::string at = "views[" + std::to_string(i) + "].";
      SessionView sv;
      key = at + "depth";
      sv.depth_file = v.at("depth").get<std::string>();
      sv.depth = cv::imread(dir + "/" + sv.depth_file, cv::IMREAD_UNCHANGED);
      if (sv.depth.empty() || sv.depth.type() != CV_16UC1) throw std::runtime_error("not a 16-bit depth PNG");
      key = at + "intrinsics";
      const json& in = v.at("intrinsics");
      sv.intrinsics = {in.at("width").get<int>(),        in.at("height").get<int>(), in.at("fx").get<double>(),
                       in.at("fy").get<double>(),        in.at("cx").get<double>(),  in.at("cy").get<double>(),
                       in.at("depth_unit").get<double>()};
      if (v.contains("flange_to_base")) {
        key = at + "flange_to_base";
        sv.flange_to_base = from_row_major(v["flange_to_base"].get<std::vector<double>>(), path + ": " + key);
      }
      if (v.contains("tcp_at_hole"))
        for (const auto& [id, p] : v["tcp_at_hole"].items()) {
          key = at + "tcp_at_hole." + id;
          const auto xyz = p.get<std::vector<double>>();
          if (xyz.size() != 3) throw std::runtime_error("expected [x, y, z]");
          sv.tcp_at_hole[id] = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
        }
      if (s.mode == "eye-in-hand" && !sv.flange_to_base) throw std::runtime_error("missing flange_to_base");
      s.views.push_back(std::move(sv));
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + key + ": " + e.what());
  }
  return s;
}

void write_session(const std::string& dir, const Session& s) {
  std::filesystem::create_directories(dir);
  json j{{"mode", s.mode}, {"views", json::array()}};
  for (const SessionView& v : s.views) {
    if (!cv::imwrite(dir + "/" + v.depth_file, v.depth))
      throw std::runtime_error(dir + "/" + v.depth_file + ": cannot write");
    const auto& in = v.intrinsics;
    json jv{{"depth", v.depth_file},
            {"intrinsics",
             {{"width", in.width},
              {"height", in.height},
              {"fx", in.fx},
              {"fy", in.fy},
              {"cx", in.cx},
              {"cy", in.cy},
              {"depth_unit", in.depth_unit}}}};
    if (v.flange_to_base) jv["flange_to_base"] = to_row_major(*v.flange_to_base);
    for (const auto& [id, p] : v.tcp_at_hole) jv["tcp_at_hole"][id] = {p.x(), p.y(), p.z()};
    j["views"].push_back(jv);
  }
  std::ofstream(dir + "/session.json") << j.dump(1) << "\n";
}

}  // namespace hg::calibrate
