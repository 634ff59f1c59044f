// hg-outline-service: plate points (HG_PLATE_CLOUD) -> outline (HG_OUTLINE) + part pose (HG_PART_POSE).
#pragma once

#include <memory>

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "hullgrind/outline_t.hpp"
#include "hullgrind/part_pose_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"
#include "outline_core/outline.hpp"
#include "runtime/node.hpp"

namespace hg::outline_service {

runtime::ProcessInfo process_info();
// The outline core's options: the hole rule (Options::min_hole_spacings) is the core's, so hg-outline and
// this service give the same outline for one cloud.
using ServiceOptions = outline::Options;
ServiceOptions options_from(const runtime::Node& node);  // throws runtime::ConfigError

struct Computed {
  hullgrind::outline_t outline;
  std::vector<hullgrind::part_pose_t> poses;  // one per part, largest first; empty unless status OK
  int holes_dropped = 0;                      // below the minimum hole size (Result::holes_dropped)
};

// The whole computation for one cloud, without LCM: never throws on bad input; a cloud that yields no
// valid loop gives an outline with an error status and the reason, and no loops.
Computed compute(const hullgrind::plate_cloud_t& cloud, const ServiceOptions& options);

// The process logic: the newest cloud wins. Clouds are computed on a worker thread; a cloud still waiting
// when a newer one arrives is dropped and counted in the heartbeat.
class OutlineService {
 public:
  explicit OutlineService(runtime::Node& node);
  ~OutlineService();

 private:
  void work();
  runtime::Node& node_;
  ServiceOptions options_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<hullgrind::plate_cloud_t> pending_;
  std::int64_t pending_recv_utime_ = 0;
  bool quit_ = false;
  bool busy_ = false;
  std::thread worker_;
};

// Wires the service onto a node (runtime::run_process). Throws runtime::ConfigError on a bad parameter.
std::unique_ptr<OutlineService> attach(runtime::Node& node);

}  // namespace hg::outline_service
