#include "jobs/job_ledger.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"

namespace hg::jobs {

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

void JobLedger::set(const hullgrind::job_status_t& s) {
  set(s.job_id, s.part_id, s.state, s.progress, s.message);
  if (auto it = entries_.find(s.job_id); it != entries_.end()) {
    it->second.status = s;
    it->second.status.answer = false;
  }
}

namespace {
const char* const kStateNames[] = {"ACCEPTED",   "PLANNING", "PLANNED",     "RUNNING",           "DONE",
                                   "FAILED",     "ABORTED",  "REFUSED",     "AWAITING_APPROVAL", "APPROVED",
                                   "INCOMPLETE", "REJECTED", "NEEDS_RESCAN"};
constexpr int kStates = int(sizeof kStateNames / sizeof kStateNames[0]);
const char* const kActionNames[] = {"START", "ABORT", "RESET", "APPROVE", "REJECT", "REPLAN", "QUERY"};
}  // namespace

std::string job_state_name(std::int8_t state) {
  return state >= 0 && state < kStates ? kStateNames[state] : std::to_string(int(state));
}

int job_state_of_name(const std::string& name) {
  for (int i = 0; i < kStates; ++i)
    if (name == kStateNames[i]) return i;
  return -1;
}

bool job_state_final(std::int8_t state) {
  using S = hullgrind::job_status_t;
  return state == S::STATE_DONE || state == S::STATE_FAILED || state == S::STATE_ABORTED || state == S::STATE_REFUSED ||
         state == S::STATE_INCOMPLETE || state == S::STATE_REJECTED || state == S::STATE_NEEDS_RESCAN;
}

std::string job_action_name(std::int8_t action) {
  return action >= 0 && action < 7 ? kActionNames[action] : std::to_string(int(action));
}

std::string repeat_answer(std::int8_t action, const std::string& job_id, const JobLedger::Entry& entry) {
  return "repeated " + job_action_name(action) + " of job " + job_id + ": it is " + job_state_name(entry.state) +
         (entry.message.empty() ? "" : " (" + entry.message + ")") + "; nothing done";
}

namespace {

constexpr std::size_t kMaxName = 120, kKeptPrefix = 100;

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

bool plain(unsigned char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

}  // namespace

std::string job_dir_name(const std::string& job_id) {
  if (job_id.empty()) return "";
  std::string name;
  for (std::size_t i = 0; i < job_id.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(job_id[i]);
    if (plain(c) || (c == '.' && i > 0)) {
      name += char(c);
    } else {
      char buf[4];
      std::snprintf(buf, sizeof buf, "%%%02X", c);
      name += buf;
    }
  }
  if (name.size() > kMaxName) {
    std::size_t keep = kKeptPrefix;
    while (keep > 0 && name[keep - 1] == '%') --keep;  // never cut an escape in two
    if (keep >= 2 && name[keep - 2] == '%') keep -= 2;
    char buf[24];
    std::snprintf(buf, sizeof buf, "~%016llx", static_cast<unsigned long long>(fnv1a(job_id)));
    name = name.substr(0, keep) + buf;
  }
  return name;
}

std::optional<RecordedJob> recorded_job(const std::string& jobs_dir, const std::string& job_id) {
  if (jobs_dir.empty() || job_id.empty()) return std::nullopt;
  std::ifstream in(std::filesystem::path(jobs_dir) / job_dir_name(job_id) / "job.json", std::ios::binary);
  if (!in) return std::nullopt;
  std::stringstream ss;
  ss << in.rdbuf();
  const nlohmann::json rec = nlohmann::json::parse(ss.str(), nullptr, false);
  if (rec.is_discarded() || !rec.is_object() || rec.value("job_id", std::string()) != job_id) return std::nullopt;
  RecordedJob job;
  job.state = std::int8_t(job_state_of_name(rec.value("state", std::string())));
  job.ended = rec.value("final", false);
  job.message = rec.value(job.ended ? "reason" : "message", std::string());
  job.requested_utime = rec.value("requested_utime", std::int64_t(0));
  return job;
}

bool recorded_before(const std::optional<RecordedJob>& job, std::int64_t now_utime) {
  if (!job) return false;
  return job->ended || (job->requested_utime > 0 && job->requested_utime < now_utime - 1000000);
}

}  // namespace hg::jobs
