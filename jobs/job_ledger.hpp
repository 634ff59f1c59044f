// What each process remembers about the job ids it has seen, so that a request repeated with the same job
// id (a retrying DDS writer, an operator pressing twice) is answered with the job's current state instead
// of being acted on again. A job id names one job: once seen it is never started again; the requester
// sends a new id for a new attempt. Bounded: the oldest ids are forgotten past `capacity`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "hullgrind/job_status_t.hpp"

namespace hg::jobs {

class JobLedger {
 public:
  struct Entry {
    std::string part_id;
    std::int8_t state = 0;  // job_status_t::STATE_*
    double progress = 0;
    std::string message;
    hullgrind::job_status_t status{};  // the last status published of the job, whole (answers to QUERY)
  };

  explicit JobLedger(std::size_t capacity = 4096) : capacity_(capacity) {}

  // nullptr when the id was never seen (or was forgotten).
  const Entry* find(const std::string& job_id) const;
  void set(const std::string& job_id, const std::string& part_id, std::int8_t state, double progress,
           const std::string& message);
  // The whole status (kept for the answers to QUERY and repeats: revision, actor, exclusions, unground).
  void set(const hullgrind::job_status_t& status);
  std::size_t size() const { return entries_.size(); }
  // The ids held, oldest first.
  const std::deque<std::string>& ids() const { return order_; }

 private:
  std::size_t capacity_;
  std::unordered_map<std::string, Entry> entries_;
  std::deque<std::string> order_;  // first seen, oldest first
};

// "ACCEPTED" ... "NEEDS_RESCAN" (job_status_t::STATE_*), or the number.
std::string job_state_name(std::int8_t state);
// The state of a name job_state_name gives; -1 for any other text.
int job_state_of_name(const std::string& name);
// DONE, FAILED, ABORTED, REFUSED, INCOMPLETE, REJECTED, NEEDS_RESCAN: nothing more happens to the job.
bool job_state_final(std::int8_t state);
// "START", "ABORT", "RESET", "APPROVE", "REJECT", "REPLAN", "QUERY" (job_request_t::ACTION_*), or the number.
std::string job_action_name(std::int8_t action);
// The text of an answer to a repeated request: "repeated START of job X: it is RUNNING (waypoint 12); nothing done".
std::string repeat_answer(std::int8_t action, const std::string& job_id, const JobLedger::Entry& entry);

// The folder name of a job id in the job history (out/jobs/NAME, hg-job-recorder): [A-Za-z0-9_-] and inner '.'
// kept, every other byte as %XX (so '/', a leading '.', "..", control characters and non-ASCII can never name
// another place); ids whose name would pass 120 characters keep 100 and add "~" and a 64-bit FNV-1a hash of the
// whole id. "" for the empty id (not recorded).
std::string job_dir_name(const std::string& job_id);

// What the job history on disk (the recorder's folder, `jobs-dir`) says about a job id: the memory of the
// processes across restarts.
struct RecordedJob {
  std::int8_t state = -1;            // job_status_t::STATE_* of job.json's "state" (-1: none yet)
  bool ended = false;                // job.json's "final"
  std::string message;               // its reason (ended) or last message
  std::int64_t requested_utime = 0;  // when the recorder heard the job's first request (0: none)
};
// std::nullopt when jobs_dir is "" or holds no readable record of the id.
std::optional<RecordedJob> recorded_job(const std::string& jobs_dir, const std::string& job_id);
// True when a START of job_id heard at now_utime must not run: the history holds the job as ended, or as
// requested before (its first request heard more than a second before this one: not the same START).
bool recorded_before(const std::optional<RecordedJob>& job, std::int64_t now_utime);

}  // namespace hg::jobs
