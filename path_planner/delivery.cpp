#include "path_planner/delivery.hpp"

#include "jobs/job_ledger.hpp"
#include "runtime/log.hpp"

namespace hg::path_planner {

using runtime::Level;
using runtime::logf;
using S = hullgrind::job_status_t;

namespace {
// The robot bridge holds one job at a time, so a few paths are held at most; this bounds the memory if
// no robot bridge is on the bus and jobs come faster than `resends` x `period`.
constexpr std::size_t kPathsHeld = 32;
}  // namespace

void PathDelivery::published(const hullgrind::grind_path_t& path, std::int64_t now) {
  if (resends_ <= 0) return;
  held_[path.job_id] = Held{path, now, now + std::int64_t(period_ * 1e6), 0};
  while (held_.size() > kPathsHeld) {
    auto oldest = held_.begin();
    for (auto it = held_.begin(); it != held_.end(); ++it)
      if (it->second.published < oldest->second.published) oldest = it;
    logf(Level::Warn, "job '%s': path revision %d no longer re-sent: %zu newer paths unacknowledged",
         oldest->first.c_str(), int(oldest->second.path.revision), kPathsHeld);
    held_.erase(oldest);
  }
}

void PathDelivery::heard(const S& s) {
  auto it = held_.find(s.job_id);
  if (it == held_.end()) return;
  const bool bridge = s.source == "hg-robot-bridge" && (s.plan_revision >= it->second.path.revision ||
                                                        s.state == S::STATE_APPROVED || s.state == S::STATE_RUNNING);
  if (!bridge && !jobs::job_state_final(s.state)) return;
  if (it->second.sent > 0)
    logf(Level::Info, "job '%s': path revision %d acknowledged (%s, %s) after %d re-sends", s.job_id.c_str(),
         int(it->second.path.revision), s.source.c_str(), jobs::job_state_name(s.state).c_str(), it->second.sent);
  held_.erase(it);
}

void PathDelivery::resend_due(std::int64_t now, const Send& send) {
  for (auto it = held_.begin(); it != held_.end();) {
    Held& h = it->second;
    if (now < h.due) {
      ++it;
    } else if (h.sent >= resends_) {  // the last copy had its period to be acknowledged too
      logf(Level::Warn,
           "job '%s': path revision %d not acknowledged by the robot bridge in %.1f s (%d re-sends); no more copies",
           it->first.c_str(), int(h.path.revision), double(now - h.published) * 1e-6, h.sent);
      it = held_.erase(it);
    } else {
      send(h.path);
      ++h.sent;
      ++resent_;
      h.due = now + std::int64_t(period_ * 1e6);
      logf(Level::Info,
           "job '%s': path revision %d re-sent (%d of %d): not acknowledged by the robot bridge; %lld re-sends "
           "since the start",
           it->first.c_str(), int(h.path.revision), h.sent, resends_, (long long)resent_);
      ++it;
    }
  }
}

}  // namespace hg::path_planner
