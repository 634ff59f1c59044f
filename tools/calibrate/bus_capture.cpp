#include "tools/calibrate/bus_capture.hpp"

#include <chrono>
#include <stdexcept>

#include <lcm/lcm-cpp.hpp>

#include "hullgrind/job_request_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"
#include "hullgrind/robot_status_t.hpp"
#include "runtime/channels.hpp"
#include "runtime/lcm_url.hpp"
#include "tools/calibrate/session.hpp"

namespace hg::calibrate {

namespace {

using Clock = std::chrono::steady_clock;

std::int64_t now_utime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

Eigen::Vector3d vec(const double* p) { return {p[0], p[1], p[2]}; }

// What the three subscriptions have seen since the capture began.
struct Listener {
  std::int64_t start_utime = 0;
  std::optional<hullgrind::plate_cloud_t> cloud;
  std::optional<hullgrind::outline_t> outline;
  std::optional<hullgrind::robot_status_t> status_after_cloud;
  void on_cloud(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::plate_cloud_t* m) {
    if (!cloud && m->header.utime >= start_utime) cloud = *m;  // a frame taken before we asked does not count
  }
  void on_outline(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::outline_t* m) {
    if (cloud && !outline && m->cloud_seq == cloud->header.seq) outline = *m;
  }
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::robot_status_t* m) {
    if (cloud) status_after_cloud = *m;
  }
};

hullgrind::job_request_t start_request(const std::string& job_id) {
  hullgrind::job_request_t r{};
  r.header.utime = now_utime();
  r.job_id = job_id;
  r.part_id = "calibration-plate";
  r.action = hullgrind::job_request_t::ACTION_START;
  return r;
}

// Spins until `done` or the deadline; with a job id, (re)sends the START every second until a cloud came (the
// bridge answers one capture per id, so a repeat is harmless).
template <class Done>
bool spin(lcm::LCM& lcm, Listener& l, const CaptureOptions& o, Clock::time_point deadline, Done done) {
  const hullgrind::job_request_t request = start_request(o.job_id);
  auto next_send = Clock::now();
  while (!done() && Clock::now() < deadline) {
    if (!o.job_id.empty() && !l.cloud && Clock::now() >= next_send) {
      lcm.publish(channels::kJobRequest, &request);
      next_send += std::chrono::seconds(1);
    }
    lcm.handleTimeout(50);
  }
  return done();
}

Eigen::Isometry3d pose_of(const hullgrind::robot_status_t& s) {
  if (s.mode == hullgrind::robot_status_t::MODE_RUNNING)
    throw std::runtime_error("the robot is moving (HG_ROBOT_STATUS RUNNING)");
  if (s.mode != hullgrind::robot_status_t::MODE_IDLE)
    throw std::runtime_error("the robot is not idle (HG_ROBOT_STATUS mode " + std::to_string(s.mode) + ": " +
                             s.fault_text + ")");
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  const double* q = s.tcp_orientation;
  t.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
  t.translation() = vec(s.tcp_position);
  return t;
}

}  // namespace

Captured capture_from_bus(const CaptureOptions& o) {
  lcm::LCM lcm(runtime::with_receive_buffer(o.lcm_url));  // plate clouds are megabytes
  if (!lcm.good()) throw std::runtime_error("cannot start LCM on " + o.lcm_url);
  Listener l;
  l.start_utime = now_utime();
  lcm.subscribe(channels::kPlateCloud, &Listener::on_cloud, &l);
  lcm.subscribe(channels::kOutline, &Listener::on_outline, &l);
  lcm.subscribe(channels::kRobotStatus, &Listener::on_status, &l);
  const Clock::time_point deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.timeout_s));
  const std::string within = " within " + std::to_string(o.timeout_s) + " s on " + o.lcm_url;
  if (!spin(lcm, l, o, deadline, [&] { return l.cloud.has_value(); }))
    throw std::runtime_error("no HG_PLATE_CLOUD" + within +
                             (o.job_id.empty() ? "" : " (after START " + o.job_id + ")"));
  const hullgrind::plate_cloud_t& c = *l.cloud;
  if (c.status != hullgrind::plate_cloud_t::STATUS_OK)
    throw std::runtime_error("camera bridge: plate cloud " + std::to_string(c.header.seq) + ": " + c.status_text);
  Captured out;
  out.plane = {vec(c.plane_origin), vec(c.plane_u_axis), vec(c.plane_v_axis)};
  if (o.local_outline) {
    out.loops = calibration::hole_loops(c.u, c.v);
  } else {
    if (!spin(lcm, l, o, deadline, [&] { return l.outline.has_value(); }))
      throw std::runtime_error("no HG_OUTLINE of plate cloud " + std::to_string(c.header.seq) + within);
    const hullgrind::outline_t& m = *l.outline;
    if (m.status != hullgrind::outline_t::STATUS_OK)
      throw std::runtime_error("outline service: outline of cloud " + std::to_string(c.header.seq) + ": " +
                               m.error_text);
    out.plane = {vec(m.plane_origin), vec(m.plane_u_axis), vec(m.plane_v_axis)};
    for (const auto& loop : m.loops) {
      if (!loop.hole) continue;
      calibration::HoleLoop ring;
      for (int i = 0; i < loop.n; ++i) ring.emplace_back(loop.u[i], loop.v[i]);
      out.loops.push_back(std::move(ring));
    }
  }
  if (o.robot_pose) {
    if (!spin(lcm, l, o, deadline, [&] { return l.status_after_cloud.has_value(); }))
      throw std::runtime_error("no HG_ROBOT_STATUS after the plate cloud" + within);
    out.tcp_to_base = pose_of(*l.status_after_cloud);
  }
  out.record = outline_view_json(out.plane, out.loops);
  out.record["source"] =
      o.local_outline ? "HG_PLATE_CLOUD + outline core in hg-calibrate" : "HG_PLATE_CLOUD + HG_OUTLINE";
  out.record["frame_id"] = c.header.frame_id;
  out.record["cloud_seq"] = c.header.seq;
  out.record["cloud_utime"] = c.header.utime;
  out.record["cloud_points"] = c.n;
  out.text = "plate cloud " + std::to_string(c.header.seq) + " (" + std::to_string(c.n) + " points), " +
             std::to_string(out.loops.size()) + " hole loops" +
             (o.local_outline ? " (outline core here)" : " (HG_OUTLINE)");
  return out;
}

}  // namespace hg::calibrate
