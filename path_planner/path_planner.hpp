// hg-path-planner: outline (HG_OUTLINE) + job request (HG_JOB_REQUEST) -> grind path in the robot's base
// frame (HG_GRIND_PATH) and the job's planning status (HG_JOB_STATUS). The planning itself is plan() in
// pipeline.hpp; this is the process around it.
#pragma once

#include "runtime/node.hpp"

namespace hg::path_planner {

runtime::ProcessInfo process_info();
// Wires the process's subscriptions and timers onto a node. Throws runtime::ConfigError on a bad config.
void attach(runtime::Node& node);

}  // namespace hg::path_planner
