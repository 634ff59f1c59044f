// A recorded pipeline run, read back from an LCM log: the messages of one job, in the order the bus saw
// them, with the time each was logged.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"

namespace hg::overview {

template <class T>
struct Logged {
  T msg;
  std::int64_t log_utime = 0;  // when lcm-logger received it
};

// A plate cloud's header and where its event starts in the log. A long run's log holds thousands of clouds
// of up to tens of MB each, and a job needs one of them: trace_job reads that one again.
struct CloudRef {
  hullgrind::header_t header;
  std::int64_t offset = 0;  // byte offset of the event in the log file
};

struct RunLog {
  std::string path;
  std::vector<Logged<CloudRef>> clouds;  // every cloud that decodes, by header
  std::vector<Logged<hullgrind::outline_t>> outlines;
  std::vector<Logged<hullgrind::grind_path_t>> paths;
  std::vector<Logged<hullgrind::job_request_t>> requests;
  std::vector<Logged<hullgrind::job_status_t>> statuses;
  std::size_t events = 0, undecodable = 0;
};

// Throws std::runtime_error naming the file when it cannot be read.
RunLog read_run_log(const std::string& path);

// The messages that made one job: its request, the path, the outline it was planned on, the cloud that
// outline came from (read again from the log file), and the job's statuses. Empty job_id: the last START
// request in the log.
struct JobTrace {
  std::string job_id;
  std::optional<Logged<hullgrind::job_request_t>> request;
  std::optional<Logged<hullgrind::grind_path_t>> path;
  std::optional<Logged<hullgrind::outline_t>> outline;
  std::optional<Logged<hullgrind::plate_cloud_t>> cloud;
  std::vector<Logged<hullgrind::job_status_t>> statuses;
  // The last status that ends the job (DONE, FAILED, ABORTED, REFUSED), if any.
  std::optional<Logged<hullgrind::job_status_t>> final_status;
};
JobTrace trace_job(const RunLog& log, const std::string& job_id = "");

}  // namespace hg::overview
