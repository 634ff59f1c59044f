// runtime::RateLimiter: the log's guard against a flood of the same message; the log sink (log_sink.hpp):
// every logged line at or above the level, once, in order, never recursively, and none after removal.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "runtime/log.hpp"
#include "runtime/log_sink.hpp"

namespace hr = hg::runtime;

namespace {

TEST(RuntimeLog, RateLimiterHoldsBackAndReports) {
  hr::RateLimiter limiter(2, std::chrono::hours(1));
  uint64_t suppressed = 99;
  EXPECT_TRUE(limiter.allow(suppressed));
  EXPECT_EQ(suppressed, 0u);
  EXPECT_TRUE(limiter.allow(suppressed));
  EXPECT_FALSE(limiter.allow(suppressed));
  EXPECT_FALSE(limiter.allow(suppressed));
}

TEST(RuntimeLog, SinkGetsEveryLineOnceAndCannotRecurse) {
  struct Line {
    hr::Level level;
    std::int64_t utime;
    std::string text;
  };
  std::vector<Line> got;
  hr::set_log_level(hr::Level::Info);
  hr::set_log_sink([&got](hr::Level level, std::int64_t utime, const char* text) {
    got.push_back({level, utime, text});
    hr::logf(hr::Level::Error, "logged inside the sink");  // stderr only: no second call
  });
  const auto before = std::chrono::system_clock::now();
  hr::logf(hr::Level::Debug, "below the level");
  for (int i = 0; i < 50; ++i) hr::logf(i % 2 ? hr::Level::Warn : hr::Level::Info, "line %d of %s", i, "fifty");
  const auto after = std::chrono::system_clock::now();
  hr::set_log_sink(nullptr);
  hr::logf(hr::Level::Info, "after the sink was removed");
  ASSERT_EQ(got.size(), 50u);
  const auto us = [](std::chrono::system_clock::time_point t) {
    return std::chrono::duration_cast<std::chrono::microseconds>(t.time_since_epoch()).count();
  };
  for (int i = 0; i < 50; ++i) {
    EXPECT_EQ(got[i].text, "line " + std::to_string(i) + " of fifty");
    EXPECT_EQ(got[i].level, i % 2 ? hr::Level::Warn : hr::Level::Info);
    EXPECT_GE(got[i].utime, us(before) - 1000);  // gettimeofday and system_clock: the same clock
    EXPECT_LE(got[i].utime, us(after) + 1000);
  }
}

TEST(RuntimeLog, SinkTakesLinesFromManyThreads) {
  std::atomic<int> calls{0};
  hr::set_log_sink([&calls](hr::Level, std::int64_t, const char*) { ++calls; });
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([] {
      for (int i = 0; i < 100; ++i) hr::logf(hr::Level::Info, "thread line %d", i);
    });
  for (auto& t : threads) t.join();
  hr::set_log_sink(nullptr);
  EXPECT_EQ(calls.load(), 400);
}

}  // namespace
