// The job protocol of the robot bridge (no LCM here: the process wires it to the bus, tests call it;
// docs/robot_bridge.md, docs/CHANNELS.md).
//
//   START(job)  idle  -> ACCEPTED "waiting for the grind path"   (REFUSED when busy, in FAULT or not ready;
//                        a job the job history (jobs_dir) holds as ended or started before: answered, never run)
//   path(job)   accepted job -> checked against the cell (REFUSED with the reason) ->
//                 cell approval auto and every edge reached: APPROVED "policy auto" -> RUNNING
//                 else AWAITING_APPROVAL (the plan's gaps in unground[]); the bridge holds the plan
//   APPROVE     the held revision (0 = latest), minus excluded loops, checked again: APPROVED -> RUNNING
//               (refused: stays AWAITING_APPROVAL, answered with why)
//   REJECT      AWAITING_APPROVAL -> REJECTED
//   path(job, revision+1)  while AWAITING_APPROVAL (a REPLAN): replaces the held plan, decided again
//   end of run  DONE when every loop not excluded was fully reached, else INCOMPLETE (unground[] lists it all)
//   ABORT(job)  the accepted, awaiting or running job -> ABORTED
//   fault       -> FAULT: the job ABORTED with the reason; nothing runs until RESET clears it
//   RESET(id)   FAULT -> idle when the driver says the robot is fit again (DONE "reset"), else REFUSED
//   QUERY(id)   the last status of the id (of every id held, for ""), answer = true
//   any other request with a job id seen before is answered with that id's state (answer = true) and
//   changes nothing; so is an APPROVE, REJECT or REPLAN of a job never seen.
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
#include "robot_bridge/plan.hpp"
#include "robot_bridge/urscript.hpp"
#include "jobs/job_ledger.hpp"

namespace hg::robot_bridge {

struct BridgeConfig {
  Limits limits;
  std::string source = "hg-robot-bridge";  // job_status_t.source
  std::string frame = "robot_base";        // the cell's frames.base: robot_status_t header.frame_id, every path's
  double path_timeout = 60;                // seconds an accepted job waits for its path before it FAILS
  double progress_period = 0.2;            // RUNNING reports at most this often (seconds)
  std::string state_file;                  // remembers the running job across a crash; "" = off
  // This run of the pipeline (tools/run.sh sets HG_RUN_ID). With the sim driver, a state file left by another
  // run is an earlier simulated robot's: this one starts clean. "" = every state file counts (as a real robot's).
  std::string run_id;
  std::string export_file;    // the URScript of every path run is also written here; "" = off
  ScriptOptions script;       // for export_file
  bool auto_approve = false;  // the cell's `approval: auto`: a plan reaching every edge runs without an operator
  std::string jobs_dir;       // the job history (hg-job-recorder's folder) looked up on START; "" = off
};

struct BridgeOutputs {
  std::function<void(hullgrind::job_status_t&)> job_status = [](hullgrind::job_status_t&) {};
  std::function<void(hullgrind::robot_status_t&)> robot_status = [](hullgrind::robot_status_t&) {};
  std::function<void(std::int8_t, const std::string&)> health = [](std::int8_t, const std::string&) {
  };  // heartbeat_t::STATE_*
};

class Bridge {
 public:
  enum class State { Idle, Accepted, Awaiting, Running, Fault };

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
  const hullgrind::grind_path_t& held_plan() const { return held_; }
  const std::string& fault_text() const { return fault_text_; }
  Driver& driver() { return *driver_; }
  const jobs::JobLedger& ledger() const { return ledger_; }

 private:
  // A status of job_id; for the held job with its plan revision, approval and (given) unground stretches.
  hullgrind::job_status_t make_status(const std::string& job_id, std::int8_t state, double progress,
                                      const std::string& message) const;
  // record: false for an answer (answer = true; the ledger keeps the job's own state and message).
  void publish(hullgrind::job_status_t s, bool record = true);
  void report(const std::string& job_id, std::int8_t state, double progress, const std::string& message,
              bool record = true);
  void start_job(const hullgrind::job_request_t& req, double now);
  void reset_fault(const hullgrind::job_request_t& req, double now);
  void on_unknown(const hullgrind::job_request_t& req, double now);
  void on_repeat(const hullgrind::job_request_t& req, const jobs::JobLedger::Entry& seen, double now);
  void answer(const hullgrind::job_request_t& req, const jobs::JobLedger::Entry& seen, bool keep_message);
  void answer_query(const hullgrind::job_request_t& req);
  void abort_held(const hullgrind::job_request_t& req, double now);
  void approve(const hullgrind::job_request_t& req, double now);
  void refuse_approval(const std::string& why);
  void reject(const hullgrind::job_request_t& req);
  void take_plan(const hullgrind::grind_path_t& msg, double now);
  void run_plan(const hullgrind::grind_path_t& plan, double now);
  void end_run(double now);
  void recover(double now);
  void enter_fault(std::int32_t code, const std::string& text, double now);
  void finish(std::int8_t state, const std::string& message, double now,
              const std::vector<hullgrind::edge_stretch_t>& unground = {});
  void release();
  void save_state();
  void update_health();

  BridgeConfig cfg_;
  std::unique_ptr<Driver> driver_;
  BridgeOutputs out_;
  State state_ = State::Idle;
  std::string job_id_, part_id_;
  // The plan of the held job (AWAITING_APPROVAL: the one to approve; RUNNING: the one approved, before
  // exclusions), the loops the approval excluded and who approved.
  hullgrind::grind_path_t held_{};
  std::vector<std::int16_t> excluded_;
  std::string actor_;
  double accepted_at_ = 0, last_progress_report_ = -1e9, progress_ = 0;
  std::int32_t fault_code_ = 0;
  std::string fault_text_;
  std::int64_t seq_ = 0;
  jobs::JobLedger ledger_;  // every job id seen and its state here
};

const char* state_name(Bridge::State s);

}  // namespace hg::robot_bridge
