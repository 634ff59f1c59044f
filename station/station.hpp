// hg-station: the operator station (docs/station.md). The LCM loop on the main thread feeds LiveState and
// publishes the job requests the HTTP thread queued (bounded); the Beast server runs on its own thread.
#pragma once

#include <memory>

#include "runtime/node.hpp"

namespace hg::station {

runtime::ProcessInfo process_info();

// Reads the users and cell files, binds the server, subscribes the bus. Throws ConfigError /
// std::invalid_argument for a bad parameter (exit 2), std::runtime_error when it cannot listen.
std::shared_ptr<void> attach(runtime::Node& node);

}  // namespace hg::station
