// hg-path-planner: Outline (HG_OUTLINE) + job request -> grind path in the robot's frame (HG_GRIND_PATH).
#pragma once

#include "runtime/node.hpp"

namespace hg::path_planner {

runtime::ProcessInfo process_info();
// Wires the process's subscriptions and timers onto a node.
void attach(runtime::Node& node);

}  // namespace hg::path_planner
