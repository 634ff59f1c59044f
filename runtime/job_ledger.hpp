// What each process remembers about the job ids it has seen, so that a request repeated with the same job
// id (a retrying DDS writer, an operator pressing twice) is answered with the job's current state instead
// of being acted on again. A job id names one job: once seen it is never started again; the requester
// sends a new id for a new attempt. Bounded: the oldest ids are forgotten past `capacity`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <unordered_map>

namespace hg::runtime {

class JobLedger {
 public:
  struct Entry {
    std::string part_id;
    std::int8_t state = 0;  // job_status_t::STATE_*
    double progress = 0;
    std::string message;
  };

  explicit JobLedger(std::size_t capacity = 4096) : capacity_(capacity) {}

  // nullptr when the id was never seen (or was forgotten).
  const Entry* find(const std::string& job_id) const;
  void set(const std::string& job_id, const std::string& part_id, std::int8_t state, double progress,
           const std::string& message);
  std::size_t size() const { return entries_.size(); }

 private:
  std::size_t capacity_;
  std::unordered_map<std::string, Entry> entries_;
  std::deque<std::string> order_;  // first seen, oldest first
};

// "ACCEPTED" ... "REFUSED" (job_status_t::STATE_*), or the number.
std::string job_state_name(std::int8_t state);
// DONE, FAILED, ABORTED, REFUSED: nothing more happens to the job.
bool job_state_final(std::int8_t state);
// "START", "ABORT", "RESET" (job_request_t::ACTION_*), or the number.
std::string job_action_name(std::int8_t action);
// The text of an answer to a repeated request: "repeated START of job X: it is RUNNING (waypoint 12); nothing done".
std::string repeat_answer(std::int8_t action, const std::string& job_id, const JobLedger::Entry& entry);

}  // namespace hg::runtime
