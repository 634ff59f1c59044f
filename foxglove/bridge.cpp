#include "bridge.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/log_line_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"
#include "hullgrind/robot_status_t.hpp"
#include "lcm_json.hpp"
#include "outline_io/palette.hpp"

namespace hg::foxglove {

using lcmtools::DecodeError;
using lcmtools::Json;

namespace {

const char* kPoints = "/hg/plate/points";
const char* kOutline = "/hg/outline";
const char* kPath = "/hg/grind_path";
const char* kTf = "/tf";
// The camera's transform has a topic of its own: a viewer opening a recording at some time takes the last
// message of each topic before it, and on /tf that is the robot's TCP, so the camera (and the cloud in its
// frame) would be missing until the next cloud.
const char* kTfCamera = "/tf/camera";
const char* kLog = "/hg/log";

// ---- schemas of the well-known messages (the fields this bridge fills) ----

Json object(std::initializer_list<std::pair<const char*, Json>> props) {
  Json p = Json::object(), req = Json::array();
  for (const auto& [k, v] : props) {
    p[k] = v;
    req.push_back(k);
  }
  return Json{{"type", "object"}, {"properties", p}, {"required", req}};
}
Json number() { return Json{{"type", "number"}}; }
Json integer() { return Json{{"type", "integer"}}; }
Json text() { return Json{{"type", "string"}}; }
Json array_of(Json item) { return Json{{"type", "array"}, {"items", std::move(item)}}; }
// A primitive list this bridge leaves empty: typed all the same, as viewers read no field without a type.
Json unused_list() { return array_of(Json{{"type", "object"}}); }
Json time_schema() { return object({{"sec", integer()}, {"nsec", integer()}}); }
Json vec3() { return object({{"x", number()}, {"y", number()}, {"z", number()}}); }
Json quat() { return object({{"x", number()}, {"y", number()}, {"z", number()}, {"w", number()}}); }
Json pose() { return object({{"position", vec3()}, {"orientation", quat()}}); }
Json color() { return object({{"r", number()}, {"g", number()}, {"b", number()}, {"a", number()}}); }

Json line_schema() {
  return object({{"type", integer()},
                 {"pose", pose()},
                 {"thickness", number()},
                 {"scale_invariant", Json{{"type", "boolean"}}},
                 {"points", array_of(vec3())},
                 {"color", color()},
                 {"colors", array_of(color())},
                 {"indices", array_of(integer())}});
}

Json scene_update_schema() {
  Json entity = object({{"timestamp", time_schema()},
                        {"frame_id", text()},
                        {"id", text()},
                        {"lifetime", time_schema()},
                        {"frame_locked", Json{{"type", "boolean"}}},
                        {"metadata", array_of(object({{"key", text()}, {"value", text()}}))},
                        {"arrows", unused_list()},
                        {"cubes", unused_list()},
                        {"spheres", unused_list()},
                        {"cylinders", unused_list()},
                        {"lines", array_of(line_schema())},
                        {"triangles", unused_list()},
                        {"texts", unused_list()},
                        {"models", unused_list()}});
  Json deletion = object({{"timestamp", time_schema()}, {"type", integer()}, {"id", text()}});
  return object({{"deletions", array_of(deletion)}, {"entities", array_of(entity)}});
}

Json titled(Json s, const std::string& title) {
  s["title"] = title;
  s["$schema"] = "http://json-schema.org/draft-07/schema#";
  return s;
}

// ---- message pieces ----

Json time_json(int64_t utime) {
  int64_t sec = utime >= 0 ? utime / 1000000 : 0;
  int64_t nsec = utime >= 0 ? (utime % 1000000) * 1000 : 0;
  return Json{{"sec", sec}, {"nsec", nsec}};
}
Json vec3_json(const Eigen::Vector3d& v) { return Json{{"x", v.x()}, {"y", v.y()}, {"z", v.z()}}; }
Json quat_json(const Eigen::Quaterniond& q) { return Json{{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}}; }
Json identity_pose() {
  return Json{{"position", vec3_json(Eigen::Vector3d::Zero())},
              {"orientation", quat_json(Eigen::Quaterniond::Identity())}};
}
Json color_json(double r, double g, double b, double a = 1) { return Json{{"r", r}, {"g", g}, {"b", b}, {"a", a}}; }
// One of the product's colours (outline_io/palette.hpp, the station's) as a foxglove.Color.
Json color_json(std::uint32_t rgb) {
  return color_json(((rgb >> 16) & 0xff) / 255.0, ((rgb >> 8) & 0xff) / 255.0, (rgb & 0xff) / 255.0);
}

Json transform_json(int64_t utime, const std::string& parent, const std::string& child, const Eigen::Isometry3d& t) {
  Eigen::Quaterniond q(t.rotation());
  q.normalize();
  return Json{{"timestamp", time_json(utime)},
              {"parent_frame_id", parent},
              {"child_frame_id", child},
              {"translation", vec3_json(t.translation())},
              {"rotation", quat_json(q)}};
}

Json entity_json(int64_t utime, const std::string& frame, const std::string& id, Json lines) {
  return Json{{"timestamp", time_json(utime)},
              {"frame_id", frame},
              {"id", id},
              {"lifetime", Json{{"sec", 0}, {"nsec", 0}}},  // 0: until replaced
              {"frame_locked", false},
              {"metadata", Json::array()},
              {"arrows", Json::array()},
              {"cubes", Json::array()},
              {"spheres", Json::array()},
              {"cylinders", Json::array()},
              {"lines", std::move(lines)},
              {"triangles", Json::array()},
              {"texts", Json::array()},
              {"models", Json::array()}};
}

Json line_json(int type, Json points, Json color, Json colors) {
  return Json{{"type", type},  // foxglove LineType: 0 strip, 1 loop, 2 list
              {"pose", identity_pose()},
              {"thickness", 3},
              {"scale_invariant", true},  // pixels, so a loop stays visible at any zoom
              {"points", std::move(points)},
              {"color", std::move(color)},
              {"colors", std::move(colors)},
              {"indices", Json::array()}};
}

Eigen::Vector3d vec(const double* p) { return {p[0], p[1], p[2]}; }

template <class T>
bool decode_generated(T& msg, const uint8_t* data, std::size_t size) {
  return msg.decode(data, 0, static_cast<int>(size)) == static_cast<int>(size);
}

}  // namespace

std::string well_known_schema(const std::string& name) {
  if (name == "foxglove.PointCloud") {
    Json field = object({{"name", text()}, {"offset", integer()}, {"type", integer()}});
    return titled(object({{"timestamp", time_schema()},
                          {"frame_id", text()},
                          {"pose", pose()},
                          {"point_stride", integer()},
                          {"fields", array_of(field)},
                          {"data", Json{{"type", "string"}, {"contentEncoding", "base64"}}}}),
                  name)
        .dump();
  }
  if (name == "foxglove.Log")
    return titled(object({{"timestamp", time_schema()},
                          {"level", integer()},
                          {"message", text()},
                          {"name", text()},
                          {"file", text()},
                          {"line", integer()}}),
                  name)
        .dump();
  if (name == "foxglove.SceneUpdate") return titled(scene_update_schema(), name).dump();
  if (name == "foxglove.FrameTransform")
    return titled(object({{"timestamp", time_schema()},
                          {"parent_frame_id", text()},
                          {"child_frame_id", text()},
                          {"translation", vec3()},
                          {"rotation", quat()}}),
                  name)
        .dump();
  return "";
}

Bridge::Bridge(lcmtools::Schema schema, BridgeOptions options)
    : schema_(std::move(schema)), opt_(std::move(options)), cloud_(std::make_unique<hullgrind::plate_cloud_t>()) {}

Bridge::~Bridge() = default;

// The largest recycled buffer for a message of a few hundred kB or more (a small one gets a new string).
std::string Bridge::spare_buffer(std::size_t expected) {
  std::string s;
  if (expected >= (256u << 10) && !spare_.empty()) {
    auto it = std::max_element(spare_.begin(), spare_.end(),
                               [](const std::string& a, const std::string& b) { return a.capacity() < b.capacity(); });
    s = std::move(*it);
    spare_.erase(it);
    s.clear();
  }
  s.reserve(expected);
  return s;
}

void Bridge::recycle(std::string&& payload) {
  if (payload.capacity() < (256u << 10)) return;
  spare_.push_back(std::move(payload));
  if (spare_.size() > 4)  // keeps the four largest
    spare_.erase(std::min_element(spare_.begin(), spare_.end(), [](const std::string& a, const std::string& b) {
      return a.capacity() < b.capacity();
    }));
}

int Bridge::add_topic(Topic t, Converted& c) {
  topics_.push_back(std::move(t));
  int id = static_cast<int>(topics_.size()) - 1;
  c.new_topics.push_back(id);
  return id;
}

int Bridge::well_known(const std::string& name, const std::string& schema_name, Converted& c) {
  auto it = well_known_.find(name);
  if (it != well_known_.end()) return it->second;
  int id = add_topic(Topic{name, schema_name, "jsonschema", well_known_schema(schema_name), "json"}, c);
  well_known_[name] = id;
  return id;
}

Converted Bridge::camera_transform(int64_t utime) {
  Converted c;
  if (!opt_.camera_to_base || opt_.camera_to_flange) return c;
  int tf = well_known(kTfCamera, "foxglove.FrameTransform", c);
  c.outputs.push_back({tf, transform_json(utime, opt_.base_frame, opt_.camera_frame, *opt_.camera_to_base).dump()});
  return c;
}

Converted Bridge::convert(const std::string& channel, const uint8_t* data, std::size_t size,
                          const std::function<bool(int)>& wanted, std::string* in_place) {
  Converted c;
  int64_t fp = 0;
  for (std::size_t i = 0; i < 8 && i < size; ++i) fp = static_cast<int64_t>((static_cast<uint64_t>(fp) << 8) | data[i]);
  const lcmtools::Struct* type = size >= 8 ? schema_.find_by_fingerprint(fp) : nullptr;
  ChannelState& st = channels_[channel];
  if (st.topic < 0 || st.fingerprint != fp) {
    if (st.topic >= 0) {  // the channel changed type: its old topic goes
      topics_[st.topic].active = false;
      c.retired_topics.push_back(st.topic);
    }
    st.fingerprint = fp;
    st.topic =
        type ? add_topic(Topic{channel, type->full_name(), "jsonschema", json_schema(schema_, *type).dump(), "json"}, c)
             : add_topic(Topic{channel, "", "", "", "lcm"}, c);
  }
  if (!type) {
    c.unknown_type = true;
    if (!wanted || wanted(st.topic))
      c.outputs.push_back({st.topic, std::string(reinterpret_cast<const char*>(data), size)});
    return c;
  }
  try {
    // Checks the whole message first with the bounded decoder (arrays skipped), so that the generated
    // classes below never see a lying length.
    std::size_t consumed = 0;
    schema_.decode(*type, data, size, consumed, lcmtools::DecodeOptions{false, 0});
    if (consumed != size) throw DecodeError(std::to_string(size - consumed) + " trailing bytes");
    if (in_place) {
      // Room for the text's usual size, and a quarter more for the small messages before the next cloud in
      // the same chunk: the buffer does not move (and fault in new pages) at every cloud.
      std::size_t need = in_place->size() + size * 3 + 64;
      if (in_place->capacity() < need) in_place->reserve(need + need / 4);
      to_json(schema_, *type, data, size, *in_place, opt_.cancel);
      c.outputs.push_back({st.topic, {}, true});
    } else if (!wanted || wanted(st.topic)) {
      std::string json = spare_buffer(size * 3 + 64);
      to_json(schema_, *type, data, size, json, opt_.cancel);
      c.outputs.push_back({st.topic, std::move(json)});
    }
    derive(*type, data, size, wanted, c);
  } catch (const std::exception& e) {
    c.outputs.clear();
    c.error = e.what();
  }
  return c;
}

namespace {

Eigen::Isometry3d pose_of(const double* position, const double* wxyz) {
  Eigen::Quaterniond q(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  if (q.norm() > 0) t.linear() = q.normalized().toRotationMatrix();
  t.translation() = vec(position);
  return t;
}

// x, y, z float32 little endian, every `step`-th point of the plane's (u, v) coordinates.
std::string cloud_bytes(const hullgrind::plate_cloud_t& m, std::size_t step) {
  Eigen::Vector3d o = vec(m.plane_origin), ua = vec(m.plane_u_axis), va = vec(m.plane_v_axis);
  std::string out;
  out.reserve((static_cast<std::size_t>(m.n) / step + 1) * 12);
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.n); i += step) {
    Eigen::Vector3d p = o + double(m.u[i]) * ua + double(m.v[i]) * va;
    float xyz[3] = {float(p.x()), float(p.y()), float(p.z())};
    char b[12];
    std::memcpy(b, xyz, 12);  // the machine is little endian (x86-64, arm64), as PointCloud wants
    out.append(b, 12);
  }
  return out;
}

// Appended to s: a recycled buffer (Bridge::spare_buffer), so that the 3 MB of text of each cloud go into
// pages already touched.
void point_cloud_json(const hullgrind::plate_cloud_t& m, std::size_t max_points, std::string& s) {
  std::size_t n = static_cast<std::size_t>(std::max(0, m.n));
  std::size_t step = max_points == 0 || n <= max_points ? 1 : (n + max_points - 1) / max_points;
  Json fields = Json::array();
  const char* names[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) fields.push_back(Json{{"name", names[i]}, {"offset", 4 * i}, {"type", 7}});  // FLOAT32
  Json head{{"timestamp", time_json(m.header.utime)},
            {"frame_id", m.header.frame_id},
            {"pose", identity_pose()},
            {"point_stride", 12},
            {"fields", fields}};
  std::string bytes = cloud_bytes(m, step);
  s += head.dump();
  s.pop_back();  // '}': the data goes in as text, not through a JSON value
  s += ",\"data\":\"";
  s.reserve(s.size() + bytes.size() / 3 * 4 + 8);
  append_base64(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), s);
  s += "\"}";
}

Json outline_lines(const hullgrind::outline_t& m) {
  Eigen::Vector3d o = vec(m.plane_origin), ua = vec(m.plane_u_axis), va = vec(m.plane_v_axis);
  Json lines = Json::array();
  for (const auto& loop : m.loops) {
    Json pts = Json::array();
    for (int i = 0; i < loop.n; ++i) pts.push_back(vec3_json(o + loop.u[i] * ua + loop.v[i] * va));
    Json col = color_json(loop.hole ? outline_io::palette::kHole : outline_io::palette::kOuter);
    lines.push_back(line_json(1, std::move(pts), std::move(col), Json::array()));
  }
  return lines;
}

// The smoothed edge the tool grinds (grind_path_t.edge, each loop's ring in turn): one line loop per
// outline loop, in the station's colour of the smoothed edge (magenta; the path is coloured by kind).
Json edge_lines(const hullgrind::grind_path_t& m) {
  Json lines = Json::array();
  for (int i = 0; i < m.num_edge_points;) {
    int end = i;
    Json pts = Json::array();
    for (; end < m.num_edge_points && m.edge_loop[end] == m.edge_loop[i]; ++end)
      pts.push_back(vec3_json(vec(m.edge[end].data())));
    lines.push_back(line_json(1, std::move(pts), color_json(outline_io::palette::kEdge), Json::array()));
    i = end;
  }
  return lines;
}

Json path_lines(const hullgrind::grind_path_t& m) {
  Json pts = Json::array(), cols = Json::array();
  for (int i = 1; i < m.n; ++i) {
    Json c = color_json(outline_io::palette::kind_colour(m.kind[i]));
    pts.push_back(vec3_json(vec(m.position[i - 1].data())));
    pts.push_back(vec3_json(vec(m.position[i].data())));
    cols.push_back(c);
    cols.push_back(c);
  }
  Json lines = Json::array();
  lines.push_back(line_json(2, std::move(pts), color_json(1, 1, 1), std::move(cols)));
  return lines;
}

const char* state_name(int s) {
  static const char* names[] = {"ACCEPTED",   "PLANNING", "PLANNED",     "RUNNING",           "DONE",
                                "FAILED",     "ABORTED",  "REFUSED",     "AWAITING_APPROVAL", "APPROVED",
                                "INCOMPLETE", "REJECTED", "NEEDS_RESCAN"};
  return s >= 0 && s < 13 ? names[s] : "UNKNOWN";
}

// A job status as a log line (foxglove.Log): the processes' own words about the job, at the level its
// state deserves (a job that ended without its work done is an error).
std::string log_json(const hullgrind::job_status_t& m) {
  using S = hullgrind::job_status_t;
  int level = 2;                                         // INFO
  if (m.state == S::STATE_AWAITING_APPROVAL) level = 3;  // WARNING: waits for a person
  if (m.state == S::STATE_FAILED || m.state == S::STATE_ABORTED || m.state == S::STATE_REFUSED ||
      m.state == S::STATE_INCOMPLETE || m.state == S::STATE_REJECTED || m.state == S::STATE_NEEDS_RESCAN)
    level = 4;  // ERROR
  char pct[16];
  std::snprintf(pct, sizeof pct, "%.0f%%", 100 * m.progress);
  std::string text =
      "job " + m.job_id + " " + state_name(m.state) + " " + pct + (m.message.empty() ? "" : ": " + m.message);
  return Json{{"timestamp", time_json(m.header.utime)},
              {"level", level},
              {"message", text},
              {"name", m.source},
              {"file", ""},
              {"line", 0}}
      .dump();
}

// A process's own log line (log_line_t) in foxglove.Log's levels (DEBUG 1, INFO 2, WARNING 3, ERROR 4).
std::string log_json(const hullgrind::log_line_t& m) {
  int level = std::clamp(int(m.level), 0, 3) + 1;
  return Json{{"timestamp", time_json(m.header.utime)},
              {"level", level},
              {"message", m.text},
              {"name", m.process},
              {"file", ""},
              {"line", 0}}
      .dump();
}

}  // namespace

void Bridge::derive(const lcmtools::Struct& type, const uint8_t* data, std::size_t size,
                    const std::function<bool(int)>& wanted, Converted& c) {
  auto want = [&](int t) { return !wanted || wanted(t); };
  const std::string& name = type.full_name();
  if (name == "hullgrind.plate_cloud_t") {
    int pts = well_known(kPoints, "foxglove.PointCloud", c);
    std::optional<Eigen::Isometry3d> base_camera;
    hullgrind::plate_cloud_t& m = *cloud_;
    bool need_points = want(pts);
    if (!need_points && !opt_.camera_to_base && !opt_.camera_to_flange) return;
    if (opt_.cancel && opt_.cancel->load()) throw Cancelled();  // decoding a cloud takes milliseconds
    if (!decode_generated(m, data, size)) throw DecodeError("plate_cloud_t refused by its generated class");
    if (need_points) {
      std::size_t points = std::min<std::size_t>(std::max(0, m.n), opt_.max_points ? opt_.max_points : SIZE_MAX);
      c.outputs.push_back({pts, spare_buffer(points * 16 + 1024)});  // 12 bytes a point as base64, the head
      point_cloud_json(m, opt_.max_points, c.outputs.back().payload);
    }
    if (opt_.camera_to_flange && m.flange_valid)
      base_camera = pose_of(m.flange_position, m.flange_orientation) * *opt_.camera_to_flange;
    else if (opt_.camera_to_base)
      base_camera = *opt_.camera_to_base;
    opt_.camera_frame = m.header.frame_id;
    int tf = base_camera ? well_known(kTfCamera, "foxglove.FrameTransform", c) : -1;
    if (base_camera && want(tf))
      c.outputs.push_back(
          {tf, transform_json(m.header.utime, opt_.base_frame, m.header.frame_id, *base_camera).dump()});
  } else if (name == "hullgrind.outline_t") {
    int t = well_known(kOutline, "foxglove.SceneUpdate", c);
    hullgrind::outline_t m;
    if (!want(t)) return;
    if (!decode_generated(m, data, size)) throw DecodeError("outline_t refused by its generated class");
    Json e = entity_json(m.header.utime, m.header.frame_id, "outline", outline_lines(m));
    c.outputs.push_back({t, Json{{"deletions", Json::array()}, {"entities", Json::array({e})}}.dump()});
  } else if (name == "hullgrind.grind_path_t") {
    int t = well_known(kPath, "foxglove.SceneUpdate", c);
    hullgrind::grind_path_t m;
    if (!want(t)) return;
    if (!decode_generated(m, data, size)) throw DecodeError("grind_path_t refused by its generated class");
    std::string frame = m.frame.empty() ? opt_.base_frame : m.frame;
    Json entities = Json::array({entity_json(m.header.utime, frame, "grind_path", path_lines(m)),
                                 entity_json(m.header.utime, frame, "smoothed_edge", edge_lines(m))});
    c.outputs.push_back({t, Json{{"deletions", Json::array()}, {"entities", std::move(entities)}}.dump()});
  } else if (name == "hullgrind.job_status_t") {
    int t = well_known(kLog, "foxglove.Log", c);
    hullgrind::job_status_t m;
    if (!want(t)) return;
    if (!decode_generated(m, data, size)) throw DecodeError("job_status_t refused by its generated class");
    c.outputs.push_back({t, log_json(m)});
  } else if (name == "hullgrind.log_line_t") {
    int t = well_known(kLog, "foxglove.Log", c);
    hullgrind::log_line_t m;
    if (!want(t)) return;
    if (!decode_generated(m, data, size)) throw DecodeError("log_line_t refused by its generated class");
    c.outputs.push_back({t, log_json(m)});
  } else if (name == "hullgrind.robot_status_t") {
    int t = well_known(kTf, "foxglove.FrameTransform", c);
    hullgrind::robot_status_t m;
    if (!want(t)) return;
    if (!decode_generated(m, data, size)) throw DecodeError("robot_status_t refused by its generated class");
    std::string parent = m.header.frame_id.empty() ? opt_.base_frame : m.header.frame_id;
    Eigen::Isometry3d tcp = pose_of(m.tcp_position, m.tcp_orientation);
    c.outputs.push_back({t, transform_json(m.header.utime, parent, opt_.tcp_frame, tcp).dump()});
  }
}

}  // namespace hg::foxglove
