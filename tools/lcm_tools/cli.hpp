// What hg-lcm-dump and hg-lcm-send share besides runtime::Params (their options are declared there).
#pragma once

#include <stdexcept>
#include <string>

#include "runtime/lcm_url.hpp"

namespace hg::lcmtools {

using runtime::default_lcm_url;  // LCM_DEFAULT_URL, else multicast with ttl=0
using runtime::with_receive_buffer;

// A command line that parses but asks for something impossible (a missing --job-id, an unknown type): exit 2.
class UsageError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace hg::lcmtools
