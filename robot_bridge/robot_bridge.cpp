#include "robot_bridge/robot_bridge.hpp"

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "runtime/channels.hpp"

namespace hg::robot_bridge {

runtime::ProcessInfo process_info() {
  return {"hg-robot-bridge", "Grind paths (HG_GRIND_PATH) -> robot (sim or Universal Robots) -> HG_ROBOT_STATUS, HG_JOB_STATUS.",
          "Not there yet (issue 6): the simulated robot and the UR driver. This skeleton runs the shared\nruntime only and counts the paths and job requests it receives.",
          {}};
}

void attach(runtime::Node& node) {
  node.subscribe<hullgrind::grind_path_t>(channels::kGrindPath, [](const hullgrind::grind_path_t&, const runtime::Delivery& d) {
    runtime::logf(runtime::Level::Debug, "received grind_path_t on %s", d.channel.c_str());
  });
  node.subscribe<hullgrind::job_request_t>(channels::kJobRequest, [](const hullgrind::job_request_t&, const runtime::Delivery& d) {
    runtime::logf(runtime::Level::Debug, "received job_request_t on %s", d.channel.c_str());
  });
}

}  // namespace hg::robot_bridge
