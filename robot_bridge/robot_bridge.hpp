// hg-robot-bridge: Grind paths (HG_GRIND_PATH) -> robot (sim or Universal Robots) -> HG_ROBOT_STATUS, HG_JOB_STATUS.
#pragma once

#include "runtime/node.hpp"

namespace hg::robot_bridge {

runtime::ProcessInfo process_info();
// Wires the process's subscriptions and timers onto a node.
void attach(runtime::Node& node);

}  // namespace hg::robot_bridge
