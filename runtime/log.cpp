#include "runtime/log.hpp"
#include "runtime/log_sink.hpp"

#include <cstdarg>
#include <cstdio>
#include <ctime>
#include <stdexcept>
#include <sys/time.h>

namespace hg::runtime {
namespace {
std::string g_name = "hullgrind";
Level g_level = Level::Info;
std::mutex g_mutex;
std::mutex g_sink_mutex;  // held while the sink runs
LogSink g_sink;
thread_local bool t_in_sink = false;

void to_sink(Level level, std::int64_t utime, const char* text) {
  if (t_in_sink) return;
  std::lock_guard lock(g_sink_mutex);
  if (!g_sink) return;
  t_in_sink = true;
  try {
    g_sink(level, utime, text);
  } catch (...) {  // a log line never ends a process
  }
  t_in_sink = false;
}

const char* level_name(Level l) {
  switch (l) {
    case Level::Debug: return "DEBUG";
    case Level::Info: return "INFO ";
    case Level::Warn: return "WARN ";
    case Level::Error: return "ERROR";
  }
  return "?";
}
}  // namespace

void set_process_name(const std::string& name) {
  std::lock_guard lock(g_mutex);
  g_name = name;
}
void set_log_level(Level level) { g_level = level; }

void set_log_sink(LogSink sink) {
  std::lock_guard lock(g_sink_mutex);
  g_sink = std::move(sink);
}

Level parse_level(const std::string& t) {
  if (t == "debug") return Level::Debug;
  if (t == "info") return Level::Info;
  if (t == "warn") return Level::Warn;
  if (t == "error") return Level::Error;
  throw std::invalid_argument("unknown log level '" + t + "' (debug|info|warn|error)");
}

void logf(Level level, const char* fmt, ...) {
  if (level < g_level) return;
  char text[2048];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(text, sizeof text, fmt, ap);
  va_end(ap);
  timeval tv{};
  gettimeofday(&tv, nullptr);
  tm utc{};
  gmtime_r(&tv.tv_sec, &utc);
  char stamp[40];
  strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%S", &utc);
  {
    std::lock_guard lock(g_mutex);
    fprintf(stderr, "%s.%03dZ %s %s: %s\n", stamp, int(tv.tv_usec / 1000), level_name(level), g_name.c_str(), text);
    fflush(stderr);
  }
  to_sink(level, std::int64_t(tv.tv_sec) * 1000000 + tv.tv_usec, text);
}

bool RateLimiter::allow(std::uint64_t& suppressed) {
  std::lock_guard lock(mutex_);
  auto now = std::chrono::steady_clock::now();
  if (now - window_start_ >= period_) {
    window_start_ = now;
    in_window_ = 0;
  }
  if (in_window_ < burst_) {
    ++in_window_;
    suppressed = suppressed_;
    suppressed_ = 0;
    return true;
  }
  ++suppressed_;
  return false;
}

}  // namespace hg::runtime
