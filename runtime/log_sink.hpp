// Where each logged line goes besides stderr (runtime/log.hpp): the Node installs the sink that publishes
// the lines as log_line_t on HG_LOG once it has opened LCM.
#pragma once

#include <cstdint>
#include <functional>

#include "runtime/log.hpp"

namespace hg::runtime {

// One sink per process (an empty function removes it). The sink is called with the line's level, time
// (microseconds since the epoch) and text, after stderr, one line at a time; a line logged while the sink
// runs (on the same thread) goes to stderr only, so a sink that logs cannot recurse. set_log_sink waits for
// a running call, so the sink's owner may be destroyed once it has removed the sink.
using LogSink = std::function<void(Level level, std::int64_t utime, const char* text)>;
void set_log_sink(LogSink sink);

}  // namespace hg::runtime
