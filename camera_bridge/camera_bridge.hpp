// hg-camera-bridge: Depth camera -> plate points (HG_PLATE_CLOUD).
#pragma once

#include "runtime/node.hpp"

namespace hg::camera_bridge {

runtime::ProcessInfo process_info();
// Wires the process's subscriptions and timers onto a node.
void attach(runtime::Node& node);

}  // namespace hg::camera_bridge
