#include "path_planner/io.hpp"

#include "path_file/path_file.hpp"

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
  std::vector<Param> params = {
      cell::cell_param(),
      runtime::quantity_param(quantity::kGrindSpeed, "0.02", "job default; <= the cell's max-speed"),
      runtime::quantity_param(quantity::kTravelSpeed, "0.2", "job default; <= the cell's max-speed"),
      runtime::quantity_param(quantity::kStep, "0.002", "job default"),
      runtime::quantity_param(quantity::kSafeHeight, "0.05", "job default"),
      text_param("direction", "climb", "hg-plan; a job request carries its own", job::direction_names()),
      flag_param("flipped", "plan for the flipped part (hg-plan; a job request carries its own)"),
      Param{"spindle-clockwise", "true", "spindle turns clockwise seen from above (decides what climb means)", false,
            runtime::ParamType::Flag},
      number_param("approach-speed", "0.05",
                   "speed of the vertical approach and retract, m/s (capped by travel-speed; <= the cell's max-speed)",
                   0, inf, open),
      number_param("lead-radius", "0.01", "radius of the lead-in/lead-out arcs, m (smaller in small holes)", 0, inf,
                   open),
      number_param("lead-angle", "1.5707963267948966", "sweep of the lead arcs, rad", 0, inf, open),
      number_param("z-offset", "0", "height of the grind points above the plate's top surface, m"),
      number_param("pixel-pitch", "0",
                   "pixel pitch of the outline, m; 0 (normal): the outline's point spacing, else estimated from its "
                   "loops",
                   0),
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
                   "every edge point must be within the tool radius + this of the grind path, m", 0, inf, open),
      number_param("resample-chord-error", "1e-5", "largest distance of a resampled chord from the offset ring, m", 0,
                   inf, open),
      numbers_param("plane-origin", "0,0,1.19",
                    "plate plane in the camera frame for outline files without one: origin"),
      numbers_param("plane-u", "1,0,0", "... u axis"),
      numbers_param("plane-v", "0,-1,0", "... v axis"),
      numbers_param("plane-normal", "0,0,-1", "... normal (u, v, normal right-handed)"),
      text_param("outline-frame", "",
                 "hg-plan: frame of the outline file's plane: camera (the cell's camera-to-base applied), robot_base "
                 "(the cell's frames.base: none applied); default: the file's \"frame\" (cloud or none: camera)"),
      number_param(
          "outline-max-age", "2.0",
          "hg-path-planner: a job starts on the latest outline if it arrived at most this long ago (s), else on the next",
          0),
      number_param("outline-timeout", "10.0", "hg-path-planner: a job with no outline after this long fails, s", 0, inf,
                   open),
  };
  for (Param& p : moved_planner_keys()) params.push_back(std::move(p));
  return params;
}

ParamLookup lookup_from(const runtime::Params& params) {
  return {std::shared_ptr<const runtime::Params>(std::shared_ptr<void>(), &params)};  // not owned
}

ParamLookup lookup_from(const runtime::Node& node) { return lookup_from(node.params()); }

ParamLookup lookup_from(const std::map<std::string, std::string>& cli, const runtime::Config& config) {
  // The one precedence rule (runtime::Params), over the planner's declarations; shared so the lookup owns it.
  auto params = std::make_shared<runtime::Params>(planner_params());
  params->use_config(config);
  for (const auto& [k, v] : cli) params->set(k, v);
  return {params};
}

namespace {

Vec3 vec3(const runtime::Params& P, const std::string& key) {
  const std::vector<double> v = P.numbers(key);
  if (v.size() != 3) throw P.error(key, "expected 3 numbers");
  return Vec3(v[0], v[1], v[2]);
}

// The job defaults: the tool is the cell's, speeds within the cell's max-speed.
JobParams job_defaults(const runtime::Params& P, const cell::LoadedCell& cell) {
  const cell::Cell& c = cell.cell;
  JobParams d;
  // The tool is the cell's (tool.radius, tool.tilt, in their ranges by the cell's own check): no parameter.
  d.tool_radius = c.tool.radius;
  d.tilt = c.tool.tilt;
  d.grind_speed = P.number("grind-speed");
  d.travel_speed = P.number("travel-speed");
  for (const char* speed : {"grind-speed", "travel-speed", "approach-speed"})
    cell::refuse_above(P, speed, P.number(speed), cell, "max-speed", c.max_speed);
  d.step = P.number("step");
  d.safe_height = P.number("safe-height");
  d.direction = job::direction_from_name(P.text("direction")).value_or(Direction::Climb);  // one of its choices
  d.flipped = P.flag("flipped");
  return d;
}

}  // namespace

std::vector<Param> moved_planner_keys() {
  return cell::moved_to_cell({{"camera-to-base", "calibration.camera-to-base"},
                              {"camera-xyz", "calibration.camera-to-base"},
                              {"camera-rpy", "calibration.camera-to-base"},
                              {"home", "home"},
                              {"workspace-min", "workspace.min"},
                              {"workspace-max", "workspace.max"},
                              {"table-z", "table-z"},
                              {"max-speed", "max-speed"},
                              {"max-accel", "max-accel"},
                              {"tool-radius", "tool.radius"},
                              {"chamfer-angle", "tool.tilt"},
                              {"base-frame", "frames.base"}});
}

PlannerConfig config_from(const ParamLookup& L) { return config_from(L, cell::load_cell(*L.params)); }

PlannerConfig config_from(const ParamLookup& L, const cell::LoadedCell& cell) {
  const runtime::Params& P = *L.params;
  PlannerConfig c;
  c.defaults = job_defaults(P, cell);
  c.spindle_clockwise = P.flag("spindle-clockwise");
  c.approach_speed = P.number("approach-speed");
  c.lead_radius = P.number("lead-radius");
  c.lead_angle = P.number("lead-angle");
  c.z_offset = P.number("z-offset");
  c.smooth.pitch = P.number("pixel-pitch");
  c.smooth.window_pitches = P.number("smooth-window");
  c.smooth.corner_scale_pitches = P.number("corner-scale");
  c.smooth.corner_angle = P.number("corner-angle");
  c.smooth.edge_compensation = P.flag("edge-compensation");
  c.arc_tolerance = P.number("arc-tolerance");
  c.resample_corner_angle = P.number("resample-corner-angle");
  c.coverage_tolerance = P.number("coverage-tolerance");
  c.resample_chord_error = P.number("resample-chord-error");
  c.small_hole = P.text("small-hole") == "skip" ? SmallHolePolicy::Skip : SmallHolePolicy::Fail;
  c.camera_to_base = cell.cell.calibration.camera_to_base;
  if (cell.cell.calibration.mounting == cell::Mounting::EyeInHand)
    c.camera_to_flange = cell.cell.calibration.camera_to_flange;
  c.default_plane = {vec3(P, "plane-origin"), vec3(P, "plane-u"), vec3(P, "plane-v"), vec3(P, "plane-normal")};
  c.base_frame = cell.cell.frames.base;
  c.home = cell.cell.home;
  c.limits = cell::limits_of(cell.cell);
  c.cell_file = cell.file;
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
  if (j.contains("spacing")) {
    if (!j["spacing"].is_number() || !(j["spacing"].get<double>() >= 0))
      throw std::runtime_error("spacing: expected a number >= 0 (metres)");
    in.point_spacing = j["spacing"].get<double>();
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
  } else if (f.used == "camera" && cfg.camera_to_flange) {
    throw ConfigError("the cell " + cfg.cell_file +
                      " is eye-in-hand (calibration.mounting): an outline file holds no flange pose to place a "
                      "camera-frame plane with; give the outline in " +
                      cfg.base_frame + " (--outline-frame " + cfg.base_frame + ")");
  } else if (f.used == "camera") {
    f.camera_to_base = cfg.camera_to_base;
  } else {
    throw ConfigError("outline frame '" + f.used + "' is neither camera nor " + cfg.base_frame +
                      " (the cell's frames.base); give --outline-frame camera or --outline-frame " + cfg.base_frame);
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
  in.point_spacing = std::isfinite(m.point_spacing) && m.point_spacing > 0 ? m.point_spacing : 0;
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

std::vector<hullgrind::edge_stretch_t> unground_stretches(const PlanResult& r) {
  using hullgrind::edge_stretch_t;
  std::vector<edge_stretch_t> out;
  char buf[160];
  for (const LoopCoverage& c : r.coverage) {
    edge_stretch_t s{};
    s.loop_index = std::int16_t(c.loop);
    s.hole = c.hole;
    if (!c.planned) {
      s.length = c.length;
      s.cause = edge_stretch_t::CAUSE_TOO_SMALL;
      s.reason = "not planned: " + c.skipped;
      out.push_back(s);
      continue;
    }
    for (const UnreachedStretch& u : c.unreached) {
      s.start = u.start;
      s.length = u.length;
      s.cause = u.concave ? edge_stretch_t::CAUSE_CORNER : edge_stretch_t::CAUSE_UNREACHED;
      std::snprintf(buf, sizeof buf, "farther than %.1f + %.1f mm from the tool path%s", r.params.tool_radius * 1e3,
                    r.coverage_tolerance * 1e3, u.concave ? ", at a concave corner or bend tighter than the tool" : "");
      s.reason = buf;
      out.push_back(s);
    }
  }
  return out;
}

hullgrind::grind_path_t to_lcm(const PlanResult& r, const std::string& job_id, std::int64_t outline_seq,
                               const std::string& frame, std::int64_t utime, std::int32_t revision) {
  hullgrind::grind_path_t g{};  // every count zero until filled: a message that encodes
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
  g.tilt = r.params.tilt;
  g.flipped = r.params.flipped;
  g.revision = revision;
  for (const LoopCoverage& c : r.coverage) {
    hullgrind::loop_coverage_t lc{};
    lc.loop_index = std::int16_t(c.loop);
    lc.hole = c.hole;
    lc.planned = c.planned;
    lc.edge_length = c.length;
    lc.reached_length = c.planned ? c.length - c.unreached_length : 0;
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.1f mm of its %.1f mm edge not reached", c.unreached_length * 1e3, c.length * 1e3);
    lc.reason = !c.planned ? c.skipped : c.unreached.empty() ? std::string() : std::string(buf);
    g.coverage.push_back(lc);
  }
  g.num_loops = std::int32_t(g.coverage.size());
  g.unreached = unground_stretches(r);
  g.num_unreached = std::int32_t(g.unreached.size());
  for (std::size_t k = 0; k < r.edges.size(); ++k)
    for (const Vec2& p : r.edges[k]) {
      const Vec3 b = r.plate_to_base * Vec3(p.x(), p.y(), 0);
      g.edge.push_back({b.x(), b.y(), b.z()});
      g.edge_loop.push_back(std::int16_t(k));
    }
  g.num_edge_points = std::int32_t(g.edge.size());
  return g;
}

}  // namespace hg::path_planner
