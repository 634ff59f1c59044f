#include "job_recorder/recorder.hpp"

#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>

#include "jobs/job_ledger.hpp"
#include "runtime/log.hpp"
#include "path_file/path_file.hpp"
#include "runtime/quantities.hpp"
#include "outline_io/outline_message.hpp"

namespace hg::job_recorder {

namespace fs = std::filesystem;
using nlohmann::json;
using runtime::Level;
using runtime::logf;

namespace {

constexpr std::size_t kOutlinesKept = 8;
constexpr std::size_t kRecordsInMemory = 1024;  // beyond this, ended records are dropped (reloaded from disk)

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Who ends a job: the robot bridge's DONE, or any other terminal state (FAILED, ABORTED, REFUSED, INCOMPLETE,
// REJECTED, NEEDS_RESCAN) from anyone (as tools/run.sh reads it).
bool ends_job(const hullgrind::job_status_t& s) {
  return (s.state == hullgrind::job_status_t::STATE_DONE && s.source == "hg-robot-bridge") ||
         (jobs::job_state_final(s.state) && s.state != hullgrind::job_status_t::STATE_DONE);
}

json stretch_json(const hullgrind::edge_stretch_t& e) {
  static const char* causes[] = {"UNREACHED", "TOO_SMALL", "CORNER", "EXCLUDED", "NOT_RUN"};
  return {{"loop", e.loop_index},
          {"hole", e.hole},
          {"start", e.start},
          {"length", e.length},
          {"cause", e.cause >= 0 && e.cause < 5 ? causes[e.cause] : std::to_string(int(e.cause))},
          {"reason", e.reason}};
}

json unground_json(const hullgrind::job_status_t& s) {
  json out = json::array();
  for (const auto& e : s.unground) out.push_back(stretch_json(e));
  return out;
}

// The status as an event line: what it said, and the approval and unground fields when it has them.
json status_event(const hullgrind::job_status_t& s, std::int64_t utime) {
  json ev = {{"time", iso_time(utime)},
             {"utime", utime},
             {"event", "status"},
             {"source", s.source},
             {"state", jobs::job_state_name(s.state)},
             {"progress", s.progress},
             {"message", s.message}};
  if (s.answer) ev["answer"] = true;
  if (s.plan_revision > 0) ev["plan_revision"] = s.plan_revision;
  if (!s.actor.empty()) ev["actor"] = s.actor;
  if (!s.excluded_loops.empty()) ev["excluded_loops"] = s.excluded_loops;
  if (!s.unground.empty()) ev["unground"] = unground_json(s);
  return ev;
}

}  // namespace

std::string job_dir_name(const std::string& job_id) { return jobs::job_dir_name(job_id); }

std::string iso_time(std::int64_t utime) {
  const std::time_t secs = static_cast<std::time_t>(utime / 1000000);
  std::tm tm{};
  gmtime_r(&secs, &tm);
  char buf[40];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                tm.tm_hour, tm.tm_min, tm.tm_sec, int((utime % 1000000) / 1000));
  return buf;
}

json request_json(const hullgrind::job_request_t& r) {
  const auto direction = job::direction_from_wire(r.direction);
  json j = {{"action", jobs::job_action_name(r.action)},
            {"job_id", r.job_id},
            {"part_id", r.part_id},
            {"direction", direction ? job::direction_name(*direction) : "unknown"},
            {"flipped", r.flipped},
            {"actor", r.actor},
            {"plan_revision", r.plan_revision},
            {"excluded_loops", r.excluded_loops}};
  quantity::for_each_job_quantity([&j](const quantity::Quantity& q, double v) { j[q.name] = v; }, r);
  return j;
}

Recorder::Recorder(fs::path root, std::int64_t now_utime) : root_(std::move(root)) {
  fs::create_directories(root_);
  load_open_records(now_utime);
}

void Recorder::load_open_records(std::int64_t now_utime) {
  for (const auto& entry : fs::directory_iterator(root_)) {
    const fs::path file = entry.path() / "job.json";
    if (!entry.is_directory() || !fs::exists(file)) continue;
    json rec = json::parse(read_text(file), nullptr, false);
    if (rec.is_discarded() || !rec.is_object() || !rec.contains("job_id") || !rec["job_id"].is_string() ||
        job_dir_name(rec["job_id"].get<std::string>()) != entry.path().filename().string()) {
      ++stats_.bad_records;
      logf(Level::Warn, "%s: not a job record; skipped", file.c_str());
      continue;
    }
    if (rec.value("final", false) || rec.contains("interrupted")) continue;
    const std::string id = rec["job_id"];
    records_[id] = std::move(rec);
    mark_interrupted(records_[id], "hg-job-recorder was not running when the job ended (or it has not ended)",
                     now_utime);
  }
}

json* Recorder::record(const std::string& job_id, std::int64_t utime) {
  if (job_id.empty()) {
    ++stats_.rejected_ids;
    return nullptr;
  }
  if (auto it = records_.find(job_id); it != records_.end()) return &it->second;
  const fs::path dir = dir_of(job_id);
  std::error_code ec;
  if (fs::exists(dir / "job.json", ec)) {  // recorded before (an ended job dropped from memory, or before a restart)
    json rec = json::parse(read_text(dir / "job.json"), nullptr, false);
    if (!rec.is_discarded() && rec.is_object()) return &(records_[job_id] = std::move(rec));
  }
  fs::create_directories(dir, ec);
  if (ec) {
    ++stats_.write_errors;
    logf(Level::Error, "cannot make %s: %s", dir.c_str(), ec.message().c_str());
    return nullptr;
  }
  if (records_.size() >= kRecordsInMemory)
    std::erase_if(records_, [](const auto& kv) { return kv.second.value("final", false); });
  ++stats_.records;
  return &(records_[job_id] = json{{"job_id", job_id},
                                   {"part_id", ""},
                                   {"created", iso_time(utime)},
                                   {"created_utime", utime},
                                   {"state", "NONE"},
                                   {"final", false},
                                   {"requests", 0}});
}

void Recorder::write_file(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) {
      ++stats_.write_errors;
      logf(Level::Error, "cannot write %s", tmp.c_str());
      return;
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);  // whole or not at all, whenever the process dies
  if (ec) {
    ++stats_.write_errors;
    logf(Level::Error, "cannot rename %s: %s", tmp.c_str(), ec.message().c_str());
  }
}

void Recorder::save(const std::string& job_id) {
  write_file(dir_of(job_id) / "job.json", records_[job_id].dump(1) + "\n");
}

void Recorder::append_event(const std::string& job_id, const json& event) {
  std::ofstream out(dir_of(job_id) / "events.jsonl", std::ios::app);
  out << event.dump() << "\n";
  out.flush();
  if (!out) ++stats_.write_errors;
}

void Recorder::mark_interrupted(json& rec, const std::string& why, std::int64_t utime) {
  rec["interrupted"] = {{"at", iso_time(utime)},
                        {"at_utime", utime},
                        {"why", why},
                        {"last_state", rec.value("state", "NONE")},
                        {"last_update", rec.value("updated", "")}};
  const std::string id = rec["job_id"];
  append_event(id, {{"time", iso_time(utime)}, {"utime", utime}, {"event", "interrupted"}, {"why", why}});
  save(id);
}

void Recorder::on_request(const hullgrind::job_request_t& r, std::int64_t utime) {
  if (r.action == hullgrind::job_request_t::ACTION_QUERY) return;  // asks about jobs; not part of one
  json* rec = record(r.job_id, utime);
  if (!rec) return;
  json req = request_json(r);
  append_event(r.job_id, {{"time", iso_time(utime)}, {"utime", utime}, {"event", "request"}, {"request", req}});
  (*rec)["requests"] = rec->value("requests", 0) + 1;
  if (!rec->contains("request") && r.action == hullgrind::job_request_t::ACTION_START) {
    // the first START says what the job is; repeats and the other actions are events
    (*rec)["request"] = req;
    (*rec)["requested"] = iso_time(utime);
    (*rec)["requested_utime"] = utime;
    if (!r.part_id.empty()) (*rec)["part_id"] = r.part_id;
  }
  save(r.job_id);
}

void Recorder::on_status(const hullgrind::job_status_t& s, std::int64_t utime) {
  json* rec = record(s.job_id, utime);
  if (!rec) return;
  append_event(s.job_id, status_event(s, utime));
  if ((*rec)["part_id"] == "" && !s.part_id.empty()) (*rec)["part_id"] = s.part_id;
  if (rec->value("final", false)) return save(s.job_id);  // the first end stands; later words are events
  // An answer (to a QUERY or a repeat) changes nothing, unless it tells the end of a job this record does not
  // hold as ended: the end was published while the recorder was down (catch-up after a restart).
  if (s.answer && !ends_job(s)) return save(s.job_id);
  if (s.answer) (*rec)["caught_up"] = {{"at", iso_time(utime)}, {"source", s.source}};
  // A status after an interruption: the job went on (the recorder was the one that died).
  if (rec->contains("interrupted")) {
    (*rec)["resumed_after_interruption"] = (*rec)["interrupted"];
    rec->erase("interrupted");
  }
  apply_status(*rec, s, utime);
  save(s.job_id);
}

void Recorder::apply_status(json& rec, const hullgrind::job_status_t& s, std::int64_t utime) {
  using S = hullgrind::job_status_t;
  const std::string state = jobs::job_state_name(s.state);
  const bool progress_only = s.state == S::STATE_RUNNING && rec["state"] == "RUNNING";
  rec["state"] = state;
  rec["source"] = s.source;
  rec["progress"] = s.progress;
  if (!progress_only || s.progress >= 1) rec["message"] = s.message;
  rec["updated"] = iso_time(utime);
  rec["updated_utime"] = utime;
  if (s.plan_revision > 0) rec["plan_revision"] = s.plan_revision;
  if (s.state == S::STATE_APPROVED)
    rec["approval"] = {{"by", s.actor},
                       {"at", iso_time(utime)},
                       {"at_utime", utime},
                       {"revision", s.plan_revision},
                       {"excluded_loops", s.excluded_loops}};
  if (s.state == S::STATE_REJECTED)
    rec["rejection"] = {{"by", s.actor}, {"at", iso_time(utime)}, {"revision", s.plan_revision}};
  // The plan's gaps while it awaits approval, and the run's unground stretches at the end.
  if (s.state == S::STATE_AWAITING_APPROVAL || jobs::job_state_final(s.state)) rec["unground"] = unground_json(s);
  if (ends_job(s)) {
    rec["final"] = true;
    rec["ended"] = iso_time(utime);
    rec["ended_utime"] = utime;
    rec["reason"] = s.message;
  }
}

void Recorder::on_outline(const hullgrind::outline_t& o, std::int64_t) {
  outlines_.push_back(o);
  if (outlines_.size() > kOutlinesKept) outlines_.pop_front();
}

void Recorder::on_path(const hullgrind::grind_path_t& p, std::int64_t utime) {
  json* rec = record(p.job_id, utime);
  if (!rec) return;
  const fs::path dir = dir_of(p.job_id);
  // A job's path is its first plan, replaced by each newer revision (REPLAN) while the job is not ended.
  const bool kept =
      !rec->contains("path") || (!rec->value("final", false) && p.revision > (*rec)["path"].value("revision", 0));
  append_event(p.job_id, {{"time", iso_time(utime)},
                          {"utime", utime},
                          {"event", "path"},
                          {"waypoints", p.n},
                          {"revision", p.revision},
                          {"outline_seq", p.outline_seq},
                          {"kept", kept}});
  if (!kept) return save(p.job_id);
  write_file(dir / "path.json", path_file::to_text(p));  // the one path file writer
  (*rec)["path"] = {
      {"file", "path.json"},          {"waypoints", p.n}, {"revision", p.revision}, {"outline_seq", p.outline_seq},
      {"tool_radius", p.tool_radius}, {"frame", p.frame}, {"time", iso_time(utime)}};
  for (auto it = outlines_.rbegin(); it != outlines_.rend() && !rec->contains("outline"); ++it) {
    if (it->header.seq != p.outline_seq) continue;
    write_file(dir / "outline.json", outline_io::outline_message_json(*it, nullptr).dump(1) + "\n");
    int holes = 0;
    for (const auto& l : it->loops) holes += l.hole;
    (*rec)["outline"] = {{"file", "outline.json"},
                         {"seq", it->header.seq},
                         {"loops", it->num_loops},
                         {"holes", holes},
                         {"time", iso_time(it->header.utime)}};
    break;
  }
  if (!rec->contains("outline"))
    (*rec)["outline"] = {{"seq", p.outline_seq}, {"missing", "the outline was not heard by the recorder"}};
  save(p.job_id);
}

void Recorder::stop(std::int64_t utime) {
  for (auto& [id, rec] : records_)
    if (!rec.value("final", false) && !rec.contains("interrupted"))
      mark_interrupted(rec, "hg-job-recorder stopped while the job was " + rec.value("state", std::string("NONE")),
                       utime);
}

}  // namespace hg::job_recorder
