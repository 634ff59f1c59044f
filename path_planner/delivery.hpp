// The delivery of the planner's paths on a lossy bus: a path the robot bridge has not acknowledged is
// published again, identical, every `period` seconds, at most `resends` times (docs/path_planner.md, "Path
// delivery"). A path is ~50 UDP fragments on LCM's multicast, and a receiver whose socket buffer overflows
// under the plate clouds loses one now and then; without a copy its job waits for the robot bridge's path
// timeout and fails.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/job_status_t.hpp"

namespace hg::path_planner {

class PathDelivery {
 public:
  using Send = std::function<void(const hullgrind::grind_path_t&)>;
  PathDelivery(double period, int resends) : period_(period), resends_(resends) {}

  // A path as it was published at `now` (utime): held until acknowledged; it replaces an older revision of
  // its job. With resends 0 nothing is held.
  void published(const hullgrind::grind_path_t& path, std::int64_t now);
  // A status heard on HG_JOB_STATUS: the held path of its job is acknowledged by any status of the robot
  // bridge with plan_revision >= the path's revision or past taking paths (APPROVED, RUNNING), and by any
  // terminal state of the job from anyone.
  void heard(const hullgrind::job_status_t& s);
  // Sends (with `send`) every held path due at `now`. A path not acknowledged one period after its last
  // copy (`resends` copies) is dropped with a warning: the robot bridge's path timeout then ends its job.
  void resend_due(std::int64_t now, const Send& send);

  std::size_t held() const { return held_.size(); }
  std::int64_t resent() const { return resent_; }  // copies sent since the start

 private:
  struct Held {
    hullgrind::grind_path_t path;
    std::int64_t published = 0;  // utime of the first publication
    std::int64_t due = 0;        // utime of the next copy
    int sent = 0;                // copies sent so far
  };
  double period_;
  int resends_;
  std::map<std::string, Held> held_;  // by job id: its newest revision
  std::int64_t resent_ = 0;
};

}  // namespace hg::path_planner
