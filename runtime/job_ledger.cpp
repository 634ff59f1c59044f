#include "runtime/job_ledger.hpp"

#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"

namespace hg::runtime {

const JobLedger::Entry* JobLedger::find(const std::string& job_id) const {
  auto it = entries_.find(job_id);
  return it == entries_.end() ? nullptr : &it->second;
}

void JobLedger::set(const std::string& job_id, const std::string& part_id, std::int8_t state, double progress,
                    const std::string& message) {
  auto [it, fresh] = entries_.try_emplace(job_id);
  if (fresh) {
    order_.push_back(job_id);
    it->second.part_id = part_id;
  }
  if (!part_id.empty()) it->second.part_id = part_id;
  it->second.state = state;
  it->second.progress = progress;
  it->second.message = message;
  while (entries_.size() > capacity_ && !order_.empty()) {
    entries_.erase(order_.front());
    order_.pop_front();
  }
}

std::string job_state_name(std::int8_t state) {
  static const char* names[] = {"ACCEPTED", "PLANNING", "PLANNED", "RUNNING", "DONE", "FAILED", "ABORTED", "REFUSED"};
  return state >= 0 && state < 8 ? names[state] : std::to_string(int(state));
}

bool job_state_final(std::int8_t state) {
  using S = hullgrind::job_status_t;
  return state == S::STATE_DONE || state == S::STATE_FAILED || state == S::STATE_ABORTED || state == S::STATE_REFUSED;
}

std::string job_action_name(std::int8_t action) {
  using R = hullgrind::job_request_t;
  return action == R::ACTION_START   ? "START"
         : action == R::ACTION_ABORT ? "ABORT"
         : action == R::ACTION_RESET ? "RESET"
                                     : std::to_string(int(action));
}

std::string repeat_answer(std::int8_t action, const std::string& job_id, const JobLedger::Entry& entry) {
  return "repeated " + job_action_name(action) + " of job " + job_id + ": it is " + job_state_name(entry.state) +
         (entry.message.empty() ? "" : " (" + entry.message + ")") + "; nothing done";
}

}  // namespace hg::runtime
