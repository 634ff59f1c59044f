#include "path_planner/path_planner.hpp"

#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <optional>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "hullgrind/robot_status_t.hpp"
#include "path_planner/delivery.hpp"
#include "path_planner/io.hpp"
#include "runtime/channels.hpp"
#include "jobs/job_ledger.hpp"

namespace hg::path_planner {

using runtime::Level;
using runtime::logf;

runtime::ProcessInfo process_info() {
  std::vector<runtime::Param> params = planner_params();
  params.push_back(runtime::text_param(
      "jobs-dir", "",
      "the job history (hg-job-recorder's --dir): a START of a job it holds as ended or started before is "
      "answered with that state and never planned; \"\" = off"));
  return {
      "hg-path-planner",
      "Outline (HG_OUTLINE) + job request (HG_JOB_REQUEST) -> grind path in the robot's base frame (HG_GRIND_PATH).",
      "Subscribes HG_OUTLINE, HG_JOB_REQUEST, HG_JOB_STATUS (the robot bridge's word on its paths) and\n"
      "HG_ROBOT_STATUS. On a job request with action START it reports PLANNING on HG_JOB_STATUS, plans on the\n"
      "latest outline if it is fresh (outline-max-age) or else on the next one, reports PLANNED and publishes\n"
      "grind_path_t on HG_GRIND_PATH, or FAILED with the reason (outline with an error status, bad outline,\n"
      "hole too small for the tool, validation). Zero-valued job parameters take the configured defaults below.\n"
      "The cell file (--cell, docs/cell.md) gives the camera-to-base calibration, the tool (a job's default\n"
      "tool_radius and tilt), the limits every path is validated against and home; a value given here that\n"
      "contradicts it stops the start (exit 2), a job asking for more (a speed above max-speed, a tool larger\n"
      "than the cell's) is FAILED. The path starts at the loop point nearest to the robot's TCP\n"
      "(HG_ROBOT_STATUS) or to the cell's home until it is heard. The path (revision 1) carries the coverage of\n"
      "every outline loop and every stretch it leaves unground (small-hole skip: a skipped hole is such a\n"
      "stretch; the robot bridge then waits for an operator's approval). REPLAN, while the robot bridge holds\n"
      "the job AWAITING_APPROVAL: planned again on the same outline with the REPLAN's parameters, published as\n"
      "the next revision. A path (each revision) the robot bridge has not acknowledged (a status of the job\n"
      "from it with that revision, or the job's end) is published again, identical, every path-resend-period,\n"
      "at most path-resends times: the bus may lose it. A job id is planned once: a repeated START (or an\n"
      "ABORT) of a job id already seen is answered with the job's state while the planner holds or ended it\n"
      "(PLANNING, FAILED, ABORTED, REFUSED) and changes nothing; once PLANNED the robot bridge answers. QUERY:\n"
      "the last status of each job held (answer=true). See docs/path_planner.md.",
      std::move(params)};
}

namespace {

// The wire's direction constants are runtime/quantities.hpp's Direction, value for value.
static_assert(hullgrind::job_request_t::DIRECTION_CLIMB == std::int8_t(Direction::Climb) &&
              hullgrind::job_request_t::DIRECTION_CONVENTIONAL == std::int8_t(Direction::Conventional));

JobParams job_params(const hullgrind::job_request_t& req) {
  JobParams jp;
  quantity::for_each_job_quantity([](const quantity::Quantity&, double& to, double from) { to = from; }, jp, req);
  jp.direction = job::direction_from_wire(req.direction).value_or(Direction::Climb);
  jp.flipped = req.flipped;
  return jp;
}

std::string planned_message(const PlanResult& r, std::int32_t revision) {
  std::string msg = std::to_string(r.path.size()) + " waypoints, " + std::to_string(r.loops_planned) +
                    " loops, planned in " + std::to_string(r.seconds * 1e3) + " ms";
  if (revision > 1) msg = "revision " + std::to_string(revision) + ": " + msg;
  if (r.slowed > 0) msg += ", " + std::to_string(r.slowed) + " speeds lowered at corners (max_accel)";
  for (const std::string& w : r.warnings) msg += "; warning: " + w;
  return msg;
}

constexpr std::size_t kJobsKept = 32;  // outlines kept for REPLAN, newest jobs

class Planner {
 public:
  Planner(runtime::Node& node)
      : node_(node),
        cfg_(config_from(lookup_from(node))),
        delivery_(node.params().number("path-resend-period"), int(node.params().integer("path-resends"))) {
    max_age_ = node.params().number("outline-max-age");
    timeout_ = node.params().number("outline-timeout");
    jobs_dir_ = node.params().text("jobs-dir");
  }

  void on_outline(const hullgrind::outline_t& m, const runtime::Delivery& d) {
    latest_ = m;
    latest_utime_ = d.recv_utime;
    if (m.status != hullgrind::outline_t::STATUS_OK)
      logf(Level::Info, "outline %lld has error status %d: %s", (long long)m.header.seq, int(m.status),
           m.error_text.c_str());
    if (pending_) plan_now();
  }

  void on_request(const hullgrind::job_request_t& r, const runtime::Delivery& d) {
    using R = hullgrind::job_request_t;
    if (r.action == R::ACTION_QUERY) return answer_query(r);
    if (const jobs::JobLedger::Entry* e = ledger_.find(r.job_id)) return on_seen(r, *e);
    if (r.action != R::ACTION_START) return;  // ABORT of a job never seen, RESET, APPROVE, ...: not ours
    using S = hullgrind::job_status_t;
    if (r.job_id.empty()) return status(r, S::STATE_REFUSED, 0, "refused: empty job id");
    if (const auto rec = jobs::recorded_job(jobs_dir_, r.job_id);
        jobs::recorded_before(rec, d.recv_utime) && rec->state >= 0)
      return status(r, rec->state, 0,
                    "START of job " + r.job_id + ": the job history holds it as " + jobs::job_state_name(rec->state) +
                        (rec->ended ? "" : " (started before)") +
                        (rec->message.empty() ? "" : " (" + rec->message + ")") + "; not planned again",
                    false);
    if (pending_) return status(r, S::STATE_REFUSED, 0, "planner busy with job '" + pending_->job_id + "'");
    pending_ = r;
    pending_since_ = runtime::now_utime();
    status(r, S::STATE_PLANNING, 0, latest_fresh() ? "planning on the latest outline" : "waiting for an outline");
    if (latest_fresh()) plan_now();
  }

  // The robot bridge's word on a job planned here: REPLAN is allowed while it holds the plan for approval.
  void on_status(const hullgrind::job_status_t& s, const runtime::Delivery&) {
    delivery_.heard(s);  // answers too: "ignored: it is ..." says the bridge has the path
    if (s.answer || s.source == node_.name()) return;
    auto it = jobs_.find(s.job_id);
    if (it != jobs_.end()) it->second.awaiting = s.state == hullgrind::job_status_t::STATE_AWAITING_APPROVAL;
  }

  void on_robot(const hullgrind::robot_status_t& s, const runtime::Delivery&) {
    if (s.mode == hullgrind::robot_status_t::MODE_DISCONNECTED) return;
    const Vec3 p(s.tcp_position[0], s.tcp_position[1], s.tcp_position[2]);
    if (p.allFinite()) robot_ = p;
  }

  void tick() {
    if (pending_ && double(runtime::now_utime() - pending_since_) * 1e-6 > timeout_) {
      status(*pending_, hullgrind::job_status_t::STATE_FAILED, 0,
             "no outline received within " + std::to_string(timeout_) + " s");
      pending_.reset();
    }
    delivery_.resend_due(runtime::now_utime(), [this](const hullgrind::grind_path_t& g) { resend(g); });
  }

 private:
  // What REPLAN needs of a planned job: the outline it was planned on and the revision published last.
  struct Planned {
    hullgrind::outline_t outline;
    std::int32_t revision = 1;
    bool awaiting = false;  // the robot bridge said AWAITING_APPROVAL last
  };

  bool latest_fresh() const { return latest_ && double(runtime::now_utime() - latest_utime_) * 1e-6 <= max_age_; }

  // A job id seen before: the ABORT of the pending job acts, a REPLAN of a plan awaiting approval is planned;
  // otherwise answered while the planner holds or ended the job (once PLANNED the robot bridge answers).
  void on_seen(const hullgrind::job_request_t& r, const jobs::JobLedger::Entry& e) {
    using S = hullgrind::job_status_t;
    using R = hullgrind::job_request_t;
    if (r.action == R::ACTION_ABORT && pending_ && pending_->job_id == r.job_id) {
      status(*pending_, S::STATE_ABORTED, 0, "aborted before planning finished");
      pending_.reset();
    } else if (r.action == R::ACTION_REPLAN && e.state == S::STATE_PLANNED) {
      replan(r);
    } else if (e.state != S::STATE_PLANNED) {
      status(r, e.state, e.progress, jobs::repeat_answer(r.action, r.job_id, e), false);
    }
  }

  void answer_query(const hullgrind::job_request_t& r) {
    for (const std::string& id : ledger_.ids()) {
      if (!r.job_id.empty() && id != r.job_id) continue;
      const jobs::JobLedger::Entry* e = ledger_.find(id);
      if (!e || e->status.job_id.empty()) continue;
      hullgrind::job_status_t s = e->status;
      s.answer = true;
      node_.publish(channels::kJobStatus, s);
    }
  }

  // Publishes a status of the job; `record` false for an answer (answer = true; the ledger keeps the state).
  void status(const hullgrind::job_request_t& r, std::int8_t state, double progress, const std::string& msg,
              bool record = true, const hullgrind::grind_path_t* path = nullptr) {
    hullgrind::job_status_t s{};
    s.job_id = r.job_id;
    s.part_id = r.part_id;
    if (const jobs::JobLedger::Entry* e = ledger_.find(r.job_id); e && s.part_id.empty()) s.part_id = e->part_id;
    s.source = node_.name();
    s.state = state;
    s.progress = progress;
    s.message = msg;
    s.answer = !record;
    if (path) {
      s.plan_revision = path->revision;
      s.unground = path->unreached;
      s.num_unground = std::int32_t(s.unground.size());
    }
    if (record && !r.job_id.empty()) ledger_.set(s);
    node_.publish(channels::kJobStatus, s);
    if (state == hullgrind::job_status_t::STATE_FAILED || state == hullgrind::job_status_t::STATE_REFUSED)
      logf(Level::Warn, "job '%s': %s", r.job_id.c_str(), msg.c_str());
  }

  PlanResult plan_on(const hullgrind::outline_t& m, const hullgrind::job_request_t& req) {
    PlanResult r;
    PlannerConfig cfg = cfg_;  // eye-in-hand: placed with this outline's flange pose
    if (std::string why = place_outline(m, cfg); !why.empty()) {
      r.reason = std::move(why);
      return r;
    }
    if (!job::direction_from_wire(req.direction)) {
      r.reason = "direction " + std::to_string(int(req.direction)) + " is not CLIMB (0) or CONVENTIONAL (1)";
      return r;
    }
    try {
      r = plan(from_lcm(m), job_params(req), cfg, robot_);
    } catch (const std::exception& e) {  // never let one job's input take the process down
      r.ok = false;
      r.reason = std::string("internal error: ") + e.what();
    }
    node_.set_latency(r.seconds);
    return r;
  }

  // PLANNED first, then the path: the robot bridge's answer to the path (AWAITING_APPROVAL, APPROVED)
  // always comes after PLANNED on the bus.
  void publish_plan(const hullgrind::job_request_t& req, const PlanResult& r, const hullgrind::outline_t& m,
                    std::int32_t revision) {
    hullgrind::grind_path_t g = to_lcm(r, req.job_id, m.header.seq, cfg_.base_frame, m.header.utime, revision);
    const std::string msg = planned_message(r, revision);
    status(req, hullgrind::job_status_t::STATE_PLANNED, 1, msg, true, &g);
    node_.publish(channels::kGrindPath, g);
    delivery_.published(g, runtime::now_utime());
    logf(Level::Info, "job '%s': %s", req.job_id.c_str(), msg.c_str());
  }

  // A copy as first published (its header.seq too, which Node::publish would renumber): receivers can tell it
  // is the same message.
  void resend(const hullgrind::grind_path_t& g) {
    if (node_.lcm().publish(channels::kGrindPath, &g) != 0) {
      logf(Level::Error, "publish on %s failed", channels::kGrindPath);
      return;
    }
    ++node_.counters().published;
  }

  void plan_now() {
    const hullgrind::job_request_t req = *pending_;
    pending_.reset();
    const hullgrind::outline_t& m = *latest_;
    if (m.status != hullgrind::outline_t::STATUS_OK) {
      status(req, hullgrind::job_status_t::STATE_FAILED, 0,
             "outline " + std::to_string(m.header.seq) + " has error status " + std::to_string(int(m.status)) + ": " +
                 (m.error_text.empty() ? std::string("(no reason given)") : m.error_text));
      return;
    }
    if (m.quality == hullgrind::outline_t::QUALITY_POOR) {  // no plan on a guessed edge (issue 23)
      status(req, hullgrind::job_status_t::STATE_NEEDS_RESCAN, 0,
             "outline " + std::to_string(m.header.seq) + ": scan quality poor, rescan: " +
                 (m.quality_text.empty() ? std::string("(no reason given)") : m.quality_text));
      return;
    }
    const PlanResult r = plan_on(m, req);
    if (!r.ok) return status(req, hullgrind::job_status_t::STATE_FAILED, 0, r.reason);
    remember(req.job_id, m);
    publish_plan(req, r, m, 1);
  }

  void remember(const std::string& job_id, const hullgrind::outline_t& m) {
    if (jobs_.emplace(job_id, Planned{m}).second) order_.push_back(job_id);
    while (order_.size() > kJobsKept) {
      jobs_.erase(order_.front());
      order_.pop_front();
    }
  }

  // REPLAN: the same outline, the request's parameters, the next revision; only while the bridge holds the
  // plan for approval. A plan that fails leaves the held revision as it is (answered, nothing recorded).
  void replan(const hullgrind::job_request_t& req) {
    using S = hullgrind::job_status_t;
    auto it = jobs_.find(req.job_id);
    if (it == jobs_.end() || !it->second.awaiting) {
      const std::string why = it == jobs_.end() ? "its outline is no longer kept" : "it is not awaiting approval";
      return status(req, S::STATE_PLANNED, 1, "REPLAN of job " + req.job_id + " refused: " + why, false);
    }
    const PlanResult r = plan_on(it->second.outline, req);
    if (!r.ok)
      return status(req, S::STATE_AWAITING_APPROVAL, 0,
                    "REPLAN of job " + req.job_id + " failed: " + r.reason + "; revision " +
                        std::to_string(it->second.revision) + " still awaits approval",
                    false);
    it->second.awaiting = false;
    publish_plan(req, r, it->second.outline, ++it->second.revision);
  }

  runtime::Node& node_;
  PlannerConfig cfg_;
  double max_age_ = 2, timeout_ = 10;
  std::string jobs_dir_;
  std::optional<hullgrind::outline_t> latest_;
  std::int64_t latest_utime_ = 0;
  std::optional<hullgrind::job_request_t> pending_;
  std::int64_t pending_since_ = 0;
  std::optional<Vec3> robot_;
  jobs::JobLedger ledger_;  // every job id seen, with the planner's last word on it
  std::map<std::string, Planned> jobs_;
  std::deque<std::string> order_;  // of jobs_, oldest first
  PathDelivery delivery_;          // the published paths until the robot bridge acknowledges them
};

}  // namespace

void attach(runtime::Node& node) {
  auto p = std::make_shared<Planner>(node);
  node.subscribe<hullgrind::outline_t>(
      channels::kOutline, [p](const hullgrind::outline_t& m, const runtime::Delivery& d) { p->on_outline(m, d); });
  node.subscribe<hullgrind::job_request_t>(
      channels::kJobRequest,
      [p](const hullgrind::job_request_t& m, const runtime::Delivery& d) { p->on_request(m, d); });
  node.subscribe<hullgrind::job_status_t>(
      channels::kJobStatus, [p](const hullgrind::job_status_t& m, const runtime::Delivery& d) { p->on_status(m, d); });
  node.subscribe<hullgrind::robot_status_t>(
      channels::kRobotStatus,
      [p](const hullgrind::robot_status_t& m, const runtime::Delivery& d) { p->on_robot(m, d); });
  node.every(std::chrono::milliseconds(100), [p] { p->tick(); });
}

}  // namespace hg::path_planner
