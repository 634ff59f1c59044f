#include "dds_gateway/dds_gateway.hpp"

#include "hullgrind/job_status_t.hpp"
#include "runtime/channels.hpp"

namespace hg::dds_gateway {

runtime::ProcessInfo process_info() {
  return {"hg-dds-gateway", "LCM <-> Cyclone DDS bridge for plant systems.",
          "Not there yet (issue 7): the DDS side. This skeleton runs the shared runtime only and counts the\njob statuses it receives.",
          {}};
}

void attach(runtime::Node& node) {
  node.subscribe<hullgrind::job_status_t>(channels::kJobStatus, [](const hullgrind::job_status_t&, const runtime::Delivery& d) {
    runtime::logf(runtime::Level::Debug, "received job_status_t on %s", d.channel.c_str());
  });
}

}  // namespace hg::dds_gateway
