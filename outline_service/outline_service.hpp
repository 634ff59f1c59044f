// hg-outline-service: plate points (HG_PLATE_CLOUD) -> outline (HG_OUTLINE) + part pose (HG_PART_POSE).
#pragma once

#include <memory>

#include <condition_variable>
#include <cstdint>
#include <limits>
#include <string>
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
// The outline core's options (the hole rule, Options::min_hole_spacings, is the core's, so hg-outline and
// this service give the same outline for one cloud) and the cell's outline rules (docs/cell.md, section
// outline): the smallest part, and the edge-quality limits. The defaults here keep everything and judge
// nothing POOR; the process takes them from its --cell.
struct ServiceOptions : outline::Options {
  double min_part_area = 0;     // m^2: smaller outer loops (and the holes in them) are dropped as fragments
  double max_edge_dropout = 1;  // fraction of the edge in dropout or shadow above which quality is POOR
  double max_edge_gap = std::numeric_limits<double>::infinity();  // m, the longest stretch; above: POOR
  std::string cell_file;  // named in the reasons ("config/cell.yaml outline.max-edge-gap 0.1")
};
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
