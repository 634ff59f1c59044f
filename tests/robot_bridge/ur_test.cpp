// UR driver + job protocol against the fake controller on loopback (own network namespace).
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <functional>
#include <memory>
#include <thread>

#include "fake_ur.hpp"
#include "script_check.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/robot_status_t.hpp"
#include "robot_bridge/bridge.hpp"
#include "robot_bridge/ur_driver.hpp"
#include "test_paths.hpp"

using namespace hg::robot_bridge;
using hullgrind::job_request_t;
using hullgrind::job_status_t;
using hullgrind::robot_status_t;

namespace {

constexpr int kScriptPort = 30002, kRtdePort = 30004;  // the controller's defaults: this namespace is ours

struct Harness {
  rbtest::FakeUr fake{kScriptPort, kRtdePort};
  std::vector<job_status_t> statuses;
  std::vector<robot_status_t> robot;
  std::vector<std::string> decode_errors;
  std::unique_ptr<Bridge> bridge;
  UrDriver* ur = nullptr;
  UrOptions options;

  Harness() {
    options.script.accel = 0.8;
    options.backoff_initial = 0.1;
    options.backoff_max = 1.6;
    fake.set_speedup(4);
    auto d = std::make_unique<UrDriver>(options);
    ur = d.get();
    d->on_decode_error = [this](const std::string& w) { decode_errors.push_back(w); };
    BridgeOutputs out;
    out.job_status = [this](job_status_t& s) { statuses.push_back(s); };
    out.robot_status = [this](robot_status_t& s) { robot.push_back(s); };
    BridgeConfig cfg;
    cfg.auto_approve = true;  // a cell with `approval: auto`: these paths reach every edge and run at once
    bridge = std::make_unique<Bridge>(cfg, std::move(d), out, rbtest::steady_seconds());
  }
  // Runs the bridge loop (5 ms ticks) until pred() holds; false after a generous limit (not a timing check).
  bool run_until(const std::function<bool()>& pred, double limit = 30) {
    const double end = rbtest::steady_seconds() + limit;
    while (rbtest::steady_seconds() < end) {
      bridge->tick(rbtest::steady_seconds());
      if (pred()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }
  bool has(const std::string& job, std::int8_t state) {
    for (const auto& s : statuses)
      if (s.job_id == job && s.state == state) return true;
    return false;
  }
  void send(const std::string& job, std::int8_t action) {
    bridge->on_job_request(rbtest::request(job, action), rbtest::steady_seconds());
  }
  bool idle() { return !robot.empty() && robot.back().mode == robot_status_t::MODE_IDLE && ur->state().ready; }
};

}  // namespace

TEST(RobotBridgeUr, RefusesNonLoopbackHostWithoutPermission) {
  UrOptions o;
  o.host = "10.1.2.3";
  EXPECT_THROW(UrDriver{o}, std::invalid_argument);
}

TEST(RobotBridgeUr, StateParsingFromRtde) {
  Harness h;
  const double pose[6] = {0.123456789, -0.25, 0.375, 0.1, -2.0, 0.5};
  h.fake.set_tcp(pose);
  ASSERT_TRUE(h.run_until([&] { return h.ur->raw().packages > 5 && h.ur->raw().tcp[0] == pose[0]; }));
  for (int i = 0; i < 6; ++i) EXPECT_EQ(h.ur->raw().tcp[i], pose[i]);  // big-endian doubles round-trip exactly
  EXPECT_EQ(h.ur->raw().robot_mode, 7);
  EXPECT_EQ(h.ur->raw().safety_mode, 1);
  EXPECT_EQ(h.ur->raw().runtime_state, 1u);
  EXPECT_GT(h.ur->raw().timestamp, 0);
  EXPECT_EQ(h.fake.handshakes(), 1);
  // robot_status_t carries the pose as a quaternion: compare as rotations.
  const auto& rs = h.robot.back();
  EXPECT_EQ(rs.mode, +robot_status_t::MODE_IDLE);
  EXPECT_EQ(rs.tcp_position[0], pose[0]);
  const Eigen::Vector3d rv(pose[3], pose[4], pose[5]);
  const Quat want(Eigen::AngleAxisd(rv.norm(), rv.normalized()));
  const Quat got(rs.tcp_orientation[0], rs.tcp_orientation[1], rs.tcp_orientation[2], rs.tcp_orientation[3]);
  EXPECT_NEAR(std::abs(got.dot(want)), 1.0, 1e-12);
  // A robot that is powered off is not ready: START refused with the reason.
  h.fake.set_robot_mode(3);
  ASSERT_TRUE(h.run_until([&] { return h.ur->raw().robot_mode == 3; }));
  h.send("off", job_request_t::ACTION_START);
  EXPECT_EQ(h.statuses.back().state, +job_status_t::STATE_REFUSED);
  EXPECT_NE(h.statuses.back().message.find("POWER_OFF"), std::string::npos) << h.statuses.back().message;
  EXPECT_TRUE(h.decode_errors.empty());
}

TEST(RobotBridgeUr, JobRunsScriptMatchesPathAndCompletes) {
  Harness h;
  ASSERT_TRUE(h.run_until([&] { return h.idle(); }));
  const auto path = rbtest::square_path("u1");
  h.send("u1", job_request_t::ACTION_START);
  ASSERT_EQ(h.statuses.back().state, +job_status_t::STATE_ACCEPTED);
  h.bridge->on_grind_path(path, rbtest::steady_seconds());
  ASSERT_EQ(h.statuses.back().state, +job_status_t::STATE_RUNNING) << h.statuses.back().message;
  ASSERT_TRUE(h.run_until([&] {
    return h.has("u1", job_status_t::STATE_DONE) || h.has("u1", job_status_t::STATE_ABORTED) ||
           h.has("u1", job_status_t::STATE_FAILED);
  }));
  ASSERT_TRUE(h.has("u1", job_status_t::STATE_DONE)) << h.statuses.back().message;
  const auto scripts = h.fake.scripts();
  ASSERT_EQ(scripts.size(), 1u);
  expect_script_matches(rbtest::parse_script(scripts[0]), path, 24, 0.8);
  double last = -1;
  for (const auto& s : h.statuses)
    if (s.job_id == "u1" && (s.state == job_status_t::STATE_RUNNING || s.state == job_status_t::STATE_DONE)) {
      EXPECT_GE(s.progress, last);
      last = s.progress;
    }
  EXPECT_EQ(last, 1.0);
  int last_index = -1, running = 0;
  for (const auto& r : h.robot)
    if (r.mode == robot_status_t::MODE_RUNNING) {
      ++running;
      EXPECT_GE(r.path_index, last_index);
      last_index = r.path_index;
    }
  EXPECT_GT(running, 0);
  // The TCP read back through RTDE is the last waypoint.
  ASSERT_TRUE(h.run_until([&] { return h.idle(); }));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(h.robot.back().tcp_position[k], path.position.back()[std::size_t(k)], 1e-9);
}

TEST(RobotBridgeUr, ProtectiveStopFaultsUntilResetAfterUnlock) {
  Harness h;
  ASSERT_TRUE(h.run_until([&] { return h.idle(); }));
  h.fake.protective_stop_at(3);
  h.send("p1", job_request_t::ACTION_START);
  h.bridge->on_grind_path(rbtest::square_path("p1"), rbtest::steady_seconds());
  ASSERT_TRUE(
      h.run_until([&] { return h.has("p1", job_status_t::STATE_ABORTED) || h.has("p1", job_status_t::STATE_DONE); }));
  ASSERT_TRUE(h.has("p1", job_status_t::STATE_ABORTED));
  EXPECT_NE(h.statuses.back().message.find("PROTECTIVE_STOP"), std::string::npos) << h.statuses.back().message;
  EXPECT_EQ(h.bridge->state(), Bridge::State::Fault);
  h.run_until([] { return false; }, 0.1);
  EXPECT_EQ(h.robot.back().mode, +robot_status_t::MODE_FAULT);
  EXPECT_EQ(h.robot.back().fault_code, +robot_status_t::FAULT_PROTECTIVE_STOP);
  // The bridge sent a stop program so the paused job can never resume.
  auto scripts = h.fake.scripts();
  ASSERT_EQ(scripts.size(), 2u);
  EXPECT_NE(scripts[1].find("stopl"), std::string::npos);
  EXPECT_EQ(h.fake.runtime_state(), 1u);
  // Reset while the controller is still protective-stopped: refused.
  h.send("r1", job_request_t::ACTION_RESET);
  EXPECT_EQ(h.statuses.back().state, +job_status_t::STATE_REFUSED);
  EXPECT_NE(h.statuses.back().message.find("PROTECTIVE_STOP"), std::string::npos);
  h.send("p2", job_request_t::ACTION_START);
  EXPECT_EQ(h.statuses.back().state, +job_status_t::STATE_REFUSED);
  // The operator unlocks the stop on the pendant; then RESET clears the FAULT and a new job runs.
  h.fake.set_safety_mode(1);
  ASSERT_TRUE(h.run_until([&] { return h.ur->raw().safety_mode == 1; }));
  h.send("r2", job_request_t::ACTION_RESET);
  EXPECT_EQ(h.statuses.back().state, +job_status_t::STATE_DONE) << h.statuses.back().message;
  ASSERT_TRUE(h.run_until([&] { return h.idle(); }));
  h.send("p3", job_request_t::ACTION_START);
  h.bridge->on_grind_path(rbtest::square_path("p3"), rbtest::steady_seconds());
  EXPECT_TRUE(h.run_until([&] { return h.has("p3", job_status_t::STATE_DONE); }));
}

TEST(RobotBridgeUr, ConnectionDropReconnectsWithBackoff) {
  Harness h;
  ASSERT_TRUE(h.run_until([&] { return h.idle(); }));
  h.fake.set_speedup(0.2);  // slow, so the drop hits mid-job
  h.send("c1", job_request_t::ACTION_START);
  h.bridge->on_grind_path(rbtest::square_path("c1"), rbtest::steady_seconds());
  h.run_until([] { return false; }, 0.2);
  const std::size_t accepts_before = h.fake.accept_times().size();
  h.fake.drop_rtde(1.5);
  ASSERT_TRUE(h.run_until([&] { return h.has("c1", job_status_t::STATE_ABORTED); }));
  EXPECT_NE(h.statuses.back().message.find("connection lost"), std::string::npos) << h.statuses.back().message;
  h.run_until([] { return false; }, 0.05);
  EXPECT_EQ(h.robot.back().mode, +robot_status_t::MODE_FAULT);
  EXPECT_EQ(h.robot.back().fault_code, +robot_status_t::FAULT_CONNECTION_LOST);
  // The program must not run on unobserved: the bridge stopped it through the script port.
  const auto scripts = h.fake.scripts();
  ASSERT_EQ(scripts.size(), 2u);
  EXPECT_NE(scripts[1].find("stopl"), std::string::npos);
  EXPECT_EQ(h.fake.runtime_state(), 1u);
  ASSERT_TRUE(h.run_until([&] { return h.fake.handshakes() == 2; }));
  // Attempts during the outage are accepted and closed by the fake; gaps between them follow the back-off
  // (a delay can only make a gap longer, so these lower bounds hold on a loaded machine).
  const auto t = h.fake.accept_times();
  ASSERT_GE(t.size() - accepts_before, 3u);
  double backoff = h.options.backoff_initial;
  for (std::size_t i = accepts_before + 1; i < t.size(); ++i) {
    EXPECT_GE(t[i] - t[i - 1], backoff - 1e-3) << "attempt " << i - accepts_before;
    backoff = std::min(backoff * 2, h.options.backoff_max);
  }
  EXPECT_EQ(h.bridge->state(), Bridge::State::Fault);  // connected again, still FAULT until RESET
  ASSERT_TRUE(h.run_until([&] { return h.ur->state().connected; }));
  h.send("r", job_request_t::ACTION_RESET);
  EXPECT_EQ(h.statuses.back().state, +job_status_t::STATE_DONE) << h.statuses.back().message;
}

TEST(RobotBridgeUr, GarbageAndTruncatedPackagesAreCountedAndSurvived) {
  Harness h;
  ASSERT_TRUE(h.run_until([&] { return h.idle(); }));
  // A data package cut short (its size says 20 bytes), an unknown package type, a text message whose
  // lengths do not add up: each framed correctly, each skipped and counted; the stream goes on.
  std::vector<std::uint8_t> bad = {0, 20, 'U', 1};
  bad.resize(20, 0xAB);
  const std::vector<std::uint8_t> unknown = {0, 6, 'Z', 1, 2, 3};
  const std::vector<std::uint8_t> text = {0, 8, 'M', 200, 'h', 'i', 0, 0};
  h.fake.inject(bad);
  h.fake.inject(unknown);
  h.fake.inject(text);
  ASSERT_TRUE(h.run_until([&] { return h.decode_errors.size() >= 3; }));
  const auto packages = h.ur->raw().packages;
  ASSERT_TRUE(h.run_until([&] { return h.ur->raw().packages > packages + 10; }));
  EXPECT_EQ(h.decode_errors.size(), 3u);
  EXPECT_EQ(h.fake.handshakes(), 1);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
  // A package size below the header's own: framing is lost; counted, the link is rebuilt (and, as any
  // lost connection, latches FAULT).
  h.fake.inject({0, 1, 'U'});
  ASSERT_TRUE(h.run_until([&] { return h.fake.handshakes() == 2 && h.ur->state().connected; }));
  EXPECT_EQ(h.decode_errors.size(), 4u);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Fault);
  h.send("r", job_request_t::ACTION_RESET);
  EXPECT_EQ(h.statuses.back().state, +job_status_t::STATE_DONE) << h.statuses.back().message;
}
