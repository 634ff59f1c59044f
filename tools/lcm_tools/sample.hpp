// Deterministic sample messages of any hullgrind type, for demos and tests: every field is a function of
// (seq, position of the value in the message), so a subscriber can rebuild the expected message from the
// seq alone. header.seq is seq and header.utime the given time (the one field a checker must take from
// the message itself).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "lcm_schema.hpp"

namespace hg::lcmtools {

Json sample_message(const Schema& schema, const Struct& type, int64_t seq, int64_t utime);

// The channel a type is published on (runtime/channels.hpp); "" for types that are only parts of others.
std::string default_channel(const Struct& type);

// Types that are messages on a channel of their own, in schema order.
std::vector<const Struct*> message_types(const Schema& schema);

// A message's header.seq, or the seq field of a header_t itself; -1 if it has none.
int64_t message_seq(const Json& msg);

}  // namespace hg::lcmtools
