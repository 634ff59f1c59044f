// Frame pacing for depth sources that make their frames themselves (synthetic scenes, files): frames at a
// rate, never a burst to catch up.
#pragma once

#include <algorithm>
#include <chrono>
#include <thread>

namespace hg::camera {

using PacingClock = std::chrono::steady_clock;

// The period of `rate` Hz; zero (no pacing) for rate <= 0.
inline PacingClock::duration period_of(double rate) {
  if (!(rate > 0)) return PacingClock::duration::zero();
  return std::chrono::duration_cast<PacingClock::duration>(std::chrono::duration<double>(1.0 / rate));
}

// Waits for the pacing slot `next` (period zero: no pacing). False when it is further away than timeout
// (after waiting out the timeout), so grab() can return nullopt and the caller stays responsive.
inline bool wait_slot(PacingClock::time_point& next, PacingClock::duration period, std::chrono::milliseconds timeout) {
  if (period == PacingClock::duration::zero()) return true;
  const auto now = PacingClock::now();
  if (next == PacingClock::time_point{}) next = now;
  if (next > now + timeout) {
    std::this_thread::sleep_for(timeout);
    return false;
  }
  std::this_thread::sleep_until(next);
  // Late by more than a period (slow consumer): restart the schedule rather than bursting to catch up.
  next = std::max(next + period, PacingClock::now());
  return true;
}

}  // namespace hg::camera
