// An LCM log -> MCAP: every event through the Bridge (the live server's topics and schemas), log time and
// publish time the event's time. hg-mcap is this plus a command line.
#pragma once

#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "bridge.hpp"
#include "mcap_writer.hpp"

namespace hg::foxglove {

struct ToMcapOptions {
  McapOptions mcap;
  BridgeOptions bridge;
  // Only the events with start_utime <= time <= end_utime (a job's slice); the default: all.
  std::int64_t start_utime = std::numeric_limits<std::int64_t>::min();
  std::int64_t end_utime = std::numeric_limits<std::int64_t>::max();
};

struct ToMcapStats {
  std::size_t events = 0;       // well-formed events in the time range
  std::size_t events_read = 0;  // well-formed events in the whole log
  std::size_t corrupt = 0;      // corrupt stretches of the log skipped
  std::vector<std::size_t> corrupt_offsets;
  std::size_t decode_errors = 0;                              // events of a known type that did not decode: skipped
  std::string first_decode_error;                             // "CHANNEL event N: why"
  std::vector<std::pair<std::string, std::int64_t>> skipped;  // channel and event number of each (first 100)
  std::size_t unknown = 0;   // events of no hullgrind type: written raw (encoding "lcm")
  std::size_t messages = 0;  // MCAP messages written (LCM channels and derived topics)
  std::size_t topics = 0;
  std::uint64_t bytes_out = 0;
  std::map<std::string, std::size_t> per_topic;
};

// Throws std::runtime_error on a write failure.
ToMcapStats lcmlog_to_mcap(const std::uint8_t* log, std::size_t size, std::FILE* out, const ToMcapOptions& opt);

}  // namespace hg::foxglove
