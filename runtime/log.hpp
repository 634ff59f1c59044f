// Logging to stderr: "2026-11-22T04:52:45.123Z INFO  hg-outline-service: message".
#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace hg::runtime {

enum class Level { Debug = 0, Info = 1, Warn = 2, Error = 3 };

void set_process_name(const std::string& name);
void set_log_level(Level level);
Level parse_level(const std::string& text);  // debug|info|warn|error; throws std::invalid_argument

void logf(Level level, const char* fmt, ...) __attribute__((format(printf, 2, 3)));

// Lets at most `burst` messages through per `period`; counts the rest so the next allowed message can
// say how many were suppressed. For messages caused by input (bad packets), which must not flood the log.
class RateLimiter {
 public:
  explicit RateLimiter(int burst = 5, std::chrono::milliseconds period = std::chrono::seconds(10))
      : burst_(burst), period_(period) {}
  // True if a message may be logged now; `suppressed` receives how many were held back since the last one.
  bool allow(std::uint64_t& suppressed);

 private:
  int burst_;
  std::chrono::milliseconds period_;
  std::chrono::steady_clock::time_point window_start_{};
  int in_window_ = 0;
  std::uint64_t suppressed_ = 0;
  std::mutex mutex_;
};

}  // namespace hg::runtime
