#include "robot_bridge/sim_driver.hpp"

#include <algorithm>
#include <stdexcept>

#include "hullgrind/robot_status_t.hpp"
#include "runtime/log.hpp"

namespace hg::robot_bridge {

using hullgrind::robot_status_t;
using runtime::Level;
using runtime::logf;

SimFault parse_sim_fault(const std::string& name) {
  if (name == "none" || name.empty()) return SimFault::None;
  if (name == "protective") return SimFault::ProtectiveStop;
  if (name == "estop") return SimFault::EmergencyStop;
  if (name == "connection") return SimFault::ConnectionLoss;
  throw std::invalid_argument("unknown simulated fault '" + name + "' (none|protective|estop|connection)");
}

SimDriver::SimDriver(SimOptions options) : o_(std::move(options)) {
  state_.connected = true;
  state_.pose_valid = true;
  state_.tcp = o_.home;
  state_.ready = true;
}

void SimDriver::fault(SimFault f, double now) {
  state_.running = false;  // the simulated robot stops where it is
  state_.path_index = -1;
  switch (f) {
    case SimFault::None: return;
    case SimFault::ProtectiveStop:
      state_.fault_code = robot_status_t::FAULT_PROTECTIVE_STOP;
      state_.fault_text = "simulated protective stop";
      break;
    case SimFault::EmergencyStop:
      state_.fault_code = robot_status_t::FAULT_EMERGENCY_STOP;
      state_.fault_text = "simulated emergency stop";
      break;
    case SimFault::ConnectionLoss:
      state_.fault_code = robot_status_t::FAULT_CONNECTION_LOST;
      state_.fault_text = "simulated controller connection lost";
      state_.connected = false;
      state_.pose_valid = false;
      link_back_at_ = now + o_.outage;
      backoff_ = o_.backoff_initial;
      next_attempt_ = now + backoff_;
      break;
  }
  state_.ready = false;
  state_.not_ready = state_.fault_text;
  logf(Level::Warn, "sim: %s", state_.fault_text.c_str());
}

void SimDriver::inject(SimFault f, double now) { fault(f, now); }

void SimDriver::update(double now) {
  if (last_now_ < 0) last_now_ = now;
  sim_time_ += (now - last_now_) * o_.time_scale;
  last_now_ = now;
  if (!state_.connected && now >= next_attempt_) {  // reconnect with back-off
    ++attempts_;
    if (now >= link_back_at_) {
      state_.connected = true;
      state_.pose_valid = true;
      logf(Level::Info, "sim: controller connection back after %d attempt(s); FAULT stays until RESET", attempts_);
    } else {
      backoff_ = std::min(backoff_ * 2, o_.backoff_max);
      next_attempt_ = now + backoff_;
    }
  }
  if (!state_.running) return;
  const double t = sim_time_ - job_start_;
  Profile::Sample s = profile_.at(t);
  state_.tcp = s.pose;
  state_.path_index = std::min<int>(s.waypoint, int(profile_.segments()) - 1);
  state_.progress = profile_.length() > 0 ? s.distance / profile_.length() : 1.0;
  if (o_.fault != SimFault::None && (o_.fault_every_job || !injected_once_) &&
      ((o_.fault_at_index >= 0 && s.waypoint >= o_.fault_at_index) ||
       (o_.fault_at_time >= 0 && t >= o_.fault_at_time))) {
    injected_once_ = true;
    fault(o_.fault, now);
    return;
  }
  if (t >= profile_.duration()) {
    state_.running = false;
    state_.finished = true;
    state_.progress = 1;
    state_.path_index = -1;
  }
}

std::string SimDriver::start(const Path& path, double now) {
  update(now);
  if (!state_.ready) return "robot not ready: " + state_.not_ready;
  if (state_.running) return "robot already running a path";
  profile_ = Profile(state_.tcp, path, o_.accel);
  job_start_ = sim_time_;
  state_.running = true;
  state_.finished = false;
  state_.failure.clear();
  state_.progress = 0;
  state_.path_index = 0;
  logf(Level::Info, "sim: running job %s, %zu waypoints, %.3f m, %.2f s simulated", path.job_id.c_str(), path.size(),
       profile_.length(), profile_.duration());
  return "";
}

void SimDriver::stop(double now) {
  update(now);
  state_.running = false;
  state_.path_index = -1;
}

std::string SimDriver::reset(double now) {
  update(now);
  if (!state_.connected) return "the controller connection is still down";
  state_.fault_code = robot_status_t::FAULT_NONE;
  state_.fault_text.clear();
  state_.ready = true;
  state_.not_ready.clear();
  return "";
}

}  // namespace hg::robot_bridge
