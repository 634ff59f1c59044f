// Small command-line helpers shared by hg-lcm-dump and hg-lcm-send.
#pragma once

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "runtime/lcm_url.hpp"

namespace hg::lcmtools {

using runtime::default_lcm_url;  // LCM_DEFAULT_URL, else multicast with ttl=0
using runtime::with_receive_buffer;

class UsageError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Walks argv accepting "--name value" and "--name=value".
class Args {
 public:
  Args(int argc, char** argv, int first) : args_(argv + first, argv + argc) {}
  bool done() const { return i_ >= args_.size(); }
  // The next option's name ("--count"); its inline value, if any, is kept for value().
  std::string next() {
    std::string a = args_[i_++];
    inline_.clear();
    has_inline_ = false;
    if (a.rfind("--", 0) == 0) {
      auto eq = a.find('=');
      if (eq != std::string::npos) {
        inline_ = a.substr(eq + 1);
        has_inline_ = true;
        a.resize(eq);
      }
    }
    current_ = a;
    return a;
  }
  std::string value() {
    if (has_inline_) return inline_;
    if (done()) throw UsageError(current_ + " needs a value");
    return args_[i_++];
  }
  double number(double lo, double hi) {
    std::string v = value();
    std::size_t used = 0;
    double x = 0;
    try {
      x = std::stod(v, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != v.size() || v.empty() || !(x >= lo && x <= hi))
      throw UsageError(current_ + ": '" + v + "' is not a number in [" + std::to_string(lo) + ", " +
                       std::to_string(hi) + "]");
    return x;
  }
  long long integer(long long lo, long long hi) {
    std::string v = value();
    std::size_t used = 0;
    long long x = 0;
    try {
      x = std::stoll(v, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != v.size() || v.empty() || x < lo || x > hi)
      throw UsageError(current_ + ": '" + v + "' is not an integer in [" + std::to_string(lo) + ", " +
                       std::to_string(hi) + "]");
    return x;
  }
  bool flag() {
    if (has_inline_) throw UsageError(current_ + " takes no value");
    return true;
  }

 private:
  std::vector<std::string> args_;
  std::size_t i_ = 0;
  std::string current_, inline_;
  bool has_inline_ = false;
};

}  // namespace hg::lcmtools
