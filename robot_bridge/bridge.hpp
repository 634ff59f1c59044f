// The job protocol of the robot bridge (no LCM here: the process wires it to the bus, tests call it).
//
//   START(job)  idle  -> ACCEPTED "waiting for the grind path"   (REFUSED when busy, in FAULT or not ready)
//   path(job)   accepted job -> checked -> RUNNING ... DONE      (REFUSED with the reason if the check fails;
//                                                                  a path for a job never seen: REFUSED)
//   ABORT(job)  the accepted or running job -> ABORTED
//   fault       -> FAULT: the job ABORTED with the reason; nothing runs until RESET clears it
//   RESET(id)   FAULT -> idle when the driver says the robot is fit again (DONE "reset"), else REFUSED
//   any request with a job id seen before (START, ABORT or RESET; the ledger) is answered with that id's
//   current state and changes nothing, except the ABORT of the job being held.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/robot_move_t.hpp"
#include "hullgrind/robot_status_t.hpp"
#include "robot_bridge/driver.hpp"
#include "robot_bridge/urscript.hpp"
#include "runtime/job_ledger.hpp"

namespace hg::robot_bridge {

struct BridgeConfig {
  Limits limits;
  std::string source = "hg-robot-bridge";  // job_status_t.source
  std::string frame = "robot_base";        // robot_status_t header.frame_id
  double path_timeout = 60;                // seconds an accepted job waits for its path before it FAILS
  double progress_period = 0.2;            // RUNNING reports at most this often (seconds)
  std::string state_file;                  // remembers the running job across a crash; "" = off
  // This run of the pipeline (tools/run.sh sets HG_RUN_ID). With the sim driver, a state file left by another
  // run is an earlier simulated robot's: this one starts clean. "" = every state file counts (as a real robot's).
  std::string run_id;
  std::string export_file;  // the URScript of every path run is also written here; "" = off
  ScriptOptions script;     // for export_file
};

struct BridgeOutputs {
  std::function<void(hullgrind::job_status_t&)> job_status = [](hullgrind::job_status_t&) {};
  std::function<void(hullgrind::robot_status_t&)> robot_status = [](hullgrind::robot_status_t&) {};
  std::function<void(std::int8_t, const std::string&)> health = [](std::int8_t, const std::string&) {
  };  // heartbeat_t::STATE_*
};

class Bridge {
 public:
  enum class State { Idle, Accepted, Running, Fault };

  Bridge(BridgeConfig config, std::unique_ptr<Driver> driver, BridgeOutputs outputs, double now);

  void on_job_request(const hullgrind::job_request_t& req, double now);
  void on_grind_path(const hullgrind::grind_path_t& path, double now);
  void on_job_status(const hullgrind::job_status_t& status, double now);  // other processes' reports
  // One straight move of the TCP (HG_ROBOT_MOVE): runs like a job of one waypoint under move_id, checked
  // against the same limits; refused unless idle.
  void on_move(const hullgrind::robot_move_t& move, double now);
  // Polls the driver, advances the job, publishes robot_status_t. Call at 100 Hz.
  void tick(double now);
  // The process is stopping: a held job is stopped and reported ABORTED (the state file stays, so a restart
  // holds FAULT as after a crash).
  void shutdown(double now);

  State state() const { return state_; }
  const std::string& job_id() const { return job_id_; }
  const std::string& fault_text() const { return fault_text_; }
  Driver& driver() { return *driver_; }
  const runtime::JobLedger& ledger() const { return ledger_; }

 private:
  // record: false for an answer to a repeated request (the ledger keeps the job's own state and message).
  void report(const std::string& job_id, std::int8_t state, double progress, const std::string& message,
              bool record = true);
  void start_job(const hullgrind::job_request_t& req, double now);
  void reset_fault(const hullgrind::job_request_t& req, double now);
  void on_repeat(const hullgrind::job_request_t& req, runtime::JobLedger::Entry seen, double now);
  void recover(double now);
  void enter_fault(std::int32_t code, const std::string& text, double now);
  void finish(std::int8_t state, const std::string& message, double now);
  void save_state();
  void update_health();

  BridgeConfig cfg_;
  std::unique_ptr<Driver> driver_;
  BridgeOutputs out_;
  State state_ = State::Idle;
  std::string job_id_, part_id_;
  // What the planner's PLANNED message said the path leaves unground (its coverage warnings), carried into
  // DONE: the path being complete does not mean the whole edge was ground.
  std::string not_ground_;
  double accepted_at_ = 0, last_progress_report_ = -1e9, progress_ = 0;
  std::int32_t fault_code_ = 0;
  std::string fault_text_;
  std::int64_t seq_ = 0;
  runtime::JobLedger ledger_;  // every job id seen and its state here
};

const char* state_name(Bridge::State s);

}  // namespace hg::robot_bridge
