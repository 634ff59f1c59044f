// What the bridge needs from a robot: start a checked path, stop, reset a latched fault, and its state.
// Drivers are polled (update) from the process's main loop at ~100 Hz with a monotonic time in seconds,
// so tests can drive them with their own clock.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "robot_bridge/path.hpp"

namespace hg::robot_bridge {

struct RobotState {
  bool connected = false;  // state is being received (the sim is always connected unless told otherwise)
  bool pose_valid = false;
  Pose tcp;
  bool ready = false;           // a job may start now
  std::string not_ready;        // why not, when !ready
  bool running = false;         // a path is being executed
  int path_index = -1;          // waypoint being approached, -1 when idle
  double progress = 0;          // 0..1 along the running path (by distance)
  bool finished = false;        // the last started path ran to its end
  std::string failure;          // the last started path ended early, not by a safety fault (program stopped)
  std::int32_t fault_code = 0;  // robot_status_t::FAULT_*, latched until reset()
  std::string fault_text;
};

class Driver {
 public:
  virtual ~Driver() = default;
  virtual const char* name() const = 0;
  virtual void update(double now) = 0;
  virtual const RobotState& state() const = 0;
  // Starts the (already checked) path; "" when started, else why not (nothing moves then).
  virtual std::string start(const Path& path, double now) = 0;
  // Halts motion now (abort, fault). Idempotent.
  virtual void stop(double now) = 0;
  // Clears a latched fault if the robot is fit to run again; "" when cleared, else why not.
  virtual std::string reset(double now) = 0;
  // Called for every malformed controller packet (counted in the heartbeat as decode errors).
  std::function<void(const std::string&)> on_decode_error = [](const std::string&) {};
};

}  // namespace hg::robot_bridge
