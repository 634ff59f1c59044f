// hg-outline-service: plate points (HG_PLATE_CLOUD) -> outline (HG_OUTLINE) + part pose (HG_PART_POSE).
#pragma once

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
struct ServiceOptions {
  ServiceOptions(outline::Options o = {}, double min_hole = 5) : outline(o), min_hole_spacings(min_hole) {}
  outline::Options outline;
  // Holes smaller in area than (min_hole_spacings x median point spacing s)^2 are dropped: a gap that
  // small is a few missing pixels, not a cut-out (a 2x2 block of dropout leaves a 7 s^2 hole, a 3x3 block
  // 14 s^2; pm806 frames show 3x3 gaps now and then). 5 spacings, 25 s^2: a round cut-out is kept from
  // about 5.7 s across (7.6 mm at pm806's 1.34 mm pixels), far below any tool that could grind it. 0 keeps
  // every hole.
  double min_hole_spacings = 5;
};
ServiceOptions options_from(const runtime::Node& node);  // throws runtime::ConfigError

struct Computed {
  hullgrind::outline_t outline;
  std::vector<hullgrind::part_pose_t> poses;  // one per part, largest first; empty unless status OK
  int holes_dropped = 0;                       // below the minimum hole size
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

}  // namespace hg::outline_service
