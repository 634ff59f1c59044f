#include "tools/overview/run_log.hpp"

#include "jobs/job_ledger.hpp"
#include "runtime/channels.hpp"

#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>

namespace hg::overview {
namespace {

template <class T>
bool decode(const lcm::LogEvent* e, std::vector<Logged<T>>& into) {
  T msg;
  int used = -1;
  try {
    used = msg.decode(e->data, 0, int(e->datalen));
  } catch (const std::exception&) {
    used = -1;
  }
  if (used != int(e->datalen)) return false;
  into.push_back({std::move(msg), e->timestamp});
  return true;
}

// A cloud is decoded whole (so that one that does not decode is counted as before) but kept as its header
// and offset: the log may hold more clouds than memory.
bool decode_cloud(const lcm::LogEvent* e, std::int64_t offset, std::vector<Logged<CloudRef>>& into) {
  std::vector<Logged<hullgrind::plate_cloud_t>> one;
  if (!decode(e, one)) return false;
  into.push_back({CloudRef{one[0].msg.header, offset}, e->timestamp});
  return true;
}

// The cloud whose event starts at `offset` of the log file; nullopt if it cannot be read again.
std::optional<Logged<hullgrind::plate_cloud_t>> read_cloud(const std::string& path, std::int64_t offset) {
  lcm::LogFile file(path, "r");
  std::vector<Logged<hullgrind::plate_cloud_t>> one;
  if (!file.good() || fseeko(file.getFilePtr(), offset, SEEK_SET) != 0) return std::nullopt;
  const lcm::LogEvent* e = file.readNextEvent();
  if (!e || !decode(e, one)) return std::nullopt;
  return std::move(one[0]);
}

// A status that ends the job: the robot bridge's DONE, any other terminal state from anyone (as the recorder
// and tools/run.sh read it).
bool ends_job(const hullgrind::job_status_t& s) {
  return (s.state == hullgrind::job_status_t::STATE_DONE && s.source == "hg-robot-bridge") ||
         (jobs::job_state_final(s.state) && s.state != hullgrind::job_status_t::STATE_DONE);
}

// The planner's copy of a path the robot bridge had not acknowledged (docs/path_planner.md, "Path delivery"):
// the same message, header.seq included; a second planning of the job has its own compute time.
bool same_path(const hullgrind::grind_path_t& a, const hullgrind::grind_path_t& b) {
  return a.header.seq == b.header.seq && a.header.utime == b.header.utime && a.revision == b.revision &&
         a.compute_time == b.compute_time;
}

}  // namespace

RunLog read_run_log(const std::string& path) {
  lcm::LogFile file(path, "r");
  if (!file.good()) throw std::runtime_error(path + ": cannot open the LCM log");
  RunLog log;
  log.path = path;
  for (std::int64_t offset = ftello(file.getFilePtr()); const lcm::LogEvent* e = file.readNextEvent();
       offset = ftello(file.getFilePtr())) {
    ++log.events;
    bool ok = true;
    if (e->channel == channels::kPlateCloud) ok = decode_cloud(e, offset, log.clouds);
    else if (e->channel == channels::kOutline)
      ok = decode(e, log.outlines);
    else if (e->channel == channels::kGrindPath)
      ok = decode(e, log.paths);
    else if (e->channel == channels::kJobRequest)
      ok = decode(e, log.requests);
    else if (e->channel == channels::kJobStatus)
      ok = decode(e, log.statuses);
    if (!ok) ++log.undecodable;
  }
  return log;
}

JobTrace trace_job(const RunLog& log, const std::string& job_id) {
  JobTrace t;
  t.job_id = job_id;
  for (const auto& r : log.requests)
    if (r.msg.action == hullgrind::job_request_t::ACTION_START && (job_id.empty() || r.msg.job_id == job_id)) {
      t.request = r;
      t.job_id = r.msg.job_id;
    }
  if (t.job_id.empty()) return t;
  for (const auto& p : log.paths)
    // The last plan, if a restart planned it twice; a copy keeps the time the path first came.
    if (p.msg.job_id == t.job_id && !(t.path && same_path(t.path->msg, p.msg))) t.path = p;
  // The outline the path was planned on: the last one with that seq logged before the path.
  if (t.path)
    for (const auto& o : log.outlines)
      if (o.msg.header.seq == t.path->msg.outline_seq && o.log_utime <= t.path->log_utime) t.outline = o;
  const Logged<CloudRef>* cloud = nullptr;
  if (t.outline)
    for (const auto& c : log.clouds)
      if (c.msg.header.seq == t.outline->msg.cloud_seq && c.log_utime <= t.outline->log_utime) cloud = &c;
  if (cloud) t.cloud = read_cloud(log.path, cloud->msg.offset);
  for (const auto& s : log.statuses)
    if (s.msg.job_id == t.job_id) {
      t.statuses.push_back(s);
      // The first end the bus said; an answer (a repeat's, a QUERY's) only when nothing else ended the job.
      const bool have_end = t.final_status && !t.final_status->msg.answer;
      if (ends_job(s.msg) && !have_end && (!t.final_status || !s.msg.answer)) t.final_status = s;
    }
  return t;
}

}  // namespace hg::overview
