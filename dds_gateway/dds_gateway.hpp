// hg-dds-gateway: LCM <-> Cyclone DDS bridge for plant systems.
#pragma once

#include "runtime/node.hpp"

namespace hg::dds_gateway {

runtime::ProcessInfo process_info();
// Wires the process's subscriptions and timers onto a node.
void attach(runtime::Node& node);

}  // namespace hg::dds_gateway
