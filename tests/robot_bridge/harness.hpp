// The robot bridge on the simulated robot, driven by the test's own clock: statuses and robot reports kept.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hullgrind/job_status_t.hpp"
#include "hullgrind/robot_status_t.hpp"
#include "robot_bridge/bridge.hpp"
#include "robot_bridge/sim_driver.hpp"
#include "test_paths.hpp"

namespace rbtest {

using namespace hg::robot_bridge;
using hullgrind::job_request_t;
using hullgrind::job_status_t;
using hullgrind::robot_status_t;

constexpr double kA = 0.5;    // tangential acceleration of the profile in these tests
constexpr double kDt = 0.01;  // 100 Hz ticks, as the process runs them

// A cell with `approval: auto` (a plan reaching every edge runs at once, as before approvals existed).
inline BridgeConfig auto_cfg() {
  BridgeConfig c;
  c.auto_approve = true;
  return c;
}

struct Harness {
  std::vector<job_status_t> statuses;
  std::vector<robot_status_t> robot;
  std::unique_ptr<Bridge> bridge;
  SimDriver* sim = nullptr;
  double now = 0;

  explicit Harness(SimOptions so = {}, BridgeConfig cfg = auto_cfg()) {
    so.home.position = Vec3(0.5, 0, 0.3);
    so.home.orientation = Quat(0, 1, 0, 0);
    so.accel = kA;
    auto d = std::make_unique<SimDriver>(so);
    sim = d.get();
    BridgeOutputs out;
    out.job_status = [this](job_status_t& s) { statuses.push_back(s); };
    out.robot_status = [this](robot_status_t& s) { robot.push_back(s); };
    bridge = std::make_unique<Bridge>(cfg, std::move(d), out, now);
  }
  void tick(int n = 1) {
    for (int i = 0; i < n; ++i) bridge->tick(now += kDt);
  }
  void send(const std::string& job, std::int8_t action) { bridge->on_job_request(request(job, action), now); }
  void send(const job_request_t& r) { bridge->on_job_request(r, now); }
  void path(const hullgrind::grind_path_t& p) { bridge->on_grind_path(p, now); }
  const job_status_t& last() const { return statuses.back(); }
  // Ticks until a status for `job` with `state` appears; false after `limit` simulated seconds.
  bool run_until(const std::string& job, std::int8_t state, double limit = 120) {
    const double end = now + limit;
    while (now < end) {
      for (const auto& s : statuses)
        if (s.job_id == job && s.state == state) return true;
      tick();
    }
    return false;
  }
};

}  // namespace rbtest
