#include "job_recorder/job_recorder.hpp"

#include <chrono>

#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "runtime/channels.hpp"

namespace hg::job_recorder {

runtime::ProcessInfo process_info() {
  return {"hg-job-recorder",
          "Job history: every job's request, outline, path, statuses, final state and reason under --dir/JOB/.",
          "Subscribes HG_JOB_REQUEST, HG_JOB_STATUS, HG_OUTLINE and HG_GRIND_PATH and keeps, per job id, a folder\n"
          "DIR/NAME/ (NAME: the job id with every byte outside [A-Za-z0-9_-] and a leading '.' written %XX):\n"
          "job.json (summary: part, first request, state, source, reason, times; rewritten atomically),\n"
          "events.jsonl (every request and status, appended as they come), outline.json and path.json.\n"
          "A job ends with the robot bridge's DONE or anyone's FAILED/ABORTED/REFUSED/INCOMPLETE/REJECTED/\n"
          "NEEDS_RESCAN; job.json keeps the plan revision, the approval (who, when, excluded loops) and the\n"
          "unground stretches. Jobs still open when the recorder stops, or found open when it starts, are marked\n"
          "\"interrupted\" with the last known state and time; a later status still ends them. On start (and\n"
          "once more a second later) it sends QUERY \"\" on HG_JOB_REQUEST: every process answers its last status\n"
          "of each job it holds, and an answer with a terminal state ends a record not ended (catch-up after a\n"
          "restart). Read the history with tools/hg-jobs list|show.\n"
          "Details: docs/job_recorder.md.",
          {{"dir", "out/jobs", "directory of the job records (made if missing)"}}};
}

std::shared_ptr<Recorder> attach(runtime::Node& node) {
  auto rec = std::make_shared<Recorder>(node.params().text("dir"), runtime::now_utime());
  auto health = [rec, &node] {
    const RecorderStats& s = rec->stats();
    if (s.write_errors > 0)
      node.set_state(hullgrind::heartbeat_t::STATE_DEGRADED,
                     std::to_string(s.write_errors) + " writes failed in " + rec->root().string());
    else
      node.set_state(hullgrind::heartbeat_t::STATE_OK);
  };
  node.subscribe<hullgrind::job_request_t>(
      channels::kJobRequest,
      [rec](const hullgrind::job_request_t& m, const runtime::Delivery& d) { rec->on_request(m, d.recv_utime); });
  node.subscribe<hullgrind::job_status_t>(
      channels::kJobStatus,
      [rec](const hullgrind::job_status_t& m, const runtime::Delivery& d) { rec->on_status(m, d.recv_utime); });
  node.subscribe<hullgrind::outline_t>(
      channels::kOutline,
      [rec](const hullgrind::outline_t& m, const runtime::Delivery& d) { rec->on_outline(m, d.recv_utime); });
  node.subscribe<hullgrind::grind_path_t>(
      channels::kGrindPath,
      [rec](const hullgrind::grind_path_t& m, const runtime::Delivery& d) { rec->on_path(m, d.recv_utime); });
  // Catch-up: what ended while the recorder was down. Asked at once and once more a second later (a
  // process still starting may miss the first).
  auto query = [&node] {
    hullgrind::job_request_t q{};
    q.action = hullgrind::job_request_t::ACTION_QUERY;
    q.actor = "hg-job-recorder";
    node.publish(channels::kJobRequest, q);
  };
  query();
  node.every(std::chrono::milliseconds(1000), [health, query, asked = 1]() mutable {
    health();
    if (asked++ < 2) query();
  });
  health();
  // Destroyed after the loop (runtime::run_process): open jobs end interrupted, with their last known state.
  return std::shared_ptr<Recorder>(rec.get(), [rec](Recorder*) { rec->stop(runtime::now_utime()); });
}

}  // namespace hg::job_recorder
