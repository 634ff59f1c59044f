// runtime::RateLimiter: the log's guard against a flood of the same message.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>

#include "runtime/log.hpp"

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

}  // namespace
