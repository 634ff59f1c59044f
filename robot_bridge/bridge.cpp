#include "robot_bridge/bridge.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "hullgrind/heartbeat_t.hpp"
#include "runtime/log.hpp"

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

void Bridge::report(const std::string& job_id, std::int8_t state, double progress, const std::string& message,
                    bool record) {
  job_status_t s{};
  s.header.frame_id = "";
  s.job_id = job_id;
  s.part_id = job_id == job_id_ ? part_id_ : "";
  if (record && !job_id.empty()) ledger_.set(job_id, s.part_id, state, progress, message);
  if (const runtime::JobLedger::Entry* e = ledger_.find(job_id); e && s.part_id.empty()) s.part_id = e->part_id;
  s.source = cfg_.source;
  s.state = state;
  s.progress = progress;
  s.message = message;
  if (state != job_status_t::STATE_RUNNING)
    logf(state == job_status_t::STATE_DONE || state == job_status_t::STATE_ACCEPTED ? Level::Info : Level::Warn,
         "job %s: state %d: %s", job_id.c_str(), int(state), message.c_str());
  out_.job_status(s);
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

void Bridge::finish(std::int8_t state, const std::string& message, double) {
  report(job_id_, state, state == job_status_t::STATE_DONE ? 1.0 : progress_, message);
  state_ = State::Idle;
  job_id_.clear();
  part_id_.clear();
  save_state();
}

void Bridge::enter_fault(std::int32_t code, const std::string& text, double now) {
  driver_->stop(now);
  fault_code_ = code;
  fault_text_ = text;
  if (state_ == State::Accepted || state_ == State::Running) {
    const int idx = driver_->state().path_index;
    report(
        job_id_, job_status_t::STATE_ABORTED, progress_,
        "FAULT: " + text + (state_ == State::Running && idx >= 0 ? " (at waypoint " + std::to_string(idx) + ")" : ""));
  }
  logf(Level::Error, "FAULT: %s; nothing runs until a RESET request", text.c_str());
  state_ = State::Fault;
  job_id_.clear();
  part_id_.clear();
  save_state();
}

void Bridge::on_job_request(const job_request_t& req, double now) {
  driver_->update(now);
  if (const runtime::JobLedger::Entry* seen = ledger_.find(req.job_id)) return on_repeat(req, *seen, now);
  switch (req.action) {
    case job_request_t::ACTION_START: return start_job(req, now);
    case job_request_t::ACTION_ABORT: return;  // an abort for a job never seen here is another stage's
    case job_request_t::ACTION_RESET: return reset_fault(req, now);
    default:
      return report(req.job_id, job_status_t::STATE_REFUSED, 0,
                    "refused: unknown action " + std::to_string(int(req.action)));
  }
}

// A job id seen before: a retrying writer, or an operator repeating. Only the ABORT of the job being held
// acts; everything else is answered with the id's state.
void Bridge::on_repeat(const job_request_t& req, runtime::JobLedger::Entry seen, double now) {
  const bool held = (state_ == State::Accepted || state_ == State::Running) && req.job_id == job_id_;
  if (req.action == job_request_t::ACTION_ABORT && held) {
    driver_->stop(now);
    return finish(
        job_status_t::STATE_ABORTED,
        state_ == State::Running ? "aborted by request; robot stopped" : "aborted by request before the path arrived",
        now);
  }
  report(req.job_id, seen.state, seen.progress, runtime::repeat_answer(req.action, req.job_id, seen), false);
}

void Bridge::start_job(const job_request_t& req, double now) {
  const RobotState& st = driver_->state();
  if (req.job_id.empty()) return report(req.job_id, job_status_t::STATE_REFUSED, 0, "refused: empty job id");
  if (state_ == State::Fault)
    return report(req.job_id, job_status_t::STATE_REFUSED, 0,
                  "refused: robot bridge in FAULT (" + fault_text_ + "); check the cell and send RESET");
  if (state_ != State::Idle)
    return report(req.job_id, job_status_t::STATE_REFUSED, 0, "refused: busy with job " + job_id_);
  if (!st.ready) return report(req.job_id, job_status_t::STATE_REFUSED, 0, "refused: robot not ready: " + st.not_ready);
  state_ = State::Accepted;
  job_id_ = req.job_id;
  part_id_ = req.part_id;
  not_ground_.clear();
  accepted_at_ = now;
  progress_ = 0;
  report(job_id_, job_status_t::STATE_ACCEPTED, 0, "accepted; waiting for the grind path");
}

void Bridge::reset_fault(const job_request_t& req, double now) {
  if (state_ == State::Accepted || state_ == State::Running)
    return report(req.job_id, job_status_t::STATE_REFUSED, 0,
                  "reset refused: job " + job_id_ + " is running (ABORT it)");
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
  if (state_ != State::Accepted || msg.job_id != job_id_) {
    if (const runtime::JobLedger::Entry* seen = ledger_.find(msg.job_id))  // a second path never runs
      return report(msg.job_id, seen->state, seen->progress,
                    "grind path for job " + msg.job_id + " ignored: it is " + runtime::job_state_name(seen->state) +
                        (seen->message.empty() ? "" : " (" + seen->message + ")"),
                    false);
    return report(msg.job_id, job_status_t::STATE_REFUSED, 0,
                  "path refused: job " + msg.job_id + " was not accepted by the robot bridge (" + state_name(state_) +
                      (job_id_.empty() ? "" : ", holding job " + job_id_) + ")");
  }
  const Path path = from_lcm(msg);
  const RobotState& st = driver_->state();
  std::string why;
  if (!st.pose_valid) why = "the robot's TCP pose is unknown";
  if (why.empty()) why = check_path(path, st.tcp, cfg_.limits);
  if (why.empty() && !cfg_.export_file.empty()) {
    std::ofstream out(cfg_.export_file, std::ios::trunc);
    out << make_script(path, cfg_.script);
    if (!out) logf(Level::Warn, "cannot write %s", cfg_.export_file.c_str());
  }
  if (why.empty()) why = driver_->start(path, now);
  if (!why.empty()) {
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

void Bridge::on_move(const hullgrind::robot_move_t& msg, double now) {
  driver_->update(now);
  if (const runtime::JobLedger::Entry* seen = ledger_.find(msg.move_id))
    return report(msg.move_id, seen->state, seen->progress,
                  "move " + msg.move_id + " seen before: it is " + runtime::job_state_name(seen->state), false);
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
  not_ground_.clear();
  progress_ = 0;
  state_ = State::Running;
  save_state();
  last_progress_report_ = now;
  report(job_id_, job_status_t::STATE_RUNNING, 0, std::string("moving the TCP on the ") + driver_->name() + " robot");
}

// The planner's coverage warnings in a PLANNED message ("; warning: skipped: ..." and "; warning: not
// reached: ...", each naming a loop and "N mm of its M mm edge"), joined by "; ".
static std::string not_ground_in(const std::string& planned) {
  static const std::string kWarning = "; warning: ";
  std::string out;
  for (std::size_t at = planned.find(kWarning); at != std::string::npos;) {
    const std::size_t from = at + kWarning.size(), next = planned.find(kWarning, from);
    const std::string w = planned.substr(from, next == std::string::npos ? std::string::npos : next - from);
    if (w.find(" mm edge") != std::string::npos) out += (out.empty() ? "" : "; ") + w;
    at = next;
  }
  return out;
}

void Bridge::on_job_status(const job_status_t& s, double) {
  if (s.source == cfg_.source || s.job_id != job_id_) return;
  // The planner publishes the path, then PLANNED: the job may already be running when it arrives.
  if (s.state == job_status_t::STATE_PLANNED && (state_ == State::Accepted || state_ == State::Running))
    not_ground_ = not_ground_in(s.message);
  if (state_ != State::Accepted) return;
  if (s.state == job_status_t::STATE_FAILED || s.state == job_status_t::STATE_ABORTED ||
      s.state == job_status_t::STATE_REFUSED) {
    logf(Level::Warn, "job %s ended upstream (%s: %s); no longer waiting for its path", s.job_id.c_str(),
         s.source.c_str(), s.message.c_str());
    ledger_.set(s.job_id, part_id_, s.state, 0, "ended upstream: " + s.source + ": " + s.message);
    state_ = State::Idle;
    job_id_.clear();
    part_id_.clear();
  }
}

void Bridge::shutdown(double now) {
  if (state_ != State::Accepted && state_ != State::Running) return;
  driver_->stop(now);
  const bool running = state_ == State::Running;
  report(job_id_, job_status_t::STATE_ABORTED, progress_,
         std::string("hg-robot-bridge stopped while the job was ") +
             (running ? "running; robot stopped" : "waiting for its path"));
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
      finish(job_status_t::STATE_DONE,
             not_ground_.empty() ? "path complete" : "path complete; edge not ground (planner): " + not_ground_, now);
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
