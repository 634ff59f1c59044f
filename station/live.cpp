#include "station/live.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace hg::station {

namespace {

using hullgrind::job_status_t;

constexpr std::size_t kKeptClouds = 3, kKeptOutlines = 8, kStatusRows = 200;

Eigen::Vector3d vec3(const double* v) { return {v[0], v[1], v[2]}; }

void put_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xff);
}

void put_i64(std::string& s, std::int64_t v) {
  const auto u = static_cast<std::uint64_t>(v);
  for (int i = 0; i < 8; ++i) s += static_cast<char>((u >> (8 * i)) & 0xff);
}

void put_f32(std::string& s, float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, 4);
  put_u32(s, bits);
}

Json stretch_json(const hullgrind::edge_stretch_t& s) {
  return {{"loop_index", s.loop_index},   {"hole", s.hole},    {"start", s.start}, {"length", s.length},
          {"cause", cause_name(s.cause)}, {"reason", s.reason}};
}

// The points of a loop (closed polyline, xyz flat) from arc length `start` over `length`.
Json stretch_polyline(const Json& xyz, double start, double length) {
  const std::size_t n = xyz.size() / 3;
  Json out = Json::array();
  if (n < 2 || !(length > 0)) return out;
  auto p = [&](std::size_t i) {
    i %= n;
    return Eigen::Vector3d(xyz[3 * i].get<double>(), xyz[3 * i + 1].get<double>(), xyz[3 * i + 2].get<double>());
  };
  double perimeter = 0;
  for (std::size_t i = 0; i < n; ++i) perimeter += (p(i + 1) - p(i)).norm();
  if (!(perimeter > 0)) return out;
  start = std::fmod(std::max(0.0, start), perimeter);
  const double end = start + std::min(length, perimeter);
  double s = 0;
  for (std::size_t k = 0; k < 2 * n && s < end; ++k) {
    const Eigen::Vector3d a = p(k), b = p(k + 1);
    const double seg = (b - a).norm();
    if (s + seg >= start && seg > 0) {
      const double t0 = std::max(0.0, (start - s) / seg), t1 = std::min(1.0, (end - s) / seg);
      for (double t : {t0, t1}) {
        const Eigen::Vector3d q = a + t * (b - a);
        out.insert(out.end(), {q.x(), q.y(), q.z()});
      }
    }
    s += seg;
  }
  return out;
}

// The smoothed edge of a plan, one entry per run of points of one loop (edge_loop), base frame.
Json edge_json(const hullgrind::grind_path_t& p) {
  Json out = Json::array();
  for (std::size_t i = 0; i < p.edge.size() && i < p.edge_loop.size(); ++i) {
    if (out.empty() || out.back()["loop_index"] != p.edge_loop[i])
      out.push_back({{"loop_index", p.edge_loop[i]}, {"xyz", Json::array()}});
    out.back()["xyz"].insert(out.back()["xyz"].end(), {p.edge[i][0], p.edge[i][1], p.edge[i][2]});
  }
  return out;
}

// The closed polyline an unreached stretch of loop `loop` lies on: the plan's smoothed edge of that loop (the
// stretch's arc length is measured along it), else the outline's loop.
const Json* stretch_ring(const Json& edge, const Json* outline, int loop) {
  for (const Json& e : edge)
    if (e["loop_index"] == loop) return &e["xyz"];
  if (outline && loop >= 0 && std::size_t(loop) < (*outline)["loops"].size()) return &(*outline)["loops"][loop]["xyz"];
  return nullptr;
}

}  // namespace

std::optional<Eigen::Isometry3d> capture_to_base(const LiveOptions& options, bool flange_valid, const double* position,
                                                 const double* orientation, std::string& why) {
  if (!options.camera_to_flange) return options.camera_to_base;
  if (!flange_valid) {
    why = "eye-in-hand cell: the capture carries no flange pose, so the plate cannot be placed";
    return std::nullopt;
  }
  const Eigen::Vector3d t = vec3(position);
  const Eigen::Quaterniond q(orientation[0], orientation[1], orientation[2], orientation[3]);
  if (!t.allFinite() || !q.coeffs().allFinite() || std::abs(q.norm() - 1) > 1e-6) {
    why = "eye-in-hand cell: the capture's flange pose is not a finite position and unit quaternion";
    return std::nullopt;
  }
  Eigen::Isometry3d base_from_flange = Eigen::Isometry3d::Identity();
  base_from_flange.linear() = q.toRotationMatrix();
  base_from_flange.translation() = t;
  return base_from_flange * *options.camera_to_flange;
}

std::string state_name(int state) {
  static const char* names[] = {"ACCEPTED",   "PLANNING", "PLANNED",     "RUNNING",           "DONE",
                                "FAILED",     "ABORTED",  "REFUSED",     "AWAITING_APPROVAL", "APPROVED",
                                "INCOMPLETE", "REJECTED", "NEEDS_RESCAN"};
  if (state >= 0 && state < 13) return names[state];
  return std::to_string(state);
}

// A job's state on the page: REQUESTED while only this station's START is known of it.
std::string LiveState::shown_state(const JobLive& j) {
  return j.state < 0 && j.requested ? "REQUESTED" : state_name(j.state);
}

bool state_terminal(int state) {
  switch (state) {
    case job_status_t::STATE_DONE:
    case job_status_t::STATE_FAILED:
    case job_status_t::STATE_ABORTED:
    case job_status_t::STATE_REFUSED:
    case job_status_t::STATE_INCOMPLETE:
    case job_status_t::STATE_REJECTED:
    case job_status_t::STATE_NEEDS_RESCAN: return true;
    default: return false;
  }
}

std::string cause_name(int cause) {
  static const char* names[] = {"UNREACHED", "TOO_SMALL", "CORNER", "EXCLUDED", "NOT_RUN"};
  if (cause >= 0 && cause < 5) return names[cause];
  return std::to_string(cause);
}

std::string cloud_frame(const hullgrind::plate_cloud_t& cloud, const Eigen::Isometry3d& camera_to_base,
                        std::size_t max_points) {
  const std::size_t n = std::max<std::int32_t>(cloud.n, 0);
  const std::size_t stride = max_points == 0 ? 1 : std::max<std::size_t>(1, (n + max_points - 1) / max_points);
  const std::size_t kept = (n + stride - 1) / stride;
  std::string out = "HGC1";
  out.reserve(16 + kept * 12);
  put_u32(out, static_cast<std::uint32_t>(kept));
  put_i64(out, cloud.header.seq);
  const Eigen::Vector3d origin = vec3(cloud.plane_origin), u = vec3(cloud.plane_u_axis), v = vec3(cloud.plane_v_axis);
  for (std::size_t i = 0; i < n && i < cloud.u.size() && i < cloud.v.size(); i += stride) {
    const Eigen::Vector3d p = camera_to_base * (origin + double(cloud.u[i]) * u + double(cloud.v[i]) * v);
    for (int k = 0; k < 3; ++k) put_f32(out, static_cast<float>(p[k]));
  }
  return out;
}

Json outline_json(const hullgrind::outline_t& o, const Eigen::Isometry3d& camera_to_base) {
  const Eigen::Vector3d origin = vec3(o.plane_origin), u = vec3(o.plane_u_axis), v = vec3(o.plane_v_axis);
  Json loops = Json::array();
  for (const auto& loop : o.loops) {
    Json xyz = Json::array();
    for (std::size_t i = 0; i < loop.u.size() && i < loop.v.size(); ++i) {
      const Eigen::Vector3d p = camera_to_base * (origin + loop.u[i] * u + loop.v[i] * v);
      xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    }
    loops.push_back({{"hole", loop.hole}, {"perimeter", loop.perimeter}, {"area", loop.area}, {"xyz", xyz}});
  }
  return {{"seq", o.header.seq},
          {"cloud_seq", o.cloud_seq},
          {"status", o.status},
          {"error_text", o.error_text},
          {"alpha_radius", o.alpha_radius},
          {"points_read", o.points_read},
          {"quality", o.quality},
          {"quality_text", o.quality_text},
          {"edge_dropout_fraction", o.edge_dropout_fraction},
          {"largest_edge_gap", o.largest_edge_gap},
          {"holes_dropped", o.holes_dropped},
          {"holes_dropped_area", o.holes_dropped_area},
          {"fragments_dropped", o.fragments_dropped},
          {"fragments_dropped_area", o.fragments_dropped_area},
          {"dropped_text", o.dropped_text},
          {"point_spacing", o.point_spacing},
          {"alpha_mode", o.alpha_mode},
          {"alpha_automatic", o.alpha_automatic},
          {"compute_time", o.compute_time},
          {"loops", loops}};
}

Json plan_json(const hullgrind::grind_path_t& p, const Json* outline) {
  Json position = Json::array(), kind = Json::array(), loop = Json::array();
  for (std::size_t i = 0; i < p.position.size(); ++i) {
    position.insert(position.end(), {p.position[i][0], p.position[i][1], p.position[i][2]});
    kind.push_back(i < p.kind.size() ? p.kind[i] : 0);
    loop.push_back(i < p.loop_index.size() ? p.loop_index[i] : -1);
  }
  Json coverage = Json::array(), unreached = Json::array(), edge = edge_json(p);
  for (const auto& c : p.coverage)
    coverage.push_back({{"loop_index", c.loop_index},
                        {"hole", c.hole},
                        {"planned", c.planned},
                        {"edge_length", c.edge_length},
                        {"reached_length", c.reached_length},
                        {"reason", c.reason}});
  for (const auto& s : p.unreached) {
    Json j = stretch_json(s);
    const Json* ring = stretch_ring(edge, outline, s.loop_index);
    j["xyz"] = ring ? stretch_polyline(*ring, s.start, s.length) : Json::array();
    unreached.push_back(std::move(j));
  }
  return {{"job_id", p.job_id},
          {"revision", p.revision},
          {"outline_seq", p.outline_seq},
          {"frame", p.frame},
          {"tool_radius", p.tool_radius},
          {"position", position},
          {"kind", kind},
          {"loop", loop},
          {"coverage", coverage},
          {"edge", edge},
          {"unreached", unreached}};
}

void LiveState::push_event(Json event) {
  events_.emplace_back(++event_seq_, event.dump(-1, ' ', false, Json::error_handler_t::replace));
  while (events_.size() > options_.event_ring) events_.pop_front();
}

LiveState::JobLive& LiveState::job_entry(const std::string& job_id, std::int64_t utime) {
  auto it = jobs_.find(job_id);
  if (it != jobs_.end()) return it->second;
  while (jobs_.size() >= options_.max_jobs && !job_order_.empty()) {
    jobs_.erase(job_order_.front());
    job_order_.pop_front();
  }
  job_order_.push_back(job_id);
  JobLive& j = jobs_[job_id];
  j.first_utime = utime;
  return j;
}

void LiveState::on_heartbeat(const hullgrind::heartbeat_t& hb, std::int64_t recv) {
  Json j = {{"type", "heartbeat"},
            {"process", hb.process},
            {"pid", hb.pid},
            {"state", hb.state},
            {"state_text", hb.state_text},
            {"uptime", hb.uptime},
            {"received", hb.received},
            {"published", hb.published},
            {"dropped", hb.dropped},
            {"decode_errors", hb.decode_errors},
            {"utime", recv}};
  std::lock_guard lock(mutex_);
  if (heartbeats_.size() > 64 && !heartbeats_.count(hb.process)) return;  // a flood of names is not kept
  heartbeats_[hb.process] = j;
  push_event(std::move(j));
}

void LiveState::on_robot(const hullgrind::robot_status_t& rs, std::int64_t recv) {
  Json j = {{"type", "robot"},
            {"mode", rs.mode},
            {"tcp", {rs.tcp_position[0], rs.tcp_position[1], rs.tcp_position[2]}},
            {"job_id", rs.job_id},
            {"path_index", rs.path_index},
            {"fault_code", rs.fault_code},
            {"fault_text", rs.fault_text},
            {"utime", recv}};
  std::lock_guard lock(mutex_);
  const bool changed = robot_.is_null() || robot_["mode"] != j["mode"] || robot_["fault_code"] != j["fault_code"];
  robot_ = j;
  if (changed || recv - robot_event_utime_ >= 40000) {  // at most 25 poses a second to the page
    robot_event_utime_ = recv;
    push_event(std::move(j));
  }
}

void LiveState::on_status(const hullgrind::job_status_t& js, std::int64_t recv) {
  Json unground = Json::array();
  for (const auto& s : js.unground) unground.push_back(stretch_json(s));
  Json row = {{"type", "status"},
              {"job_id", js.job_id},
              {"part_id", js.part_id},
              {"source", js.source},
              {"state", state_name(js.state)},
              {"progress", js.progress},
              {"message", js.message},
              {"answer", js.answer},
              {"plan_revision", js.plan_revision},
              {"actor", js.actor},
              {"excluded_loops", js.excluded_loops},
              {"unground", unground},
              {"utime", recv}};
  std::lock_guard lock(mutex_);
  JobLive& job = job_entry(js.job_id, recv);
  if (!js.part_id.empty()) job.part_id = js.part_id;
  job.updated_utime = recv;
  if (!js.answer || job.state < 0) {
    job.state = js.state;
    job.source = js.source;
  }
  const bool same = !job.statuses.empty() && job.statuses.back()["source"] == row["source"] &&
                    job.statuses.back()["state"] == row["state"];
  if (same) job.statuses.back() = row;
  else if (job.statuses.size() < kStatusRows)
    job.statuses.push_back(row);
  push_event(std::move(row));
}

void LiveState::on_cloud(const hullgrind::plate_cloud_t& pc, std::int64_t recv) {
  std::string why;
  const auto to_base = capture_to_base(options_, pc.flange_valid, pc.flange_position, pc.flange_orientation, why);
  std::shared_ptr<const std::string> frame;
  if (to_base) frame = std::make_shared<const std::string>(cloud_frame(pc, *to_base, options_.cloud_points));
  std::lock_guard lock(mutex_);
  cloud_times_.push_back(recv);
  while (cloud_times_.size() > 10) cloud_times_.pop_front();
  Json event = {{"type", "cloud"}, {"seq", pc.header.seq}, {"n", pc.n}, {"utime", recv}};
  if (frame) {
    clouds_[pc.header.seq] = frame;
    while (clouds_.size() > kKeptClouds) clouds_.erase(clouds_.begin());
  } else {
    event["placement_error"] = why;  // not kept: drawn nowhere rather than in the wrong place
  }
  push_event(std::move(event));
}

void LiveState::on_outline(const hullgrind::outline_t& o, std::int64_t recv) {
  std::string why;
  const auto to_base = capture_to_base(options_, o.flange_valid, o.flange_position, o.flange_orientation, why);
  Json j = outline_json(o, to_base.value_or(Eigen::Isometry3d::Identity()));
  if (!to_base) {
    j["loops"] = Json::array();  // drawn nowhere rather than in the wrong place
    j["placement_error"] = why;
  }
  j["utime"] = recv;
  std::lock_guard lock(mutex_);
  outlines_[o.header.seq] = std::move(j);
  while (outlines_.size() > kKeptOutlines) outlines_.erase(outlines_.begin());
  push_event({{"type", "outline"}, {"seq", o.header.seq}, {"loops", o.num_loops}, {"utime", recv}});
}

void LiveState::on_path(const hullgrind::grind_path_t& p, std::int64_t recv) {
  std::lock_guard lock(mutex_);
  auto outline = outlines_.find(p.outline_seq);
  Json plan = plan_json(p, outline == outlines_.end() ? nullptr : &outline->second);
  JobLive& job = job_entry(p.job_id, recv);
  job.outline_seq = p.outline_seq;
  if (outline != outlines_.end()) job.plan_outline = outline->second;
  job.plan = std::move(plan);
  push_event({{"type", "path"}, {"job_id", p.job_id}, {"revision", p.revision}, {"utime", recv}});
}

Json LiveState::processes(std::int64_t now) const {
  std::lock_guard lock(mutex_);
  Json out = Json::array();
  for (const auto& [name, hb] : heartbeats_) {
    Json j = hb;
    j["age"] = double(now - hb["utime"].get<std::int64_t>()) * 1e-6;
    out.push_back(std::move(j));
  }
  return out;
}

Json LiveState::robot(std::int64_t now) const {
  std::lock_guard lock(mutex_);
  if (robot_.is_null()) return nullptr;
  Json j = robot_;
  j["age"] = double(now - robot_["utime"].get<std::int64_t>()) * 1e-6;
  return j;
}

double LiveState::camera_fps() const {
  std::lock_guard lock(mutex_);
  if (cloud_times_.size() < 2) return 0;
  const double span = double(cloud_times_.back() - cloud_times_.front()) * 1e-6;
  return span > 0 ? double(cloud_times_.size() - 1) / span : 0;
}

void LiveState::on_requested(const hullgrind::job_request_t& r, std::int64_t utime) {
  std::lock_guard lock(mutex_);
  JobLive& job = job_entry(r.job_id, utime);
  job.requested = true;
  if (job.part_id.empty()) job.part_id = r.part_id;
  if (job.updated_utime == 0) job.updated_utime = utime;
}

Json LiveState::job(const std::string& job_id) const {
  std::lock_guard lock(mutex_);
  auto it = jobs_.find(job_id);
  if (it == jobs_.end()) return nullptr;
  const JobLive& j = it->second;
  Json outline = j.plan_outline;
  if (!outline.is_object() && !outlines_.empty() && outlines_.rbegin()->second["utime"] >= j.first_utime)
    outline = outlines_.rbegin()->second;  // no plan yet: the outline that came since the job started
  return {{"job_id", job_id},
          {"part_id", j.part_id},
          {"state", shown_state(j)},
          {"source", j.source},
          {"first_utime", j.first_utime},
          {"updated_utime", j.updated_utime},
          {"statuses", j.statuses},
          {"plan", j.plan},
          {"outline", outline}};
}

Json LiveState::jobs() const {
  std::lock_guard lock(mutex_);
  Json out = Json::array();
  for (const std::string& id : job_order_) {
    const JobLive& j = jobs_.at(id);
    out.push_back({{"job_id", id},
                   {"part_id", j.part_id},
                   {"state", shown_state(j)},
                   {"source", j.source},
                   {"updated_utime", j.updated_utime},
                   {"first_utime", j.first_utime}});
  }
  return out;
}

std::uint64_t LiveState::events_since(std::uint64_t after, std::vector<std::string>& out, bool& lost) const {
  std::lock_guard lock(mutex_);
  lost = !events_.empty() && after + 1 < events_.front().first && after != 0;
  for (const auto& [seq, text] : events_)
    if (seq > after) out.push_back(text);
  return event_seq_;
}

std::uint64_t LiveState::last_event() const {
  std::lock_guard lock(mutex_);
  return event_seq_;
}

std::shared_ptr<const std::string> LiveState::cloud_for(const std::string& job_id) const {
  std::lock_guard lock(mutex_);
  if (clouds_.empty()) return nullptr;
  auto job = jobs_.find(job_id);
  if (job != jobs_.end() && job->second.plan_outline.is_object()) {
    auto cloud = clouds_.find(job->second.plan_outline["cloud_seq"].get<std::int64_t>());
    if (cloud != clouds_.end()) return cloud->second;
  }
  return clouds_.rbegin()->second;
}

int LiveState::job_state(const std::string& job_id) const {
  std::lock_guard lock(mutex_);
  auto it = jobs_.find(job_id);
  return it == jobs_.end() ? -1 : it->second.state;
}

}  // namespace hg::station
