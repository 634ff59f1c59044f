#include "path_planner/path_planner.hpp"

#include "hullgrind/outline_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "runtime/channels.hpp"

namespace hg::path_planner {

runtime::ProcessInfo process_info() {
  return {"hg-path-planner", "Outline (HG_OUTLINE) + job request -> grind path in the robot's frame (HG_GRIND_PATH).",
          "Not there yet (issue 5): the planning pipeline. This skeleton runs the shared runtime only and counts\nthe outlines and job requests it receives.",
          {}};
}

void attach(runtime::Node& node) {
  node.subscribe<hullgrind::outline_t>(channels::kOutline, [](const hullgrind::outline_t&, const runtime::Delivery& d) {
    runtime::logf(runtime::Level::Debug, "received outline_t on %s", d.channel.c_str());
  });
  node.subscribe<hullgrind::job_request_t>(channels::kJobRequest, [](const hullgrind::job_request_t&, const runtime::Delivery& d) {
    runtime::logf(runtime::Level::Debug, "received job_request_t on %s", d.channel.c_str());
  });
}

}  // namespace hg::path_planner
