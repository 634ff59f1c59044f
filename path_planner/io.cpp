#include "path_planner/io.hpp"

#include "runtime/path_file.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace hg::path_planner {

using runtime::ConfigError;
using runtime::Param;

std::vector<Param> planner_params() {
  using runtime::flag_param;
  using runtime::number_param;
  using runtime::numbers_param;
  using runtime::text_param;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const bool open = true;  // the range's lower end is excluded: the value must be > min
  return {
      number_param("tool-radius", "0.01", "effective tool radius, m (job default)", 0, inf, open),
      number_param("chamfer-angle", "0.7853981633974483",
                   "tool tilt toward the edge normal, rad (job default; 45 deg; at most 80 deg)", 0,
                   1.3962634015954636),
      number_param("grind-speed", "0.02", "TCP speed along the edge, m/s (job default)", 0, inf, open),
      number_param("travel-speed", "0.2", "air-move speed, m/s (job default)", 0, inf, open),
      number_param("step", "0.002", "resampling step along the path, m (job default)", 0, inf, open),
      number_param("safe-height", "0.05", "approach/retract height above the plate, m (job default)", 0, inf, open),
      text_param("direction", "climb", "hg-plan; a job request carries its own", {"climb", "conventional"}),
      flag_param("flipped", "plan for the flipped part (hg-plan; a job request carries its own)"),
      Param{"spindle-clockwise", "true", "spindle turns clockwise seen from above (decides what climb means)", false,
            runtime::ParamType::Flag},
      number_param("approach-speed", "0.05", "speed of the vertical approach and retract, m/s (capped by travel-speed)",
                   0, inf, open),
      number_param("lead-radius", "0.01", "radius of the lead-in/lead-out arcs, m (smaller in small holes)", 0, inf,
                   open),
      number_param("lead-angle", "1.5707963267948966", "sweep of the lead arcs, rad", 0, inf, open),
      number_param("z-offset", "0", "height of the grind points above the plate's top surface, m"),
      number_param("pixel-pitch", "0", "pixel pitch of the outline, m; 0: estimated from the loops' staircase", 0),
      number_param("smooth-window", "4", "residual windows of the smoothing fits are 2x this many vertices", 0, inf,
                   open),
      number_param(
          "corner-scale", "8",
          "length of the corner detector's line fits, in pixel pitches (at least 60 noise levels of a window mean)", 0,
          inf, open),
      number_param("corner-angle", "0.5235987755982988", "smallest turn treated as a corner, rad (30 deg)", 0,
                   3.141592653589793),
      Param{"edge-compensation", "true", "move loops from the outermost pixel centres to the edge (half a pitch)",
            false, runtime::ParamType::Flag},
      number_param("arc-tolerance", "1e-5", "Clipper round-join tolerance, m", 0, inf, open),
      number_param("resample-corner-angle", "0.17453292519943295", "turn kept as a waypoint when resampling, rad", 0,
                   3.141592653589793),
      text_param("small-hole", "fail",
                 "a hole too small for the tool, or edge out of its reach: fail (job FAILED), skip (planned, warning)",
                 {"fail", "skip"}),
      number_param("coverage-tolerance", "0.0002",
                   "every edge point must be within tool-radius + this of the grind path, m", 0, inf, open),
      number_param("resample-chord-error", "1e-5", "largest distance of a resampled chord from the offset ring, m", 0,
                   inf, open),
      numbers_param("camera-to-base", "",
                    "hand-eye calibration as 16 numbers, row-major 4x4; overrides camera-xyz/rpy"),
      numbers_param("camera-xyz", "0.5,0,1.2", "camera origin in the robot base frame, m"),
      numbers_param("camera-rpy", "3.141592653589793,0,0", "camera roll, pitch, yaw in the base frame, rad (Rz Ry Rx)"),
      numbers_param("plane-origin", "0,0,1.19",
                    "plate plane in the camera frame for outline files without one: origin"),
      numbers_param("plane-u", "1,0,0", "... u axis"),
      numbers_param("plane-v", "0,-1,0", "... v axis"),
      numbers_param("plane-normal", "0,0,-1", "... normal (u, v, normal right-handed)"),
      text_param("base-frame", "robot_base", "name of the robot base frame in the path"),
      text_param("outline-frame", "",
                 "hg-plan: frame of the outline file's plane: camera (camera-to-base applied), robot_base "
                 "(the base-frame: none applied); default: the file's \"frame\" (cloud or none: camera)"),
      numbers_param("home", "0.5,0,0.3",
                    "robot position (base frame) used as the start reference until HG_ROBOT_STATUS is heard"),
      numbers_param("workspace-min", "-1,-1,0", "workspace box, base frame, m: lower corner"),
      numbers_param("workspace-max", "1.5,1,1", "workspace box, base frame, m: upper corner"),
      number_param("table-z", "0", "table top height in the base frame; every waypoint must be above it, m"),
      number_param("max-speed", "0.5", "largest TCP speed allowed, m/s", 0, inf, open),
      number_param("max-accel", "2.0",
                   "largest acceleration a corner may demand (v^2/r), m/s^2; = the robot bridge's max-accel", 0, inf,
                   open),
      number_param(
          "outline-max-age", "2.0",
          "hg-path-planner: a job starts on the latest outline if it arrived at most this long ago (s), else on the next",
          0),
      number_param("outline-timeout", "10.0", "hg-path-planner: a job with no outline after this long fails, s", 0, inf,
                   open),
  };
}

ParamLookup lookup_from(const runtime::Params& params) {
  return {[&params](const std::string& k) { return params.text(k); },
          [&params](const std::string& k) { return params.numbers(k); }};
}

ParamLookup lookup_from(const runtime::Node& node) { return lookup_from(node.params()); }

ParamLookup lookup_from(const std::map<std::string, std::string>& cli, const runtime::Config& config) {
  // The one precedence rule (runtime::Params), over the planner's declarations; shared so the lookup owns it.
  auto params = std::make_shared<runtime::Params>(planner_params());
  params->use_config(config);
  for (const auto& [k, v] : cli) params->set(k, v);
  return {[params](const std::string& k) { return params->text(k); },
          [params](const std::string& k) { return params->numbers(k); }};
}

namespace {

double num(const ParamLookup& L, const std::string& key) {
  const std::string v = L.text(key);
  char* end = nullptr;
  const double d = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !std::isfinite(d))
    throw ConfigError("parameter '" + key + "': '" + v + "' is not a number");
  return d;
}
bool boolean(const ParamLookup& L, const std::string& key) {
  const std::string v = L.text(key);
  if (v == "true" || v == "1") return true;
  if (v == "false" || v == "0" || v.empty()) return false;
  throw ConfigError("parameter '" + key + "': '" + v + "' is not true or false");
}
Vec3 vec3(const ParamLookup& L, const std::string& key) {
  const std::vector<double> v = L.list(key);
  if (v.size() != 3) throw ConfigError("parameter '" + key + "': expected 3 numbers");
  return Vec3(v[0], v[1], v[2]);
}

}  // namespace

PlannerConfig config_from(const ParamLookup& L) {
  PlannerConfig c;
  JobParams& d = c.defaults;
  d.tool_radius = num(L, "tool-radius");
  d.chamfer_angle = num(L, "chamfer-angle");
  d.grind_speed = num(L, "grind-speed");
  d.travel_speed = num(L, "travel-speed");
  d.step = num(L, "step");
  d.safe_height = num(L, "safe-height");
  const std::string dir = L.text("direction");
  if (dir == "climb") d.direction = Direction::Climb;
  else if (dir == "conventional")
    d.direction = Direction::Conventional;
  else
    throw ConfigError("parameter 'direction': '" + dir + "' is not climb or conventional");
  d.flipped = boolean(L, "flipped");
  JobParams checked;
  if (std::string why = resolve_params(d, d, checked); !why.empty()) throw ConfigError("parameters: " + why);
  c.spindle_clockwise = boolean(L, "spindle-clockwise");
  c.approach_speed = num(L, "approach-speed");
  c.lead_radius = num(L, "lead-radius");
  c.lead_angle = num(L, "lead-angle");
  c.z_offset = num(L, "z-offset");
  c.smooth.pitch = num(L, "pixel-pitch");
  c.smooth.window_pitches = num(L, "smooth-window");
  c.smooth.corner_scale_pitches = num(L, "corner-scale");
  c.smooth.corner_angle = num(L, "corner-angle");
  c.smooth.edge_compensation = boolean(L, "edge-compensation");
  c.arc_tolerance = num(L, "arc-tolerance");
  c.resample_corner_angle = num(L, "resample-corner-angle");
  c.coverage_tolerance = num(L, "coverage-tolerance");
  c.resample_chord_error = num(L, "resample-chord-error");
  if (!(c.coverage_tolerance > 0) || !(c.resample_chord_error > 0))
    throw ConfigError("coverage-tolerance and resample-chord-error must be > 0");
  if (!(c.approach_speed > 0) || !(c.lead_radius > 0) || !(c.lead_angle > 0) || !(c.arc_tolerance > 0) ||
      !(c.smooth.window_pitches > 0) || !(c.smooth.corner_scale_pitches > 0))
    throw ConfigError(
        "approach-speed, lead-radius, lead-angle, arc-tolerance, smooth-window and corner-scale must be > 0");
  const std::string sh = L.text("small-hole");
  if (sh == "fail") c.small_hole = SmallHolePolicy::Fail;
  else if (sh == "skip")
    c.small_hole = SmallHolePolicy::Skip;
  else
    throw ConfigError("parameter 'small-hole': '" + sh + "' is not fail or skip");
  if (!L.list("camera-to-base").empty()) {
    const std::vector<double> m = L.list("camera-to-base");
    if (m.size() != 16) throw ConfigError("parameter 'camera-to-base': expected 16 numbers (row-major 4x4)");
    Eigen::Matrix4d M;
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k) M(r, k) = m[r * 4 + k];
    const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
    if ((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0 ||
        M.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
      throw ConfigError("parameter 'camera-to-base': not a rigid transform");
    c.camera_to_base.matrix() = M;
  } else {
    c.camera_to_base = pose_from_xyz_rpy(vec3(L, "camera-xyz"), vec3(L, "camera-rpy"));
  }
  c.default_plane = {vec3(L, "plane-origin"), vec3(L, "plane-u"), vec3(L, "plane-v"), vec3(L, "plane-normal")};
  c.base_frame = L.text("base-frame");
  c.home = vec3(L, "home");
  c.limits.workspace_min = vec3(L, "workspace-min");
  c.limits.workspace_max = vec3(L, "workspace-max");
  c.limits.table_z = num(L, "table-z");
  c.limits.max_speed = num(L, "max-speed");
  c.limits.max_accel = num(L, "max-accel");
  if (!(c.limits.max_speed > 0) || !(c.limits.max_accel > 0)) throw ConfigError("max-speed and max-accel must be > 0");
  return c;
}

OutlineInput read_outline_json(const std::string& text, const Plane& default_plane) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error("not JSON (byte " + std::to_string(e.byte) + "): " + e.what());
  }
  OutlineInput in;
  in.plane = default_plane;
  if (!j.is_object() || !j.contains("loops") || !j["loops"].is_array())
    throw std::runtime_error("no \"loops\" array at the top level");
  auto vec = [](const nlohmann::json& a, const std::string& where) {
    if (!a.is_array() || a.size() != 3 || !a[0].is_number() || !a[1].is_number() || !a[2].is_number())
      throw std::runtime_error(where + ": expected [x, y, z] numbers");
    return Vec3(a[0].get<double>(), a[1].get<double>(), a[2].get<double>());
  };
  if (j.contains("frame")) {
    if (!j["frame"].is_string()) throw std::runtime_error("frame: expected a string");
    in.frame = j["frame"].get<std::string>();
  }
  if (j.contains("plane")) {
    const auto& p = j["plane"];
    if (!p.is_object()) throw std::runtime_error("plane: expected an object");
    for (const char* k : {"origin", "normal", "u", "v"})
      if (!p.contains(k)) throw std::runtime_error(std::string("plane: no \"") + k + "\"");
    in.plane = {vec(p["origin"], "plane.origin"), vec(p["u"], "plane.u"), vec(p["v"], "plane.v"),
                vec(p["normal"], "plane.normal")};
    in.plane_given = true;
  }
  const auto& loops = j["loops"];
  for (std::size_t k = 0; k < loops.size(); ++k) {
    const auto& jl = loops[k];
    const std::string where = "loops[" + std::to_string(k) + "]";
    if (!jl.is_object() || !jl.contains("points") || !jl["points"].is_array())
      throw std::runtime_error(where + ": no \"points\" array");
    Loop l;
    if (jl.contains("hole")) {
      if (!jl["hole"].is_boolean()) throw std::runtime_error(where + ".hole: expected true or false");
      l.hole = jl["hole"].get<bool>();
    }
    const auto& pts = jl["points"];
    l.points.reserve(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const auto& p = pts[i];
      if (!p.is_array() || p.size() < 2 || !p[0].is_number() || !p[1].is_number())
        throw std::runtime_error(where + ".points[" + std::to_string(i) + "]: expected [x, y] numbers");
      l.points.emplace_back(p[0].get<double>(), p[1].get<double>());
    }
    in.loops.push_back(std::move(l));
  }
  return in;
}

OutlineFrame resolve_outline_frame(const std::string& file_frame, const std::string& chosen, const PlannerConfig& cfg) {
  OutlineFrame f;
  f.declared = file_frame.empty() ? "(none)" : file_frame;
  f.used = chosen.empty() ? file_frame : chosen;
  if (f.used.empty() || f.used == "cloud") {
    f.used = "camera";
    f.note = "an outline in its cloud's own coordinates is taken as the camera's view; give --outline-frame " +
             cfg.base_frame + " if the cloud is in robot base coordinates";
  }
  if (f.used == cfg.base_frame) {
    f.camera_to_base = Eigen::Isometry3d::Identity();
  } else if (f.used == "camera") {
    f.camera_to_base = cfg.camera_to_base;
  } else {
    throw ConfigError("outline frame '" + f.used + "' is neither camera nor " + cfg.base_frame +
                      " (the base-frame); give --outline-frame camera or --outline-frame " + cfg.base_frame);
  }
  return f;
}

std::string matrix_text(const Eigen::Isometry3d& T) {
  std::string s = "[";
  char buf[40];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      std::snprintf(buf, sizeof buf, "%.6g%s", std::abs(T.matrix()(r, c)) < 1e-12 ? 0.0 : T.matrix()(r, c),
                    c < 3 ? " " : (r < 3 ? "; " : "]"));
      s += buf;
    }
  return s;
}

const char* kind_name(std::int8_t kind) { return path_file::kind_name(kind); }

nlohmann::ordered_json path_json(const std::string& job_id, const std::string& frame, const PlanResult& r,
                                 std::int64_t outline_seq) {
  nlohmann::ordered_json j = path_file::to_json(to_lcm(r, job_id, outline_seq, frame, 0));
  j["coverage"] = coverage_json(r);
  return j;
}

nlohmann::ordered_json coverage_json(const PlanResult& r) {
  nlohmann::ordered_json c;
  c["tolerance"] = r.coverage_tolerance;
  c["unreached_length"] = r.unreached_length;
  auto loops = nlohmann::ordered_json::array();
  for (const LoopCoverage& l : r.coverage) {
    nlohmann::ordered_json jl;
    jl["loop"] = l.loop;
    jl["hole"] = l.hole;
    jl["length"] = l.length;
    jl["reached_fraction"] = l.reached_fraction();
    auto stretches = nlohmann::ordered_json::array();
    for (const UnreachedStretch& s : l.unreached) {
      nlohmann::ordered_json js;
      js["start"] = s.start;
      js["length"] = s.length;
      js["concave"] = s.concave;
      auto pts = nlohmann::ordered_json::array();
      for (const Vec2& p : s.points) {
        const Vec3 b = r.plate_to_base * Vec3(p.x(), p.y(), 0);
        pts.push_back({b.x(), b.y(), b.z()});
      }
      js["points"] = std::move(pts);
      stretches.push_back(std::move(js));
    }
    jl["unreached"] = std::move(stretches);
    loops.push_back(std::move(jl));
  }
  c["loops"] = std::move(loops);
  return c;
}

OutlineInput from_lcm(const hullgrind::outline_t& m) {
  OutlineInput in;
  in.seq = m.header.seq;
  in.plane = {Vec3(m.plane_origin[0], m.plane_origin[1], m.plane_origin[2]),
              Vec3(m.plane_u_axis[0], m.plane_u_axis[1], m.plane_u_axis[2]),
              Vec3(m.plane_v_axis[0], m.plane_v_axis[1], m.plane_v_axis[2]),
              Vec3(m.plane_normal[0], m.plane_normal[1], m.plane_normal[2])};
  in.loops.reserve(m.loops.size());
  for (const auto& l : m.loops) {
    Loop loop;
    loop.hole = l.hole;
    const std::size_t n = std::min(l.u.size(), l.v.size());
    loop.points.reserve(n);
    for (std::size_t i = 0; i < n; ++i) loop.points.emplace_back(l.u[i], l.v[i]);
    in.loops.push_back(std::move(loop));
  }
  return in;
}

hullgrind::grind_path_t to_lcm(const PlanResult& r, const std::string& job_id, std::int64_t outline_seq,
                               const std::string& frame, std::int64_t utime) {
  hullgrind::grind_path_t g;
  g.header.utime = utime;
  g.header.frame_id = frame;
  g.job_id = job_id;
  g.outline_seq = outline_seq;
  g.frame = frame;
  g.n = std::int32_t(r.path.size());
  g.position.resize(r.path.size());
  g.orientation.resize(r.path.size());
  g.speed.resize(r.path.size());
  g.kind.resize(r.path.size());
  g.loop_index.resize(r.path.size());
  for (std::size_t i = 0; i < r.path.size(); ++i) {
    const Waypoint& w = r.path[i];
    g.position[i] = {w.position.x(), w.position.y(), w.position.z()};
    g.orientation[i] = {w.orientation.w(), w.orientation.x(), w.orientation.y(), w.orientation.z()};
    g.speed[i] = w.speed;
    g.kind[i] = w.kind;
    g.loop_index[i] = w.loop;
  }
  g.tool_radius = r.params.tool_radius;
  g.tilt = r.params.chamfer_angle;
  g.flipped = r.params.flipped;
  return g;
}

}  // namespace hg::path_planner
