#include "robot_bridge/robot_bridge.hpp"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "robot_bridge/sim_driver.hpp"
#include "robot_bridge/ur_driver.hpp"
#include "runtime/channels.hpp"

namespace hg::robot_bridge {

using runtime::Level;
using runtime::logf;

namespace {

std::atomic<int> g_sim_signal{0};  // SIGUSR1: protective stop, SIGUSR2: connection loss (sim driver only)
void on_sim_signal(int sig) { g_sim_signal = sig; }

double mono_now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

}  // namespace

Limits limits_from(const runtime::Params& params) { return cell::limits_of(cell::load_cell(params).cell); }

ScriptOptions script_from(const runtime::Params& params, const cell::LoadedCell& cell) {
  ScriptOptions s;
  s.accel = params.number("accel");
  cell::refuse_above(params, "accel", s.accel, cell, "max-accel", cell.cell.max_accel);
  s.blend_radius = params.number("blend-radius");
  s.progress_register = int(params.integer("ur-register"));
  if (s.progress_register < 0 || s.progress_register > 47) throw params.error("ur-register", "must be 0..47");
  return s;
}

runtime::ProcessInfo process_info() {
  runtime::ProcessInfo info{
      "hg-robot-bridge",
      "Accepted jobs' grind paths (HG_GRIND_PATH) -> robot (simulated or Universal Robots) -> HG_ROBOT_STATUS (100 Hz), HG_JOB_STATUS.",
      "Job protocol: a START job_request_t is ACCEPTED (or REFUSED: busy, FAULT, robot not ready); the grind_path_t\n"
      "with that job id is checked (workspace box, table height, speed, corner acceleration) and held\n"
      "AWAITING_APPROVAL until an APPROVE (optionally excluding loops; the rest checked again) or REJECT; the\n"
      "cell's `approval: auto` approves by itself only a plan that reaches every edge. Approved, it runs: RUNNING\n"
      "with progress, then DONE (every loop not excluded fully reached) or INCOMPLETE (the unground stretches\n"
      "listed), or FAILED/ABORTED with the reason. QUERY answers the last status of each job held (answer=true).\n"
      "The limits checked, the approval policy and the simulated robot's home\n"
      "come from the cell file (--cell, docs/cell.md); an accel above its max-accel stops the start (exit 2).\n"
      "A fault (protective/emergency stop, lost connection,\n"
      "unexpected robot mode) puts the bridge in FAULT until a RESET request. ABORT stops the job. A job id is\n"
      "one job: a request with an id seen before (a retrying writer) is answered with that job's state and\n"
      "changes nothing; only ABORT, APPROVE and REJECT of the held job act. A RESET needs an id of its own.\n"
      "Stopped (SIGTERM) mid-job: the robot is stopped, the job ABORTED, and the state file kept.\n"
      "HG_RUN_ID (set by tools/run.sh): with --driver sim, a state file of another run is the last run's\n"
      "simulated robot: its job is reported ABORTED (interrupted) and the bridge starts clean.\n"
      "Sim faults on demand: SIGUSR1 = protective stop, SIGUSR2 = connection loss.\n"
      "The URScript of a path file without the bus: hg-robot-export (the same keys).\n"
      "Details: docs/robot_bridge.md.",
      {
          runtime::text_param("driver", "sim", "robot driver: sim | ur", {"sim", "ur"}),
          {"export", "", "also write the URScript of every path run to this file"},
          cell::cell_param(),
          {"accel", "0.5", "tool acceleration commanded (UR a=, sim speed ramps), m/s^2; <= the cell's max-accel",
           false, runtime::ParamType::Number, 0, std::numeric_limits<double>::infinity(), true},
          {"blend-radius", "0.001", "UR blend radius between moves (capped at 40% of the shorter segment), m", false,
           runtime::ParamType::Number, 0},
          {"path-timeout", "60", "an accepted job FAILS if its path does not arrive within this, s", false,
           runtime::ParamType::Number, 0, std::numeric_limits<double>::infinity(), true},
          {"progress-period", "0.2", "RUNNING progress reports at most this often, s", false,
           runtime::ParamType::Number, 0, std::numeric_limits<double>::infinity(), true},
          {"state-file", "",
           "file remembering the running job and HG_RUN_ID across a crash (a restart reports it ABORTED and holds FAULT)"},
          {"jobs-dir", "",
           "the job history (hg-job-recorder's --dir): a START of a job it holds as ended or started before is "
           "answered with that state and never run; \"\" = off"},
          {"sim-time-scale", "1", "sim: simulated seconds per real second", false, runtime::ParamType::Number, 0,
           std::numeric_limits<double>::infinity(), true},
          {"sim-home-orientation", "0,1,0,0",
           "sim: TCP orientation at start-up, quaternion w,x,y,z (default: tool down)", false,
           runtime::ParamType::Numbers},
          runtime::text_param("sim-fault", "none",
                              "sim: fault to inject during a job: none|protective|estop|connection",
                              {"none", "protective", "estop", "connection"}),
          {"sim-fault-index", "-1", "sim: inject when the robot starts towards this waypoint (-1: off)", false,
           runtime::ParamType::Integer, -1},
          {"sim-fault-time", "-1", "sim: inject this many simulated seconds into the job (-1: off)", false,
           runtime::ParamType::Number},
          {"sim-fault-every-job", "", "sim: inject in every job, not only the first", true},
          {"sim-outage", "2", "sim: a simulated connection loss lasts this long, s", false, runtime::ParamType::Number,
           0},
          {"ur-host", "127.0.0.1", "UR controller IPv4 address"},
          {"ur-allow-remote", "", "allow a non-loopback ur_host (a real robot)", true},
          {"ur-script-port", "30002", "UR script port (secondary/primary interface)", false,
           runtime::ParamType::Integer, 1, 65535},
          {"ur-rtde-port", "30004", "UR RTDE port", false, runtime::ParamType::Integer, 1, 65535},
          {"ur-frequency", "125", "RTDE output frequency requested, Hz", false, runtime::ParamType::Number, 0,
           std::numeric_limits<double>::infinity(), true},
          {"ur-register", "24", "output integer register the program writes the waypoint index to", false,
           runtime::ParamType::Integer, 0, 47},
          {"ur-data-timeout", "0.5", "no RTDE data for this long: connection lost, s", false,
           runtime::ParamType::Number, 0, std::numeric_limits<double>::infinity(), true},
          {"ur-backoff-initial", "0.2", "first reconnect delay, s (doubles per failure)", false,
           runtime::ParamType::Number, 0, std::numeric_limits<double>::infinity(), true},
          {"ur-backoff-max", "5", "longest reconnect delay, s", false, runtime::ParamType::Number, 0,
           std::numeric_limits<double>::infinity(), true},
      }};
  for (runtime::Param& p : cell::moved_to_cell({{"workspace-min", "workspace.min"},
                                                {"workspace-max", "workspace.max"},
                                                {"table-z", "table-z"},
                                                {"max-speed", "max-speed"},
                                                {"max-accel", "max-accel"},
                                                {"sim-home", "home"},
                                                {"frame", "frames.base"}}))
    info.params.push_back(std::move(p));
  return info;
}

// The simulated robot from the sim-* parameters; SIGUSR1 / SIGUSR2 then inject its faults.
std::unique_ptr<Driver> make_sim_driver(runtime::Node& node, const ScriptOptions& script, const Vec3& home) {
  SimOptions so;
  so.home.position = home;
  auto q = node.params().numbers("sim-home-orientation");
  if (q.size() != 4) throw node.params().error("sim-home-orientation", "needs 4 numbers w,x,y,z");
  so.home.orientation = Quat(q[0], q[1], q[2], q[3]).normalized();
  so.accel = script.accel;
  so.time_scale = node.params().number("sim-time-scale");
  so.fault = parse_sim_fault(node.params().text("sim-fault"));
  so.fault_at_index = int(node.params().integer("sim-fault-index"));
  so.fault_at_time = node.params().number("sim-fault-time");
  so.fault_every_job = node.params().flag("sim-fault-every-job");
  so.outage = node.params().number("sim-outage");
  if (!(so.time_scale > 0)) throw node.params().error("sim-time-scale", "must be positive");
  struct sigaction sa {};
  sa.sa_handler = on_sim_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  sigaction(SIGUSR1, &sa, nullptr);
  sigaction(SIGUSR2, &sa, nullptr);
  return std::make_unique<SimDriver>(so);
}

// The Universal Robots driver from the ur-* parameters.
std::unique_ptr<Driver> make_ur_driver(runtime::Node& node, const ScriptOptions& script) {
  UrOptions uo;
  uo.host = node.params().text("ur-host");
  uo.allow_remote = node.params().flag("ur-allow-remote");
  uo.script_port = int(node.params().integer("ur-script-port"));
  uo.rtde_port = int(node.params().integer("ur-rtde-port"));
  uo.frequency = node.params().number("ur-frequency");
  uo.script = script;
  uo.data_timeout = node.params().number("ur-data-timeout");
  uo.backoff_initial = node.params().number("ur-backoff-initial");
  uo.backoff_max = node.params().number("ur-backoff-max");
  return std::make_unique<UrDriver>(uo);
}

std::unique_ptr<Driver> make_driver(runtime::Node& node, const std::string& driver, const ScriptOptions& script,
                                    const Vec3& home) {
  if (driver == "sim") return make_sim_driver(node, script, home);
  if (driver == "ur") return make_ur_driver(node, script);
  throw node.params().error("driver", "unknown driver '" + driver + "' (sim|ur)");
}

class Process {
 public:
  explicit Process(runtime::Node& node) : node_(node) {
    BridgeConfig cfg;
    const cell::LoadedCell cell = cell::load_cell(node.params());
    cfg.limits = cell::limits_of(cell.cell);
    cfg.path_timeout = node.params().number("path-timeout");
    cfg.progress_period = node.params().number("progress-period");
    cfg.state_file = node.params().text("state-file");
    if (const char* run = std::getenv("HG_RUN_ID")) cfg.run_id = run;
    cfg.export_file = node.params().text("export");
    cfg.jobs_dir = node.params().text("jobs-dir");
    cfg.auto_approve = cell.cell.approval == cell::Approval::Auto;
    cfg.frame = cell.cell.frames.base;
    cfg.source = node.name();
    cfg.script = script_from(node.params(), cell);
    const std::string driver = node.params().text("driver");
    std::unique_ptr<Driver> d = make_driver(node, driver, cfg.script, cell.cell.home);
    d->on_decode_error = [&node](const std::string& what) { node.count_decode_error("robot controller", what); };
    BridgeOutputs out;
    out.job_status = [&node](hullgrind::job_status_t& s) { node.publish(channels::kJobStatus, s); };
    out.robot_status = [&node](hullgrind::robot_status_t& s) { node.publish(channels::kRobotStatus, s); };
    out.health = [&node](std::int8_t state, const std::string& text) { node.set_state(state, text); };
    bridge_ = std::make_unique<Bridge>(cfg, std::move(d), out, mono_now());

    node.subscribe<hullgrind::job_request_t>(channels::kJobRequest,
                                             [this](const hullgrind::job_request_t& m, const runtime::Delivery&) {
                                               bridge_->on_job_request(m, mono_now());
                                             });
    node.subscribe<hullgrind::grind_path_t>(channels::kGrindPath,
                                            [this](const hullgrind::grind_path_t& m, const runtime::Delivery& d) {
                                              bridge_->on_grind_path(m, mono_now());
                                              node_.set_latency(double(runtime::now_utime() - d.recv_utime) * 1e-6);
                                            });
    node.subscribe<hullgrind::robot_move_t>(
        channels::kRobotMove,
        [this](const hullgrind::robot_move_t& m, const runtime::Delivery&) { bridge_->on_move(m, mono_now()); });
    node.subscribe<hullgrind::job_status_t>(
        channels::kJobStatus,
        [this](const hullgrind::job_status_t& m, const runtime::Delivery&) { bridge_->on_job_status(m, mono_now()); });
    node.every(std::chrono::milliseconds(10), [this] {
      if (int sig = g_sim_signal.exchange(0)) {
        if (auto* sim = dynamic_cast<SimDriver*>(&bridge_->driver()))
          sim->inject(sig == SIGUSR1 ? SimFault::ProtectiveStop : SimFault::ConnectionLoss, mono_now());
      }
      bridge_->tick(mono_now());
    });
    if (!cfg.run_id.empty()) logf(Level::Info, "run %s", cfg.run_id.c_str());
    logf(
        Level::Info,
        "driver %s; cell %s: workspace (%.3f, %.3f, %.3f) .. (%.3f, %.3f, %.3f), table z %.3f, max %.3f m/s, %.2f m/s^2",
        driver.c_str(), cell.file.c_str(), cfg.limits.workspace_min.x(), cfg.limits.workspace_min.y(),
        cfg.limits.workspace_min.z(), cfg.limits.workspace_max.x(), cfg.limits.workspace_max.y(),
        cfg.limits.workspace_max.z(), cfg.limits.table_z, cfg.limits.max_speed, cfg.limits.max_accel);
  }

  ~Process() { bridge_->shutdown(mono_now()); }

 private:
  runtime::Node& node_;
  std::unique_ptr<Bridge> bridge_;
};

void ProcessDeleter::operator()(Process* p) const { delete p; }

ProcessHandle attach(runtime::Node& node) { return ProcessHandle(new Process(node)); }

int export_script(const runtime::Params& params, const std::string& path_file, const std::string& out_file) {
  // The configuration first, then the input (a bad cell is named even when the path file is bad too).
  const cell::LoadedCell cell = cell::load_cell(params);
  const ScriptOptions script = script_from(params, cell);
  const Path path = read_path_json(path_file);
  if (path.size() == 0) throw std::invalid_argument(path_file + ": no waypoints");
  // Offline the robot's pose is unknown: check from the first waypoint.
  const Pose start{path.position[0], path.orientation[0]};
  std::string why = check_frame(path, cell.cell.frames.base);
  if (why.empty()) why = check_path(path, start, cell::limits_of(cell.cell));
  if (!why.empty()) {
    logf(Level::Error, "%s: refused: %s", path_file.c_str(), why.c_str());
    return 1;
  }
  std::ofstream out(out_file, std::ios::trunc);
  out << make_script(path, script);
  if (!out) {  // it ran and failed (exit 1), not a bad input
    logf(Level::Error, "cannot write %s", out_file.c_str());
    return 1;
  }
  logf(Level::Info, "wrote %s: %zu waypoints of job %s", out_file.c_str(), path.size(), path.job_id.c_str());
  return 0;
}

}  // namespace hg::robot_bridge
