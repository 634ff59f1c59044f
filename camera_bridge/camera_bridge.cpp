#include "camera_bridge/camera_bridge.hpp"

#include "hullgrind/job_request_t.hpp"
#include "runtime/channels.hpp"

namespace hg::camera_bridge {

runtime::ProcessInfo process_info() {
  return {"hg-camera-bridge", "Depth camera -> plate points (HG_PLATE_CLOUD).",
          "Not there yet (issue 4): capture (OpenNI2, .oni, virtual device, files, synthetic) and plate\nsegmentation. This skeleton runs the shared runtime only: heartbeat, config, clean shutdown, and it\nlistens to HG_JOB_REQUEST (counted in the heartbeat).",
          {}};
}

void attach(runtime::Node& node) {
  node.subscribe<hullgrind::job_request_t>(channels::kJobRequest, [](const hullgrind::job_request_t&, const runtime::Delivery& d) {
    runtime::logf(runtime::Level::Debug, "received job_request_t on %s", d.channel.c_str());
  });
}

}  // namespace hg::camera_bridge
