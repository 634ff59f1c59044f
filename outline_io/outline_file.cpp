#include "outline_io/outline_file.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

namespace hg::outline_io {

namespace {

using Json = nlohmann::json;

nlohmann::ordered_json arr3(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

bool finite_number(const Json& j) { return j.is_number() && std::isfinite(j.get<double>()); }

// Every error of one file: "NAME: KEY: what".
struct Where {
  const std::string& name;
  ReadError operator()(const std::string& key, const std::string& what) const {
    return ReadError(name + ": " + key + ": " + what);
  }
};

std::array<double, 3> vec3(const Json& j, const std::string& key, const Where& err) {
  if (!j.is_array() || j.size() != 3 || !finite_number(j[0]) || !finite_number(j[1]) || !finite_number(j[2]))
    throw err(key, "expected [x, y, z], three finite numbers");
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

Plane plane_of(const Json& p, const Where& err) {
  if (!p.is_object()) throw err("plane", "expected an object {\"origin\", \"normal\", \"u\", \"v\"}");
  for (const char* k : {"origin", "normal", "u", "v"})
    if (!p.contains(k)) throw err(std::string("plane.") + k, "missing");
  return {vec3(p["origin"], "plane.origin", err), vec3(p["normal"], "plane.normal", err), vec3(p["u"], "plane.u", err),
          vec3(p["v"], "plane.v", err)};
}

OutlineLoop loop_of(const Json& jl, const std::string& key, const Where& err) {
  if (!jl.is_object()) throw err(key, "expected an object {\"hole\", \"points\"}");
  if (!jl.contains("points") || !jl["points"].is_array()) throw err(key + ".points", "missing or not an array");
  OutlineLoop l;
  if (jl.contains("hole")) {
    if (!jl["hole"].is_boolean()) throw err(key + ".hole", "expected true or false");
    l.hole = jl["hole"].get<bool>();
  }
  const Json& pts = jl["points"];
  l.points.reserve(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Json& p = pts[i];
    if (!p.is_array() || p.size() != 2 || !finite_number(p[0]) || !finite_number(p[1]))
      throw err(key + ".points[" + std::to_string(i) + "]", "expected [u, v], two finite numbers");
    l.points.push_back({p[0].get<double>(), p[1].get<double>()});
  }
  return l;
}

}  // namespace

nlohmann::ordered_json outline_file_json(const OutlineFile& f) {
  nlohmann::ordered_json j;
  if (!f.frame.empty()) j["frame"] = f.frame;
  if (f.spacing > 0) j["spacing"] = f.spacing;
  if (f.plane)
    j["plane"] = {{"origin", arr3(f.plane->origin)},
                  {"normal", arr3(f.plane->normal)},
                  {"u", arr3(f.plane->u)},
                  {"v", arr3(f.plane->v)}};
  auto loops = nlohmann::ordered_json::array();
  for (const OutlineLoop& l : f.loops) {
    auto pts = nlohmann::ordered_json::array();
    for (const Vec2& p : l.points) pts.push_back({p.x, p.y});
    loops.push_back({{"hole", l.hole}, {"points", std::move(pts)}});
  }
  j["loops"] = std::move(loops);
  return j;
}

OutlineFile parse_outline_file(std::string_view text, const std::string& name) {
  const Where err{name};
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw ReadError(name + ": byte " + std::to_string(e.byte) + ": not JSON: " + e.what());
  }
  if (!j.is_object()) throw err("(top level)", "expected an object");
  if (!j.contains("loops") || !j["loops"].is_array()) throw err("loops", "missing or not an array");
  OutlineFile f;
  if (j.contains("frame")) {
    if (!j["frame"].is_string()) throw err("frame", "expected a string");
    f.frame = j["frame"].get<std::string>();
  }
  if (j.contains("spacing")) {
    if (!finite_number(j["spacing"]) || !(j["spacing"].get<double>() >= 0))
      throw err("spacing", "expected a number >= 0 (metres)");
    f.spacing = j["spacing"].get<double>();
  }
  if (j.contains("plane")) f.plane = plane_of(j["plane"], err);
  const Json& loops = j["loops"];
  for (std::size_t k = 0; k < loops.size(); ++k)
    f.loops.push_back(loop_of(loops[k], "loops[" + std::to_string(k) + "]", err));
  return f;
}

OutlineFile read_outline_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ReadError(path + ": cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw ReadError(path + ": read error");
  return parse_outline_file(ss.str(), path);
}

}  // namespace hg::outline_io
