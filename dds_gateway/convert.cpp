#include "dds_gateway/convert.hpp"

#include <cmath>
#include <cstring>
#include <sstream>
#include <utility>

#include "runtime/quantities.hpp"

namespace hg::dds_gateway {

namespace {

// dds_write only reads a sample, so borrowed pointers into const LCM data are never written through.
char* str(const std::string& s) { return const_cast<char*>(s.c_str()); }

template <class Seq, class T>
void borrow(Seq& seq, const std::vector<T>& v) {
  seq._maximum = seq._length = static_cast<uint32_t>(v.size());
  seq._buffer = const_cast<T*>(v.data());
  seq._release = false;
}

hgdds_Header header(const hullgrind::header_t& h) { return {h.seq, h.utime, str(h.frame_id)}; }

template <class Seq, class T>
void own(Seq& seq, std::vector<T>& v) {
  seq._maximum = seq._length = static_cast<uint32_t>(v.size());
  seq._buffer = v.data();
  seq._release = false;
}

void stretches(const std::vector<hullgrind::edge_stretch_t>& from, std::vector<hgdds_EdgeStretch>& to) {
  to.clear();
  for (const auto& e : from) to.push_back({e.loop_index, e.hole, e.start, e.length, e.cause, str(e.reason)});
}

template <std::size_t N>
void copy(double (&to)[N], const double (&from)[N]) {
  std::memcpy(to, from, sizeof to);
}

}  // namespace

void to_dds(const hullgrind::outline_t& m, OutlineSample& out) {
  hgdds_Outline& s = out.s;
  s = {};
  s.header = header(m.header);
  s.cloud_seq = m.cloud_seq;
  copy(s.plane_origin, m.plane_origin);
  copy(s.plane_normal, m.plane_normal);
  copy(s.plane_u_axis, m.plane_u_axis);
  copy(s.plane_v_axis, m.plane_v_axis);
  s.thickness = m.thickness;
  s.status = m.status;
  s.error_text = str(m.error_text);
  s.alpha_radius = m.alpha_radius;
  out.loops.resize(m.loops.size());
  for (std::size_t i = 0; i < m.loops.size(); ++i) {
    const hullgrind::outline_loop_t& l = m.loops[i];
    hgdds_OutlineLoop& d = out.loops[i];
    d.hole = l.hole;
    borrow(d.u, l.u);
    borrow(d.v, l.v);
    d.area = l.area;
    d.perimeter = l.perimeter;
  }
  s.loops._maximum = s.loops._length = static_cast<uint32_t>(out.loops.size());
  s.loops._buffer = out.loops.data();
  s.loops._release = false;
  s.points_read = m.points_read;
  s.points_used = m.points_used;
  s.duplicates_merged = m.duplicates_merged;
  s.mode = str(m.mode);
  s.order = str(m.order);
  s.triangles = m.triangles;
  s.search_cost = m.search_cost;
  s.time_triangulate = m.time_triangulate;
  s.time_alpha = m.time_alpha;
  s.time_loops = m.time_loops;
  s.compute_time = m.compute_time;
}

void to_dds(const hullgrind::grind_path_t& m, GrindPathSample& out) {
  hgdds_GrindPath& s = out.s;
  s = {};
  s.header = header(m.header);
  s.job_id = str(m.job_id);
  s.outline_seq = m.outline_seq;
  s.frame = str(m.frame);
  out.position.clear();
  out.orientation.clear();
  for (const auto& p : m.position) out.position.insert(out.position.end(), p.begin(), p.end());
  for (const auto& q : m.orientation) out.orientation.insert(out.orientation.end(), q.begin(), q.end());
  borrow(s.position, out.position);
  borrow(s.orientation, out.orientation);
  borrow(s.speed, m.speed);
  borrow(s.kind, m.kind);
  borrow(s.loop_index, m.loop_index);
  s.tool_radius = m.tool_radius;
  s.tilt = m.tilt;
  s.flipped = m.flipped;
  s.revision = m.revision;
  out.coverage.clear();
  for (const auto& c : m.coverage)
    out.coverage.push_back({c.loop_index, c.hole, c.planned, c.edge_length, c.reached_length, str(c.reason)});
  stretches(m.unreached, out.unreached);
  own(s.coverage, out.coverage);
  own(s.unreached, out.unreached);
}

hgdds_PartPose to_dds(const hullgrind::part_pose_t& m) {
  hgdds_PartPose s{};
  s.header = header(m.header);
  s.cloud_seq = m.cloud_seq;
  s.part_index = m.part_index;
  s.num_parts = m.num_parts;
  copy(s.centroid_uv, m.centroid_uv);
  copy(s.centroid_xyz, m.centroid_xyz);
  s.principal_axis_angle = m.principal_axis_angle;
  s.area = m.area;
  copy(s.bbox_min_uv, m.bbox_min_uv);
  copy(s.bbox_max_uv, m.bbox_max_uv);
  copy(s.obb_size, m.obb_size);
  return s;
}

void to_dds(const hullgrind::job_status_t& m, JobStatusSample& out) {
  hgdds_JobStatus& s = out.s;
  s = {};
  s.header = header(m.header);
  s.job_id = str(m.job_id);
  s.part_id = str(m.part_id);
  s.source = str(m.source);
  s.state = m.state;
  s.progress = m.progress;
  s.message = str(m.message);
  s.answer = m.answer;
  s.plan_revision = m.plan_revision;
  s.actor = str(m.actor);
  borrow(s.excluded_loops, m.excluded_loops);
  stretches(m.unground, out.unground);
  own(s.unground, out.unground);
}

hgdds_RobotStatus to_dds(const hullgrind::robot_status_t& m) {
  hgdds_RobotStatus s{};
  s.header = header(m.header);
  s.mode = m.mode;
  copy(s.tcp_position, m.tcp_position);
  copy(s.tcp_orientation, m.tcp_orientation);
  s.job_id = str(m.job_id);
  s.path_index = m.path_index;
  s.fault_code = m.fault_code;
  s.fault_text = str(m.fault_text);
  return s;
}

hgdds_Health to_dds(const hullgrind::heartbeat_t& m) {
  hgdds_Health s{};
  s.header = header(m.header);
  s.process = str(m.process);
  s.pid = m.pid;
  s.state = m.state;
  s.state_text = str(m.state_text);
  s.uptime = m.uptime;
  s.received = m.received;
  s.published = m.published;
  s.dropped = m.dropped;
  s.decode_errors = m.decode_errors;
  s.last_latency = m.last_latency;
  return s;
}

hullgrind::job_request_t to_lcm(const hgdds_JobRequest& r) {
  hullgrind::job_request_t m{};
  m.header.seq = 0;
  m.header.utime = r.header.utime;
  m.header.frame_id = r.header.frame_id ? r.header.frame_id : "";
  m.job_id = r.job_id ? r.job_id : "";
  m.part_id = r.part_id ? r.part_id : "";
  m.action = r.action;
  quantity::for_each_job_quantity([](const quantity::Quantity&, double& to, double from) { to = from; }, m, r);
  m.direction = r.direction;
  m.flipped = r.flipped;
  m.actor = r.actor ? r.actor : "";
  m.plan_revision = r.plan_revision;
  m.excluded_loops.assign(r.excluded_loops._buffer, r.excluded_loops._buffer + r.excluded_loops._length);
  m.num_excluded = std::int32_t(m.excluded_loops.size());
  return m;
}

std::string printable(const char* s, std::size_t max) {
  std::string out;
  if (!s) return out;
  for (; *s && out.size() < max; ++s) {
    unsigned char c = static_cast<unsigned char>(*s);
    out += (c >= 0x20 && c < 0x7f) ? char(c) : '?';
  }
  return out;
}

namespace {

bool id_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' ||
         c == ':' || c == '-';
}

// "" if v is 0 (the default) or within the quantity's range; else why not.
std::string check_quantity(const quantity::Quantity& q, double v) {
  if (!std::isfinite(v)) return std::string(q.name) + " is not a finite number";
  if (v == 0) return "";
  const std::string why = quantity::out_of_range(q, v);
  return why.empty() ? why : why + " (0 = default)";
}

}  // namespace

std::string check_job_request(const hgdds_JobRequest& r, const JobLimits& limits) {
  const char* id = r.job_id ? r.job_id : "";
  std::size_t id_len = std::strlen(id);
  if (id_len == 0) return "job_id is empty";
  if (id_len > limits.max_job_id)
    return "job_id has " + std::to_string(id_len) + " characters, more than " + std::to_string(limits.max_job_id);
  for (std::size_t i = 0; i < id_len; ++i)
    if (!id_char(id[i]))
      return "job_id has a character other than letters, digits and . _ : - at position " + std::to_string(i);
  const char* part = r.part_id ? r.part_id : "";
  std::size_t part_len = std::strlen(part);
  if (part_len > limits.max_part_id)
    return "part_id has " + std::to_string(part_len) + " bytes, more than " + std::to_string(limits.max_part_id);
  for (std::size_t i = 0; i < part_len; ++i) {
    unsigned char c = static_cast<unsigned char>(part[i]);
    if (c < 0x20 || c == 0x7f) return "part_id has a control character at position " + std::to_string(i);
  }
  if (r.action < hullgrind::job_request_t::ACTION_START || r.action > hullgrind::job_request_t::ACTION_QUERY)
    return "action " + std::to_string(int(r.action)) +
           " is not START (0), ABORT (1), RESET (2), APPROVE (3), REJECT (4), REPLAN (5) or QUERY (6)";
  const char* actor = r.actor ? r.actor : "";
  if (std::strlen(actor) > limits.max_part_id)
    return "actor has " + std::to_string(std::strlen(actor)) + " bytes, more than " +
           std::to_string(limits.max_part_id);
  for (std::size_t i = 0; actor[i]; ++i)
    if (static_cast<unsigned char>(actor[i]) < 0x20 || actor[i] == 0x7f)
      return "actor has a control character at position " + std::to_string(i);
  if (r.excluded_loops._length > 4096) return "more than 4096 excluded loops";
  if (r.excluded_loops._length > 0 && !r.excluded_loops._buffer) return "excluded_loops has no data";
  for (std::uint32_t i = 0; i < r.excluded_loops._length; ++i)
    if (r.excluded_loops._buffer[i] < 0) return "excluded loop " + std::to_string(i) + " is negative";
  if (!job::direction_from_wire(r.direction))
    return "direction " + std::to_string(int(r.direction)) + " is not CLIMB (0) or CONVENTIONAL (1)";
  std::string why;
  quantity::for_each_job_quantity(
      [&why](const quantity::Quantity& q, double v) {
        if (why.empty()) why = check_quantity(q, v);
      },
      r);
  return why;
}

}  // namespace hg::dds_gateway
