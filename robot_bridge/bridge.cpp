#include "robot_bridge/bridge.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "hullgrind/heartbeat_t.hpp"
#include "runtime/log.hpp"
#include "runtime/node.hpp"

namespace hg::robot_bridge {

using hullgrind::job_request_t;
using hullgrind::job_status_t;
using hullgrind::robot_status_t;
using runtime::Level;
using runtime::logf;

const char* state_name(Bridge::State s) {
  switch (s) {
    case Bridge::State::Idle: return "idle";
    case Bridge::State::Accepted: return "accepted";
    case Bridge::State::Awaiting: return "awaiting approval";
    case Bridge::State::Running: return "running";
    case Bridge::State::Fault: return "FAULT";
  }
  return "?";
}

Bridge::Bridge(BridgeConfig config, std::unique_ptr<Driver> driver, BridgeOutputs outputs, double now)
    : cfg_(std::move(config)), driver_(std::move(driver)), out_(std::move(outputs)) {
  recover(now);
  update_health();
}

// A job that was running when a previous bridge died: the robot may have stopped anywhere. Report the job
// and hold in FAULT until an operator checked the cell and sent RESET. A simulated robot of another run
// (HG_RUN_ID) ended with that run: report the job and start clean.
void Bridge::recover(double now) {
  if (cfg_.state_file.empty()) return;
  std::ifstream in(cfg_.state_file);
  std::string job, run;
  if (!in || !std::getline(in, job) || job.empty()) return;
  std::getline(in, run);
  job_id_ = job;
  state_ = State::Running;
  if (std::string(driver_->name()) == "sim" && !cfg_.run_id.empty() && run != cfg_.run_id) {
    report(job, job_status_t::STATE_ABORTED, 0,
           "interrupted: the run " + (run.empty() ? std::string("before") : run) +
               " stopped while the job was running; the simulated robot of this run starts clean");
    state_ = State::Idle;
    job_id_.clear();
    save_state();
    return;
  }
  enter_fault(robot_status_t::FAULT_UNEXPECTED_MODE,
              "hg-robot-bridge restarted while job " + job + " was running; robot stopped", now);
}

job_status_t Bridge::make_status(const std::string& job_id, std::int8_t state, double progress,
                                 const std::string& message) const {
  job_status_t s{};
  s.header.frame_id = "";
  s.job_id = job_id;
  s.state = state;
  s.progress = progress;
  s.message = message;
  if (job_id.empty() || job_id != job_id_) return s;
  s.part_id = part_id_;
  s.plan_revision = held_.revision;
  s.actor = actor_;
  s.excluded_loops = excluded_;
  s.num_excluded = std::int32_t(excluded_.size());
  return s;
}

void Bridge::publish(job_status_t s, bool record) {
  s.source = cfg_.source;
  s.answer = !record;
  s.num_excluded = std::int32_t(s.excluded_loops.size());
  s.num_unground = std::int32_t(s.unground.size());
  if (record && !s.job_id.empty()) ledger_.set(s);
  if (const jobs::JobLedger::Entry* e = ledger_.find(s.job_id); e && s.part_id.empty()) s.part_id = e->part_id;
  if (s.state != job_status_t::STATE_RUNNING)
    logf(s.state == job_status_t::STATE_DONE || s.state == job_status_t::STATE_ACCEPTED ? Level::Info : Level::Warn,
         "job %s: %s%s: %s", s.job_id.c_str(), jobs::job_state_name(s.state).c_str(), record ? "" : " (answer)",
         s.message.c_str());
  out_.job_status(s);
}

void Bridge::report(const std::string& job_id, std::int8_t state, double progress, const std::string& message,
                    bool record) {
  publish(make_status(job_id, state, progress, message), record);
}

void Bridge::save_state() {
  if (cfg_.state_file.empty()) return;
  if (state_ == State::Running) {
    std::ofstream out(cfg_.state_file, std::ios::trunc);
    out << job_id_ << "\n" << cfg_.run_id << "\n";
    if (!out) logf(Level::Warn, "cannot write state file %s", cfg_.state_file.c_str());
  } else {
    std::remove(cfg_.state_file.c_str());
  }
}

void Bridge::update_health() {
  const RobotState& st = driver_->state();
  if (state_ == State::Fault)
    out_.health(hullgrind::heartbeat_t::STATE_DEGRADED, "FAULT: " + fault_text_ + " (RESET to clear)");
  else if (!st.connected)
    out_.health(hullgrind::heartbeat_t::STATE_DEGRADED, "robot controller not connected");
  else
    out_.health(hullgrind::heartbeat_t::STATE_OK, "");
}

void Bridge::finish(std::int8_t state, const std::string& message, double,
                    const std::vector<hullgrind::edge_stretch_t>& unground) {
  job_status_t s = make_status(job_id_, state, state == job_status_t::STATE_DONE ? 1.0 : progress_, message);
  s.unground = unground;
  publish(s);
  release();
}

// Nothing held any more.
void Bridge::release() {
  state_ = state_ == State::Fault ? State::Fault : State::Idle;
  job_id_.clear();
  part_id_.clear();
  held_ = {};
  excluded_.clear();
  actor_.clear();
  save_state();
}

void Bridge::enter_fault(std::int32_t code, const std::string& text, double now) {
  driver_->stop(now);
  fault_code_ = code;
  fault_text_ = text;
  if (state_ == State::Accepted || state_ == State::Awaiting || state_ == State::Running) {
    const int idx = driver_->state().path_index;
    report(
        job_id_, job_status_t::STATE_ABORTED, progress_,
        "FAULT: " + text + (state_ == State::Running && idx >= 0 ? " (at waypoint " + std::to_string(idx) + ")" : ""));
  }
  logf(Level::Error, "FAULT: %s; nothing runs until a RESET request", text.c_str());
  state_ = State::Fault;
  release();
}

void Bridge::on_job_request(const job_request_t& req, double now) {
  driver_->update(now);
  if (req.action == job_request_t::ACTION_QUERY) return answer_query(req);
  if (const jobs::JobLedger::Entry* seen = ledger_.find(req.job_id)) return on_repeat(req, *seen, now);
  switch (req.action) {
    case job_request_t::ACTION_START: return start_job(req, now);
    case job_request_t::ACTION_ABORT: return;  // an abort for a job never seen here is another stage's
    case job_request_t::ACTION_RESET: return reset_fault(req, now);
    case job_request_t::ACTION_APPROVE:
    case job_request_t::ACTION_REJECT:
    case job_request_t::ACTION_REPLAN: return on_unknown(req, now);
    default:
      return report(req.job_id, job_status_t::STATE_REFUSED, 0,
                    "refused: unknown action " + std::to_string(int(req.action)));
  }
}

// An action for a job this bridge never held: the job history's word on it, else "no such job"; nothing changes.
void Bridge::on_unknown(const job_request_t& req, double) {
  const std::string what = jobs::job_action_name(req.action) + " of job " + req.job_id;
  if (const auto rec = jobs::recorded_job(cfg_.jobs_dir, req.job_id); rec && rec->state >= 0)
    return report(req.job_id, rec->state, 0,
                  what + ": the job history holds it as " + jobs::job_state_name(rec->state) +
                      (rec->message.empty() ? "" : " (" + rec->message + ")") + "; nothing done",
                  false);
  report(req.job_id, job_status_t::STATE_REFUSED, 0, what + ": no such job held by the robot bridge; nothing done",
         false);
}

// A job id seen before. The held job's ABORT, and APPROVE / REJECT while it awaits approval act; REPLAN is
// the planner's (its new revision arrives as a path); everything else is answered with the id's state.
void Bridge::on_repeat(const job_request_t& req, const jobs::JobLedger::Entry& seen, double now) {
  const bool held = state_ != State::Idle && state_ != State::Fault && req.job_id == job_id_;
  const bool awaiting = held && state_ == State::Awaiting;
  if (req.action == job_request_t::ACTION_ABORT && held) return abort_held(req, now);
  if (req.action == job_request_t::ACTION_APPROVE && awaiting) return approve(req, now);
  if (req.action == job_request_t::ACTION_REJECT && awaiting) return reject(req);
  if (req.action == job_request_t::ACTION_REPLAN && awaiting) return;
  answer(req, seen, false);
}

void Bridge::answer(const job_request_t& req, const jobs::JobLedger::Entry& seen, bool keep_message) {
  job_status_t s = seen.status;
  if (s.job_id.empty()) {  // set without a whole status (upstream ends)
    s.job_id = req.job_id;
    s.state = seen.state;
    s.progress = seen.progress;
    s.message = seen.message;
  }
  s.part_id = seen.part_id;
  if (!keep_message) s.message = jobs::repeat_answer(req.action, req.job_id, seen);
  publish(s, false);
}

// QUERY: the last status of the job (of every job the ledger holds, for ""), as it was published.
void Bridge::answer_query(const job_request_t& req) {
  if (!req.job_id.empty()) {
    if (const jobs::JobLedger::Entry* e = ledger_.find(req.job_id)) answer(req, *e, true);
    return;
  }
  for (const std::string& id : ledger_.ids())
    if (const jobs::JobLedger::Entry* e = ledger_.find(id)) {
      job_request_t r = req;
      r.job_id = id;
      answer(r, *e, true);
    }
}

void Bridge::abort_held(const job_request_t& req, double now) {
  driver_->stop(now);
  if (!req.actor.empty()) actor_ = req.actor;
  const char* when = state_ == State::Running    ? "robot stopped"
                     : state_ == State::Awaiting ? "before approval; nothing moved"
                                                 : "before the path arrived";
  finish(job_status_t::STATE_ABORTED,
         std::string("aborted by ") + (req.actor.empty() ? "request" : req.actor) + "; " + when, now);
}

void Bridge::start_job(const job_request_t& req, double now) {
  const RobotState& st = driver_->state();
  if (req.job_id.empty()) return report(req.job_id, job_status_t::STATE_REFUSED, 0, "refused: empty job id");
  if (const auto rec = jobs::recorded_job(cfg_.jobs_dir, req.job_id);
      jobs::recorded_before(rec, runtime::now_utime()) && rec->state >= 0)
    return report(req.job_id, rec->state, 0,
                  "START of job " + req.job_id + ": the job history holds it as " + jobs::job_state_name(rec->state) +
                      (rec->ended ? "" : " (started before)") +
                      (rec->message.empty() ? "" : " (" + rec->message + ")") + "; not run again",
                  false);
  if (state_ == State::Fault)
    return report(req.job_id, job_status_t::STATE_REFUSED, 0,
                  "refused: robot bridge in FAULT (" + fault_text_ + "); check the cell and send RESET");
  if (state_ != State::Idle)
    return report(req.job_id, job_status_t::STATE_REFUSED, 0, "refused: busy with job " + job_id_);
  if (!st.ready) return report(req.job_id, job_status_t::STATE_REFUSED, 0, "refused: robot not ready: " + st.not_ready);
  state_ = State::Accepted;
  job_id_ = req.job_id;
  part_id_ = req.part_id;
  held_ = {};
  excluded_.clear();
  actor_.clear();
  accepted_at_ = now;
  progress_ = 0;
  report(job_id_, job_status_t::STATE_ACCEPTED, 0, "accepted; waiting for the grind path");
}

void Bridge::reset_fault(const job_request_t& req, double now) {
  if (state_ == State::Accepted || state_ == State::Awaiting || state_ == State::Running)
    return report(req.job_id, job_status_t::STATE_REFUSED, 0, "reset refused: job " + job_id_ + " is held (ABORT it)");
  if (state_ != State::Fault) return report(req.job_id, job_status_t::STATE_DONE, 1, "reset: nothing to clear");
  const std::string why = driver_->reset(now);
  if (!why.empty()) return report(req.job_id, job_status_t::STATE_REFUSED, 0, "reset refused: " + why);
  const std::string was = fault_text_;
  state_ = State::Idle;
  fault_code_ = 0;
  fault_text_.clear();
  update_health();
  report(req.job_id, job_status_t::STATE_DONE, 1, "reset: FAULT cleared (was: " + was + ")");
}

void Bridge::on_grind_path(const hullgrind::grind_path_t& msg, double now) {
  driver_->update(now);
  const bool ours = msg.job_id == job_id_ && !job_id_.empty();
  if (ours && state_ == State::Accepted) return take_plan(msg, now);
  if (ours && state_ == State::Awaiting && msg.revision > held_.revision) return take_plan(msg, now);  // REPLAN
  if (const jobs::JobLedger::Entry* seen = ledger_.find(msg.job_id))  // a second path never runs
    return report(msg.job_id, seen->state, seen->progress,
                  "grind path (revision " + std::to_string(msg.revision) + ") for job " + msg.job_id +
                      " ignored: it is " + jobs::job_state_name(seen->state) +
                      (seen->message.empty() ? "" : " (" + seen->message + ")"),
                  false);
  report(msg.job_id, job_status_t::STATE_REFUSED, 0,
         "path refused: job " + msg.job_id + " was not accepted by the robot bridge (" + state_name(state_) +
             (job_id_.empty() ? "" : ", holding job " + job_id_) + ")");
}

// A plan for the held job (its first, or a REPLAN's new revision): checked against the cell, then approved by
// the cell's policy (every edge reached, approval auto) or held for an operator.
void Bridge::take_plan(const hullgrind::grind_path_t& msg, double now) {
  const RobotState& st = driver_->state();
  std::string why = check_frame(from_lcm(msg), cfg_.frame);
  if (why.empty())
    why = st.pose_valid ? check_path(from_lcm(msg), st.tcp, cfg_.limits) : "the robot's TCP pose is unknown";
  held_ = msg;
  excluded_.clear();
  actor_.clear();
  if (!why.empty()) {
    progress_ = 0;
    return finish(job_status_t::STATE_REFUSED,
                  "path (revision " + std::to_string(msg.revision) + ") refused, nothing moved: " + why, now);
  }
  if (cfg_.auto_approve && fully_reached(msg)) {
    actor_ = "policy auto";
    report(job_id_, job_status_t::STATE_APPROVED, 0,
           "approved by the cell's policy (approval: auto): the plan reaches every edge");
    return run_plan(msg, now);
  }
  state_ = State::Awaiting;
  const std::vector<hullgrind::edge_stretch_t> gaps = unground(msg, {}, "");
  job_status_t s = make_status(job_id_, job_status_t::STATE_AWAITING_APPROVAL, 0,
                               "plan revision " + std::to_string(msg.revision) + " (" + std::to_string(msg.n) +
                                   " waypoints) awaits an operator's approval: " +
                                   (gaps.empty() ? std::string("it reaches every edge (cell approval: operator)")
                                                 : "edge not reached: " + describe(gaps)));
  s.unground = gaps;
  publish(s);
}

// APPROVE of the held plan: the revision the operator saw, the loops excluded, the result checked again.
void Bridge::approve(const job_request_t& req, double now) {
  if (req.actor.empty()) return refuse_approval("an approval names who approves (actor)");
  if (req.plan_revision != 0 && req.plan_revision != held_.revision)
    return refuse_approval("revision " + std::to_string(req.plan_revision) + " is not the plan held (revision " +
                           std::to_string(held_.revision) + ")");
  const std::vector<std::int16_t> excluded(req.excluded_loops.begin(), req.excluded_loops.end());
  if (std::string why = check_exclusions(held_, excluded); !why.empty()) return refuse_approval(why);
  const hullgrind::grind_path_t trimmed = without_loops(held_, excluded);
  if (!excluded.empty() && grind_waypoints(trimmed) == 0)
    return refuse_approval("nothing left to grind without loops " + loop_list(excluded) + " (REJECT the job)");
  const RobotState& st = driver_->state();
  if (std::string why = st.pose_valid ? check_path(from_lcm(trimmed), st.tcp, cfg_.limits) : "TCP pose unknown";
      !why.empty())
    return refuse_approval("the plan without loops " + loop_list(excluded) + " fails the cell's check: " + why);
  excluded_ = excluded;
  actor_ = req.actor;
  report(job_id_, job_status_t::STATE_APPROVED, 0,
         "approved by " + actor_ + " (revision " + std::to_string(held_.revision) + ")" +
             (excluded_.empty() ? "" : "; loops excluded: " + loop_list(excluded_)));
  run_plan(trimmed, now);
}

void Bridge::refuse_approval(const std::string& why) {
  job_status_t s = make_status(
      job_id_, job_status_t::STATE_AWAITING_APPROVAL, 0,
      "approval refused: " + why + "; still awaiting approval of revision " + std::to_string(held_.revision));
  s.unground = unground(held_, {}, "");
  publish(s, false);
}

void Bridge::reject(const job_request_t& req) {
  actor_ = req.actor;
  finish(job_status_t::STATE_REJECTED,
         "rejected by " + (req.actor.empty() ? std::string("request") : req.actor) + " (plan revision " +
             std::to_string(held_.revision) + "); nothing moved",
         0, unground(held_, {}, ""));
}

// The approved plan to the robot.
void Bridge::run_plan(const hullgrind::grind_path_t& plan, double now) {
  const Path path = from_lcm(plan);
  if (!cfg_.export_file.empty()) {
    std::ofstream out(cfg_.export_file, std::ios::trunc);
    out << make_script(path, cfg_.script);
    if (!out) logf(Level::Warn, "cannot write %s", cfg_.export_file.c_str());
  }
  if (std::string why = driver_->start(path, now); !why.empty()) {
    progress_ = 0;
    return finish(job_status_t::STATE_REFUSED, "path refused, nothing moved: " + why, now);
  }
  state_ = State::Running;
  save_state();
  last_progress_report_ = now;
  char buf[160];
  snprintf(buf, sizeof buf, "running %zu waypoints on the %s robot", path.size(), driver_->name());
  report(job_id_, job_status_t::STATE_RUNNING, 0, buf);
}

// The path ran completely: DONE when every loop not excluded was fully reached, else INCOMPLETE.
void Bridge::end_run(double now) {
  const std::vector<hullgrind::edge_stretch_t> gaps = unground(held_, excluded_, actor_);
  std::vector<hullgrind::edge_stretch_t> not_excluded;
  for (const auto& g : gaps)
    if (!is_excluded(g)) not_excluded.push_back(g);
  const std::string excluded =
      excluded_.empty() ? "" : "; loops " + loop_list(excluded_) + " excluded by " + actor_ + " at approval";
  if (not_excluded.empty()) return finish(job_status_t::STATE_DONE, "path complete" + excluded, now, gaps);
  finish(job_status_t::STATE_INCOMPLETE, "path complete; edge not ground: " + describe(not_excluded) + excluded, now,
         gaps);
}

void Bridge::on_move(const hullgrind::robot_move_t& msg, double now) {
  driver_->update(now);
  if (const jobs::JobLedger::Entry* seen = ledger_.find(msg.move_id))
    return report(msg.move_id, seen->state, seen->progress,
                  "move " + msg.move_id + " seen before: it is " + jobs::job_state_name(seen->state), false);
  if (state_ != State::Idle)
    return report(msg.move_id, job_status_t::STATE_REFUSED, 0,
                  std::string("move refused: the robot bridge is ") + state_name(state_) +
                      (job_id_.empty() ? "" : " (job " + job_id_ + ")"));
  Path path;
  path.job_id = msg.move_id;
  path.frame = msg.header.frame_id;
  path.position = {Vec3(msg.position[0], msg.position[1], msg.position[2])};
  path.orientation = {Quat(msg.orientation[0], msg.orientation[1], msg.orientation[2], msg.orientation[3])};
  path.speed = {msg.speed > 0 ? msg.speed : 0.05};
  path.kind = {hullgrind::grind_path_t::KIND_TRAVEL};
  const RobotState& st = driver_->state();
  std::string why = st.pose_valid ? check_path(path, st.tcp, cfg_.limits) : "the robot's TCP pose is unknown";
  if (why.empty()) why = driver_->start(path, now);
  if (!why.empty()) return report(msg.move_id, job_status_t::STATE_REFUSED, 0, "move refused, nothing moved: " + why);
  job_id_ = msg.move_id;
  part_id_.clear();
  held_ = {};
  excluded_.clear();
  actor_.clear();
  progress_ = 0;
  state_ = State::Running;
  save_state();
  last_progress_report_ = now;
  report(job_id_, job_status_t::STATE_RUNNING, 0, std::string("moving the TCP on the ") + driver_->name() + " robot");
}

// Other processes' reports: a job accepted here that ends upstream (the planner FAILED it, the outline asks for
// a rescan) is no longer waited for.
void Bridge::on_job_status(const job_status_t& s, double) {
  if (s.source == cfg_.source || s.job_id != job_id_ || s.answer || state_ != State::Accepted) return;
  if (!jobs::job_state_final(s.state) || s.state == job_status_t::STATE_DONE) return;
  logf(Level::Warn, "job %s ended upstream (%s: %s); no longer waiting for its path", s.job_id.c_str(),
       s.source.c_str(), s.message.c_str());
  ledger_.set(s.job_id, part_id_, s.state, 0, "ended upstream: " + s.source + ": " + s.message);
  release();
}

void Bridge::shutdown(double now) {
  if (state_ != State::Accepted && state_ != State::Awaiting && state_ != State::Running) return;
  driver_->stop(now);
  const bool running = state_ == State::Running;
  report(job_id_, job_status_t::STATE_ABORTED, progress_,
         std::string("hg-robot-bridge stopped while the job was ") + (running ? "running; robot stopped"
                                                                      : state_ == State::Awaiting
                                                                          ? "awaiting approval"
                                                                          : "waiting for its path"));
  if (!running) {
    state_ = State::Idle;
    job_id_.clear();
  }  // running: the state file stays, and the next bridge holds FAULT until the cell is checked
}

void Bridge::tick(double now) {
  driver_->update(now);
  const RobotState& st = driver_->state();
  if (state_ != State::Fault && st.fault_code != 0) enter_fault(st.fault_code, st.fault_text, now);
  if (state_ == State::Accepted && now - accepted_at_ > cfg_.path_timeout) {
    char buf[128];
    snprintf(buf, sizeof buf, "no grind path for the job within %.0f s", cfg_.path_timeout);
    finish(job_status_t::STATE_FAILED, buf, now);
  } else if (state_ == State::Running) {
    if (st.finished) {
      end_run(now);
    } else if (!st.failure.empty()) {
      finish(job_status_t::STATE_FAILED, st.failure, now);
    } else {
      progress_ = std::max(progress_, std::clamp(st.progress, 0.0, 1.0));  // reported progress never goes back
      if (now - last_progress_report_ >= cfg_.progress_period) {
        last_progress_report_ = now;
        char buf[96];
        snprintf(buf, sizeof buf, "waypoint %d", st.path_index);
        report(job_id_, job_status_t::STATE_RUNNING, progress_, buf);
      }
    }
  }
  robot_status_t rs{};
  rs.header.frame_id = cfg_.frame;
  // LCM 1.3 constants have no definition: take them by value (unary +), never as references.
  rs.mode = std::int8_t(state_ == State::Fault     ? +robot_status_t::MODE_FAULT
                        : !st.connected            ? +robot_status_t::MODE_DISCONNECTED
                        : state_ == State::Running ? +robot_status_t::MODE_RUNNING
                                                   : +robot_status_t::MODE_IDLE);
  const Vec3& p = st.tcp.position;
  const Quat& q = st.tcp.orientation;
  rs.tcp_position[0] = p.x(), rs.tcp_position[1] = p.y(), rs.tcp_position[2] = p.z();
  rs.tcp_orientation[0] = q.w(), rs.tcp_orientation[1] = q.x(), rs.tcp_orientation[2] = q.y(),
  rs.tcp_orientation[3] = q.z();
  rs.job_id = state_ == State::Running ? job_id_ : "";
  rs.path_index = state_ == State::Running ? st.path_index : -1;
  rs.fault_code = state_ == State::Fault ? fault_code_ : 0;
  rs.fault_text = state_ == State::Fault ? fault_text_ : "";
  out_.robot_status(rs);
  update_health();
}

}  // namespace hg::robot_bridge
