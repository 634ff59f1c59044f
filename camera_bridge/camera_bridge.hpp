// hg-camera-bridge: depth frames -> the plate's points on HG_PLATE_CLOUD (plate_cloud_t, scan-line order),
// plus a decimated PNG depth image on HG_DEPTH for monitoring.
//
// Capture runs on its own thread (a device read may block); the runtime's main loop keeps the heartbeat
// and the job subscription going meanwhile. The capture thread never lets an exception out: a source that
// cannot be opened or is lost sets the heartbeat to ERROR with the reason, is closed, and re-opened after a
// back-off that doubles up to a limit; a corrupt frame (wrong size or type, all zero) is counted as dropped
// and skipped.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "camera_types/depth_source.hpp"
#include "camera_bridge/segment.hpp"
#include "hullgrind/plate_cloud_t.hpp"
#include "jobs/job_ledger.hpp"
#include "runtime/node.hpp"

namespace hg::camera_bridge {

runtime::ProcessInfo process_info();

struct BridgeOptions {
  bool job_trigger = false;  // true: one capture per job id (job_request_t ACTION_START); false: continuous
  double rate = 2.0;         // continuous: at most this many frames processed per second (<= 0: all)
  SegmentParams segment;
  double depth_rate = 1.0;                  // HG_DEPTH messages per second at most (0: none)
  int depth_decimation = 4;                 // HG_DEPTH keeps every n-th pixel of every n-th row
  double retry_min = 0.5, retry_max = 8.0;  // seconds, back-off after a device failure
  std::chrono::milliseconds grab_timeout{500};
  std::string frame_id = "camera";
  int degraded_after = 10;  // this many corrupt frames in a row: heartbeat DEGRADED
};

// Reads the options from the node's parameters (see process_info()). Throws runtime::ConfigError.
BridgeOptions options_from(const runtime::Node& node);
// Builds the source named by --source. Throws runtime::ConfigError (bad values) or std::invalid_argument.
std::unique_ptr<camera::DepthSource> source_from(const runtime::Node& node);

// plate_cloud_t from a segmentation (status, plane, points). Exposed for tests.
void fill_plate_cloud(const Segmentation& s, hullgrind::plate_cloud_t& msg);

// The robot's last report on HG_ROBOT_STATUS: for an eye-in-hand camera (on the flange), where the camera
// was at capture. The carrying robot reports its flange as the TCP (as hg-calibrate reads it).
struct FlangeReading {
  double position[3] = {0, 0, 0};
  double orientation[4] = {1, 0, 0, 0};  // w, x, y, z
  std::int8_t mode = 0;                  // robot_status_t::MODE_*
  std::int64_t recv_utime = 0;
};
constexpr double kFlangeMaxAge = 1.0;  // s: an older reading does not stand for the capture

// The cloud's flange fields from the latest reading: valid only for a robot standing still (IDLE: not
// RUNNING, no FAULT) heard within kFlangeMaxAge of now_utime; otherwise flange_valid false (and the planner of
// an eye-in-hand cell refuses the outline).
void fill_flange(const std::optional<FlangeReading>& r, std::int64_t now_utime, hullgrind::plate_cloud_t& msg);

class Bridge {
 public:
  Bridge(runtime::Node& node, std::unique_ptr<camera::DepthSource> source, BridgeOptions options);
  ~Bridge();  // stops the capture thread and closes the source
  void start();
  void stop();

  std::int64_t frames_processed() const { return processed_; }
  std::int64_t frames_corrupt() const { return corrupt_; }

 private:
  void run();
  bool sleep_for(double seconds);  // false when stopping
  void count_skipped();            // frames the source dropped -> heartbeat dropped, a bounded log
  void on_job(const std::string& job_id);
  void process(camera::DepthFrame& frame);
  void publish_depth(const camera::DepthFrame& frame);

  runtime::Node& node_;
  std::unique_ptr<camera::DepthSource> source_;
  BridgeOptions opt_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::string> jobs_;  // pending job ids (job trigger)
  jobs::JobLedger captured_;      // job ids already captured for: a repeated START takes no second frame
  std::atomic<std::int64_t> processed_{0}, corrupt_{0};
  std::chrono::steady_clock::time_point last_processed_{}, last_depth_{};
  int corrupt_in_a_row_ = 0;
  std::int64_t skipped_seen_ = 0;  // source_->frames_skipped() already counted as dropped
  runtime::RateLimiter corrupt_log_{5, std::chrono::seconds(10)};
  std::optional<FlangeReading> flange_;  // guarded by mutex_
};

// Wires the process onto a node (runtime::run_process): reads the parameters (throws runtime::ConfigError or
// std::invalid_argument on a bad one), opens the source and starts the capture thread.
std::unique_ptr<Bridge> attach(runtime::Node& node);

}  // namespace hg::camera_bridge
