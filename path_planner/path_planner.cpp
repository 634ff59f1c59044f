#include "path_planner/path_planner.hpp"

#include <cmath>
#include <memory>
#include <optional>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "hullgrind/robot_status_t.hpp"
#include "path_planner/io.hpp"
#include "runtime/channels.hpp"
#include "runtime/job_ledger.hpp"

namespace hg::path_planner {

using runtime::Level;
using runtime::logf;

runtime::ProcessInfo process_info() {
  std::vector<runtime::Param> params = planner_params();
  return {
      "hg-path-planner",
      "Outline (HG_OUTLINE) + job request (HG_JOB_REQUEST) -> grind path in the robot's base frame (HG_GRIND_PATH).",
      "Subscribes HG_OUTLINE, HG_JOB_REQUEST and HG_ROBOT_STATUS. On a job request with action START it\n"
      "reports PLANNING on HG_JOB_STATUS, plans on the latest outline if it is fresh (outline-max-age) or else\n"
      "on the next one, publishes grind_path_t on HG_GRIND_PATH and then PLANNED, or FAILED with the reason\n"
      "(outline with an error status, bad outline, hole too small for the tool, validation). Zero-valued job\n"
      "parameters take the configured defaults below. The cell file (--cell, docs/cell.md) gives the\n"
      "camera-to-base calibration, the tool (the default tool-radius and chamfer-angle), the limits every path\n"
      "is validated against and home; a value given here that contradicts it stops the start (exit 2), a job\n"
      "asking for more (a speed above max-speed, a tool larger than the cell's) is FAILED. The path starts at\n"
      "the loop point nearest to the robot's TCP (HG_ROBOT_STATUS) or to the cell's home until it is heard. A job id is planned once:\n"
      "a repeated START (or an ABORT) of a job id already seen is answered with the job's state while the\n"
      "planner holds or ended it (PLANNING, FAILED, ABORTED, REFUSED) and changes nothing; once PLANNED the\n"
      "robot bridge answers. See docs/path_planner.md.",
      std::move(params)};
}

namespace {

class Planner {
 public:
  Planner(runtime::Node& node) : node_(node), cfg_(config_from(lookup_from(node))) {
    max_age_ = node.param_double("outline-max-age");
    timeout_ = node.param_double("outline-timeout");
  }

  void on_outline(const hullgrind::outline_t& m, const runtime::Delivery& d) {
    latest_ = m;
    latest_utime_ = d.recv_utime;
    if (m.status != hullgrind::outline_t::STATUS_OK)
      logf(Level::Info, "outline %lld has error status %d: %s", (long long)m.header.seq, int(m.status),
           m.error_text.c_str());
    if (pending_) plan_now();
  }

  void on_request(const hullgrind::job_request_t& r, const runtime::Delivery&) {
    using S = hullgrind::job_status_t;
    if (const runtime::JobLedger::Entry* e = ledger_.find(r.job_id)) {
      // Seen before: answer with the job's state while the planner holds it or ended it; once PLANNED the
      // robot bridge holds it and answers. Never planned twice, never aborted twice.
      if (r.action == hullgrind::job_request_t::ACTION_ABORT && pending_ && pending_->job_id == r.job_id) {
        status(*pending_, S::STATE_ABORTED, 0, "aborted before planning finished");
        pending_.reset();
      } else if (e->state != S::STATE_PLANNED) {
        status(r, e->state, e->progress, runtime::repeat_answer(r.action, r.job_id, *e), false);
      }
      return;
    }
    if (r.action != hullgrind::job_request_t::ACTION_START) return;  // ABORT of a job never seen, RESET: not ours
    if (r.job_id.empty()) return status(r, S::STATE_REFUSED, 0, "refused: empty job id");
    if (pending_) return status(r, S::STATE_REFUSED, 0, "planner busy with job '" + pending_->job_id + "'");
    pending_ = r;
    pending_since_ = runtime::now_utime();
    status(r, S::STATE_PLANNING, 0, latest_fresh() ? "planning on the latest outline" : "waiting for an outline");
    if (latest_fresh()) plan_now();
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
  }

 private:
  bool latest_fresh() const { return latest_ && double(runtime::now_utime() - latest_utime_) * 1e-6 <= max_age_; }

  // Publishes a status of the job; `record` false for an answer to a repeat (the ledger keeps the state).
  void status(const hullgrind::job_request_t& r, std::int8_t state, double progress, const std::string& msg,
              bool record = true) {
    if (record && !r.job_id.empty()) ledger_.set(r.job_id, r.part_id, state, progress, msg);
    hullgrind::job_status_t s{};
    s.job_id = r.job_id;
    s.part_id = r.part_id;
    if (const runtime::JobLedger::Entry* e = ledger_.find(r.job_id); e && s.part_id.empty()) s.part_id = e->part_id;
    s.source = node_.name();
    s.state = state;
    s.progress = progress;
    s.message = msg;
    node_.publish(channels::kJobStatus, s);
    if (state == hullgrind::job_status_t::STATE_FAILED || state == hullgrind::job_status_t::STATE_REFUSED)
      logf(Level::Warn, "job '%s': %s", r.job_id.c_str(), msg.c_str());
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
    JobParams jp;
    jp.tool_radius = req.tool_radius;
    jp.chamfer_angle = req.chamfer_angle;
    jp.grind_speed = req.grind_speed;
    jp.travel_speed = req.travel_speed;
    jp.step = req.step;
    jp.safe_height = req.safe_height;
    jp.direction = Direction(req.direction);
    jp.flipped = req.flipped;
    PlannerConfig cfg = cfg_;  // eye-in-hand: placed with this outline's flange pose
    if (const std::string why = place_outline(m, cfg); !why.empty())
      return status(req, hullgrind::job_status_t::STATE_FAILED, 0, why);
    PlanResult r;
    try {
      r = plan(from_lcm(m), jp, cfg, robot_);
    } catch (const std::exception& e) {  // never let one job's input take the process down
      r.ok = false;
      r.reason = std::string("internal error: ") + e.what();
    }
    node_.set_latency(r.seconds);
    if (!r.ok) {
      status(req, hullgrind::job_status_t::STATE_FAILED, 0, r.reason);
      return;
    }
    hullgrind::grind_path_t g = to_lcm(r, req.job_id, m.header.seq, cfg_.base_frame, m.header.utime);
    node_.publish(channels::kGrindPath, g);
    std::string msg = std::to_string(r.path.size()) + " waypoints, " + std::to_string(r.loops_planned) +
                      " loops, planned in " + std::to_string(r.seconds * 1e3) + " ms";
    if (r.slowed > 0) msg += ", " + std::to_string(r.slowed) + " speeds lowered at corners (max_accel)";
    for (const std::string& w : r.warnings) msg += "; warning: " + w;
    status(req, hullgrind::job_status_t::STATE_PLANNED, 1, msg);
    logf(Level::Info, "job '%s': %s", req.job_id.c_str(), msg.c_str());
  }

  runtime::Node& node_;
  PlannerConfig cfg_;
  double max_age_ = 2, timeout_ = 10;
  std::optional<hullgrind::outline_t> latest_;
  std::int64_t latest_utime_ = 0;
  std::optional<hullgrind::job_request_t> pending_;
  std::int64_t pending_since_ = 0;
  std::optional<Vec3> robot_;
  runtime::JobLedger ledger_;  // every job id seen, with the planner's last word on it
};

}  // namespace

void attach(runtime::Node& node) {
  auto p = std::make_shared<Planner>(node);
  node.subscribe<hullgrind::outline_t>(
      channels::kOutline, [p](const hullgrind::outline_t& m, const runtime::Delivery& d) { p->on_outline(m, d); });
  node.subscribe<hullgrind::job_request_t>(
      channels::kJobRequest,
      [p](const hullgrind::job_request_t& m, const runtime::Delivery& d) { p->on_request(m, d); });
  node.subscribe<hullgrind::robot_status_t>(
      channels::kRobotStatus,
      [p](const hullgrind::robot_status_t& m, const runtime::Delivery& d) { p->on_robot(m, d); });
  node.every(std::chrono::milliseconds(100), [p] { p->tick(); });
}

}  // namespace hg::path_planner
