// The simulated robot: follows Profile in (scaled) time, with fault injection for tests and demos.
#pragma once

#include "robot_bridge/driver.hpp"

namespace hg::robot_bridge {

enum class SimFault { None, ProtectiveStop, EmergencyStop, ConnectionLoss };
SimFault parse_sim_fault(const std::string& name);  // none|protective|estop|connection; throws on others

struct SimOptions {
  Pose home;                                        // TCP at start-up
  double accel = 0.5;                               // tangential acceleration of the profile, m/s^2
  double time_scale = 1.0;                          // simulated seconds per real second (demos and tests run faster)
  SimFault fault = SimFault::None;                  // injected during a job, when one of the triggers below is met
  int fault_at_index = -1;                          // ... when the robot starts towards this waypoint
  double fault_at_time = -1;                        // ... this many simulated seconds into the job
  bool fault_every_job = false;                     // false: only the first job after start-up is hit
  double outage = 2.0;                              // simulated connection loss lasts this long (seconds of real time)
  double backoff_initial = 0.2, backoff_max = 5.0;  // reconnect attempts while the connection is down
};

class SimDriver final : public Driver {
 public:
  explicit SimDriver(SimOptions options);
  const char* name() const override { return "sim"; }
  void update(double now) override;
  const RobotState& state() const override { return state_; }
  std::string start(const Path& path, double now) override;
  void stop(double now) override;
  std::string reset(double now) override;
  // Fault now (signal handlers of the process, tests).
  void inject(SimFault fault, double now);
  int reconnect_attempts() const { return attempts_; }
  const Profile& profile() const { return profile_; }

 private:
  void fault(SimFault f, double now);
  SimOptions o_;
  RobotState state_;
  Profile profile_;
  double sim_time_ = 0, last_now_ = -1, job_start_ = 0;
  bool injected_once_ = false;
  double link_back_at_ = 0, next_attempt_ = 0, backoff_ = 0;
  int attempts_ = 0;
};

}  // namespace hg::robot_bridge
