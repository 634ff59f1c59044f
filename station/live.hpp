// What the station knows from the bus, kept for the HTTP side. The LCM thread writes (on_*), the HTTP
// thread reads (snapshots, events since a sequence number, cloud frames); one mutex held only to swap or
// copy small things, so a slow client never holds up the bus. Everything is bounded: jobs, statuses per
// job, clouds, outlines, the event ring.
#pragma once

#include <Eigen/Geometry>
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"
#include "hullgrind/robot_status_t.hpp"

namespace hg::station {

using Json = nlohmann::json;

std::string state_name(int state);  // job_status_t::STATE_* as text, "AWAITING_APPROVAL", ...
bool state_terminal(int state);     // DONE FAILED ABORTED REFUSED INCOMPLETE REJECTED NEEDS_RESCAN
std::string cause_name(int cause);  // edge_stretch_t::CAUSE_*

// The binary WebSocket frame of a cloud (docs/station.md): "HGC1", uint32 n, int64 cloud seq, then n
// float32 x, y, z triples in the robot base frame, little endian; at most max_points (every k-th point).
std::string cloud_frame(const hullgrind::plate_cloud_t& cloud, const Eigen::Isometry3d& camera_to_base,
                        std::size_t max_points);

// One outline in the base frame: {"seq", "cloud_seq", "loops": [{"hole", "xyz": [x,y,z,...]}], quality...}.
Json outline_json(const hullgrind::outline_t& outline, const Eigen::Isometry3d& camera_to_base);
// One plan (grind_path_t) for the page: waypoints, coverage, the smoothed edge per loop ("edge": [{"loop_index",
// "xyz"}], base frame as the planner sent it) and every unreached stretch as a polyline along its loop's
// smoothed edge (along the outline loop when the plan carries no edge for it).
Json plan_json(const hullgrind::grind_path_t& path, const Json* outline);

struct LiveOptions {
  // The cell's mounting (cell file calibration): a fixed camera's camera-to-base, or for an eye-in-hand
  // cell the camera-to-flange (then camera_to_base is not used).
  Eigen::Isometry3d camera_to_base = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Isometry3d> camera_to_flange;
  std::size_t cloud_points = 200000;
  std::size_t max_jobs = 200;
  std::size_t event_ring = 2000;
};

// Where the camera of one capture was in the base frame, as path_planner/mounting.cpp places an outline: the
// cell's camera-to-base for a fixed camera; base<-flange x camera-to-flange with the capture's flange pose
// (plate_cloud_t / outline_t flange_*) for an eye-in-hand cell. Empty, with `why`, when an eye-in-hand
// capture has no usable flange pose: the page then draws nothing rather than a plate in the wrong place.
std::optional<Eigen::Isometry3d> capture_to_base(const LiveOptions& options, bool flange_valid, const double* position,
                                                 const double* orientation, std::string& why);

class LiveState {
 public:
  explicit LiveState(LiveOptions options) : options_(std::move(options)) {}

  // LCM thread.
  void on_heartbeat(const hullgrind::heartbeat_t& hb, std::int64_t recv_utime);
  void on_robot(const hullgrind::robot_status_t& rs, std::int64_t recv_utime);
  void on_status(const hullgrind::job_status_t& js, std::int64_t recv_utime);
  void on_cloud(const hullgrind::plate_cloud_t& pc, std::int64_t recv_utime);
  void on_outline(const hullgrind::outline_t& o, std::int64_t recv_utime);
  void on_path(const hullgrind::grind_path_t& p, std::int64_t recv_utime);

  // HTTP thread.
  Json processes(std::int64_t now_utime) const;  // heartbeats by process, with their age
  Json robot(std::int64_t now_utime) const;
  double camera_fps() const;                  // plate clouds per second over the last ones (0: none)
  Json job(const std::string& job_id) const;  // live statuses, outline and plan; null when never seen
  Json jobs() const;                          // [{job_id, part_id, state, source, updated}]
  // Events after `after` (JSON text); returns the sequence number of the last one. `lost` is set when the
  // ring no longer holds every event after `after` (the client must reload).
  std::uint64_t events_since(std::uint64_t after, std::vector<std::string>& out, bool& lost) const;
  std::uint64_t last_event() const;
  // The cloud the job's outline came from (or the latest cloud for "" or a job without an outline yet).
  std::shared_ptr<const std::string> cloud_for(const std::string& job_id) const;
  // The last state of a job as the robot bridge (else anyone) reported it; -1 when unknown.
  int job_state(const std::string& job_id) const;
  // A START this station put on the bus: the job is known at once, as REQUESTED until a process answers,
  // so that the page which opens it right after finds it whatever the bus's round trip takes.
  void on_requested(const hullgrind::job_request_t& r, std::int64_t utime);

 private:
  struct JobLive {
    std::string part_id;
    std::vector<Json> statuses;  // a row per change of (source, state); the last row refreshed
    std::int64_t first_utime = 0, updated_utime = 0;
    int state = -1;
    bool requested = false;  // started by this station (on_requested)
    std::string source;
    std::int64_t outline_seq = -1;
    Json plan;          // the latest revision
    Json plan_outline;  // the outline it was planned on (base frame)
  };
  static std::string shown_state(const JobLive& j);
  void push_event(Json event);  // mutex held
  JobLive& job_entry(const std::string& job_id, std::int64_t utime);

  LiveOptions options_;
  mutable std::mutex mutex_;
  std::map<std::string, Json> heartbeats_;
  Json robot_ = nullptr;
  std::int64_t robot_event_utime_ = 0;
  std::deque<std::int64_t> cloud_times_;
  std::map<std::int64_t, std::shared_ptr<const std::string>> clouds_;  // by cloud seq, the last few
  std::map<std::int64_t, Json> outlines_;                              // by outline seq, the last few
  std::map<std::string, JobLive> jobs_;
  std::deque<std::string> job_order_;
  std::deque<std::pair<std::uint64_t, std::string>> events_;
  std::uint64_t event_seq_ = 0;
};

}  // namespace hg::station
