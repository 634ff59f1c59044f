#include "outline_service/outline_service.hpp"

#include "hullgrind/plate_cloud_t.hpp"
#include "runtime/channels.hpp"

namespace hg::outline_service {

runtime::ProcessInfo process_info() {
  return {"hg-outline-service", "Plate points (HG_PLATE_CLOUD) -> outline (HG_OUTLINE) + part pose (HG_PART_POSE).",
          "Not there yet (issue 5): running the outline core on received clouds. This skeleton runs the shared\nruntime only and counts the plate clouds it receives.",
          {}};
}

void attach(runtime::Node& node) {
  node.subscribe<hullgrind::plate_cloud_t>(channels::kPlateCloud, [](const hullgrind::plate_cloud_t&, const runtime::Delivery& d) {
    runtime::logf(runtime::Level::Debug, "received plate_cloud_t on %s", d.channel.c_str());
  });
}

}  // namespace hg::outline_service
