// The job history: one folder per job id under a root directory (make run: out/jobs/), written by one
// process (hg-job-recorder) from what the bus says about the job, so that an operator can tell afterwards
// what the cell did to which part and when (tools/hg-jobs). Layout of ROOT/NAME/ (NAME: job_dir_name):
//   job.json      summary: job id, part, first request, current state, source and reason, times, plan
//                 revision, approval (who, when, revision, excluded loops) or rejection, the unground stretches,
//                 whether it ended (final) or was interrupted; rewritten whole (temporary file + rename)
//   events.jsonl  every request, status, outline and path of the job, one JSON object a line, appended
//                 and flushed as it comes
//   outline.json  the outline the path was planned on (hg-outline's schema, as make run's out/outline.json)
//   path.json     the grind path (the schema of make run's out/path.json)
// A process killed mid-way leaves whole files: a job whose end was not heard is marked "interrupted" with
// its last known state and time when the recorder starts again or stops; a later status still ends it, and
// so does an answer (answer = true) with a terminal state: the recorder asks every process on start (QUERY "")
// for its last status of each job it holds (catch-up: "caught_up" in job.json).
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/outline_t.hpp"

namespace hg::job_recorder {

// The folder name of a job id from the network: [A-Za-z0-9_-] and inner '.' kept, every other byte as %XX
// (so '/', a leading '.', "..", control characters and non-ASCII can never name another place); ids whose
// name would pass 120 characters keep 100 and add "~" and a 64-bit FNV-1a hash of the whole id.
// "" for the empty id (not recorded).
std::string job_dir_name(const std::string& job_id);

// "2026-12-01T10:40:03.123Z" (UTC, milliseconds).
std::string iso_time(std::int64_t utime);

struct RecorderStats {
  std::int64_t records = 0;       // jobs recorded (folders made) by this recorder
  std::int64_t write_errors = 0;  // files that could not be written
  std::int64_t bad_records = 0;   // unreadable job.json files found at start (skipped, left as they are)
  std::int64_t rejected_ids = 0;  // messages with an empty job id
};

class Recorder {
 public:
  // Creates root if needed; marks every record left open by an earlier recorder as interrupted.
  Recorder(std::filesystem::path root, std::int64_t now_utime);

  void on_request(const hullgrind::job_request_t& r, std::int64_t utime);
  void on_status(const hullgrind::job_status_t& s, std::int64_t utime);
  void on_outline(const hullgrind::outline_t& o, std::int64_t utime);
  void on_path(const hullgrind::grind_path_t& p, std::int64_t utime);
  // The recorder is stopping: jobs still open are marked interrupted (a later recorder may still end them).
  void stop(std::int64_t utime);

  const RecorderStats& stats() const { return stats_; }
  const std::filesystem::path& root() const { return root_; }
  std::filesystem::path dir_of(const std::string& job_id) const { return root_ / job_dir_name(job_id); }

 private:
  // nullptr for an id that cannot be recorded (empty) or whose folder cannot be made.
  nlohmann::json* record(const std::string& job_id, std::int64_t utime);
  void append_event(const std::string& job_id, const nlohmann::json& event);
  void save(const std::string& job_id);
  void write_file(const std::filesystem::path& path, const std::string& text);
  void mark_interrupted(nlohmann::json& rec, const std::string& why, std::int64_t utime);
  // A status that is no answer (or an answer that ends the job): state, approval, unground, the end.
  void apply_status(nlohmann::json& rec, const hullgrind::job_status_t& s, std::int64_t utime);
  void load_open_records(std::int64_t now_utime);

  std::filesystem::path root_;
  std::map<std::string, nlohmann::json> records_;  // job.json of the jobs seen (or found open) by this recorder
  std::deque<hullgrind::outline_t> outlines_;      // the latest few, for the path that names one
  RecorderStats stats_;
};

nlohmann::json request_json(const hullgrind::job_request_t& r);

}  // namespace hg::job_recorder
