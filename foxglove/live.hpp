// hg-foxglove: the bus, live, for Foxglove and Lichtblick (docs/foxglove.md). Subscribes every LCM channel,
// turns each message into the Bridge's topics (the same as hg-mcap writes) and serves them with the
// Foxglove WebSocket protocol (ws_server.hpp) on 127.0.0.1:8765.
//
// It never slows the cell: the LCM thread only copies a message into a bounded queue (a full queue drops
// the oldest message, and a cloud the one of its channel still waiting, counted as dropped in the heartbeat);
// one worker converts at idle scheduling priority (SCHED_IDLE: only on a core the cell leaves free),
// building only what a client subscribed to (and the small messages, kept as each channel's last for late
// subscribers); each client has its own bounded queue, frames that do not fit are dropped for that client
// and counted.
#pragma once

#include <memory>

#include "runtime/node.hpp"

namespace hg::foxglove {

runtime::ProcessInfo process_info();
std::shared_ptr<void> attach(runtime::Node& node);

}  // namespace hg::foxglove
