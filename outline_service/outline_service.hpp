// hg-outline-service: Plate points (HG_PLATE_CLOUD) -> outline (HG_OUTLINE) + part pose (HG_PART_POSE).
#pragma once

#include "runtime/node.hpp"

namespace hg::outline_service {

runtime::ProcessInfo process_info();
// Wires the process's subscriptions and timers onto a node.
void attach(runtime::Node& node);

}  // namespace hg::outline_service
