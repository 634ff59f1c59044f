// Robot bridge with the simulated robot, driven by the test's own clock (deterministic, no sockets):
// profile timing against closed-form expectations, the job protocol, refusals, faults and reset.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <unistd.h>

#include "hullgrind/job_status_t.hpp"
#include "hullgrind/robot_status_t.hpp"
#include "robot_bridge/bridge.hpp"
#include "robot_bridge/path.hpp"
#include "robot_bridge/sim_driver.hpp"
#include "harness.hpp"
#include "test_paths.hpp"

using namespace hg::robot_bridge;
using hullgrind::job_request_t;
using hullgrind::job_status_t;
using hullgrind::robot_status_t;
using rbtest::auto_cfg;
using rbtest::Harness;
using rbtest::kA;
using rbtest::kDt;
using rbtest::make_path;
using rbtest::request;

namespace {

// Extra time a speed change costs over running each segment at its own speed, from energy/kinematics: going
// from v1 to v2 at acceleration a takes |dv|/a and covers |v2^2-v1^2|/(2a), which at the higher speed would
// take |v2^2-v1^2|/(2a vmax); the difference is dv^2 / (2 a vmax). (Valid when segments hold their ramps.)
double ramp_cost(double v1, double v2) {
  const double dv = std::abs(v2 - v1), vmax = std::max(v1, v2);
  return dv * dv / (2 * kA * vmax);
}

}  // namespace

TEST(RobotBridgeProfile, SingleSegmentMatchesTrapezoid) {
  Path p;
  p.position = {Vec3(0.8, 0, 0.3)};
  p.orientation = {Quat(0, 1, 0, 0)};
  p.speed = {0.1};
  p.kind = {0};
  Profile prof(Pose{Vec3(0.5, 0, 0.3), Quat(0, 1, 0, 0)}, p, kA);
  // 0.3 m at 0.1 m/s from rest to rest: L/v + v/a.
  EXPECT_NEAR(prof.duration(), 0.3 / 0.1 + 0.1 / kA, 1e-9);
  EXPECT_NEAR(prof.length(), 0.3, 1e-12);
  // Halfway in time is halfway in distance (symmetric profile).
  EXPECT_NEAR(prof.at(prof.duration() / 2).pose.position.x(), 0.65, 1e-9);
  // During the ramp: s = a t^2 / 2.
  EXPECT_NEAR(prof.at(0.1).distance, kA * 0.01 / 2, 1e-12);
}

TEST(RobotBridgeProfile, ShortSegmentIsTriangular) {
  Path p;
  p.position = {Vec3(0.501, 0, 0.3)};
  p.orientation = {Quat(0, 1, 0, 0)};
  p.speed = {0.1};
  p.kind = {2};
  Profile prof(Pose{Vec3(0.5, 0, 0.3), Quat(0, 1, 0, 0)}, p, kA);
  // 1 mm is too short to reach 0.1 m/s (needs v^2/a = 20 mm): accelerate half, brake half: 2 sqrt(L/a).
  EXPECT_NEAR(prof.duration(), 2 * std::sqrt(0.001 / kA), 1e-9);
}

TEST(RobotBridgeProfile, MultiSegmentTimeIsLengthOverSpeedPlusRamps) {
  const Path p = from_lcm(rbtest::three_segment_path("t"));
  Profile prof(Pose{Vec3(0.5, 0, 0.3), Quat(0, 1, 0, 0)}, p, kA);
  const double expected = 0.2 / 0.05 + 0.3 / 0.02 + 0.2 / 0.1 + ramp_cost(0, 0.05) + ramp_cost(0.05, 0.02) +
                          ramp_cost(0.02, 0.1) + ramp_cost(0.1, 0);
  EXPECT_NEAR(prof.duration(), expected, 1e-9);
  // Distance along the path never decreases and the speed never exceeds the segment's.
  double last = -1;
  for (double t = 0; t <= prof.duration(); t += 0.05) {
    auto s = prof.at(t);
    EXPECT_GE(s.distance, last);
    last = s.distance;
    EXPECT_LE(s.speed, 0.1 + 1e-12);
  }
  EXPECT_NEAR(prof.at(1e9).pose.position.z(), 0.3, 1e-12);
}

TEST(RobotBridgeChecks, RefusesOutsideLimits) {
  const Pose home{Vec3(0.5, 0, 0.3), Quat(0, 1, 0, 0)};
  Limits lim;
  lim.workspace_min = Vec3(0, -0.5, 0);
  lim.workspace_max = Vec3(1, 0.5, 0.6);
  lim.table_z = 0.05;
  lim.max_speed = 0.25;
  lim.max_accel = 2.0;
  EXPECT_EQ(check_path(from_lcm(rbtest::three_segment_path("a")), home, lim), "");
  auto out = check_path(from_lcm(make_path("b", {{0.5, 0, 0.1, 0.05, 0}, {1.2, 0, 0.1, 0.05, 2}})), home, lim);
  EXPECT_NE(out.find("waypoint 1"), std::string::npos) << out;
  EXPECT_NE(out.find("outside the workspace"), std::string::npos) << out;
  out = check_path(from_lcm(make_path("c", {{0.5, 0, 0.1, 0.05, 0}, {0.6, 0, 0.04, 0.05, 2}})), home, lim);
  EXPECT_NE(out.find("not above the table"), std::string::npos) << out;
  out = check_path(from_lcm(make_path("d", {{0.5, 0, 0.1, 0.3, 0}})), home, lim);
  EXPECT_NE(out.find("exceeds the limit"), std::string::npos) << out;
  out = check_path(from_lcm(make_path("e", {{0.5, 0, 0.1, 0.0, 0}})), home, lim);
  EXPECT_NE(out.find("not positive"), std::string::npos) << out;
  // A 90 degree corner between 2 mm segments (circle through the three points: r = sqrt(2) mm) at 0.06 m/s
  // needs 0.0036 / 0.001414 = 2.55 m/s^2 > 2; at 0.05 m/s 1.77 m/s^2 is fine.
  auto corner = [](double v) {
    return make_path("f", {{0.5, 0, 0.1, 0.05, 0}, {0.502, 0, 0.1, v, 2}, {0.502, 0.002, 0.1, v, 2}});
  };
  out = check_path(from_lcm(corner(0.06)), home, lim);
  EXPECT_NE(out.find("acceleration"), std::string::npos) << out;
  EXPECT_EQ(check_path(from_lcm(corner(0.05)), home, lim), "");
  // A reversal cannot be taken at any speed.
  out = check_path(from_lcm(make_path("g", {{0.5, 0, 0.1, 0.05, 0}, {0.6, 0, 0.1, 0.01, 2}, {0.55, 0, 0.1, 0.01, 2}})),
                   home, lim);
  EXPECT_NE(out.find("acceleration"), std::string::npos) << out;
  auto bad_q = make_path("h", {{0.5, 0, 0.1, 0.05, 0}});
  bad_q.orientation[0] = {0.5, 0.5, 0, 0};
  out = check_path(from_lcm(bad_q), home, lim);
  EXPECT_NE(out.find("not unit"), std::string::npos) << out;
}

TEST(RobotBridgeSim, JobRunsToDoneWithMonotoneProgressAndExpectedDuration) {
  Harness h;
  h.send("job1", job_request_t::ACTION_START);
  ASSERT_EQ(h.last().state, +job_status_t::STATE_ACCEPTED);
  h.path(rbtest::three_segment_path("job1"));
  ASSERT_EQ(h.last().state, +job_status_t::STATE_RUNNING) << h.last().message;
  const double started = h.now;
  ASSERT_TRUE(h.run_until("job1", job_status_t::STATE_DONE));
  const double took = h.now - started;
  const double expected = 0.2 / 0.05 + 0.3 / 0.02 + 0.2 / 0.1 + ramp_cost(0, 0.05) + ramp_cost(0.05, 0.02) +
                          ramp_cost(0.02, 0.1) + ramp_cost(0.1, 0);
  EXPECT_GE(took, expected - 1e-9);
  EXPECT_LE(took, expected + 2 * kDt);  // DONE is seen on the first tick past the end
  double last = -1;
  int running = 0;
  for (const auto& s : h.statuses) {
    EXPECT_EQ(s.source, "hg-robot-bridge");
    if (s.state == job_status_t::STATE_RUNNING || s.state == job_status_t::STATE_DONE) {
      EXPECT_GE(s.progress, last);
      last = s.progress;
      running += s.state == job_status_t::STATE_RUNNING;
    }
  }
  EXPECT_EQ(last, 1.0);
  EXPECT_GT(running, 50);  // ~21 s at one report per 0.2 s
  // robot_status_t: every tick, path index never decreasing while running, RUNNING then IDLE at the end.
  int last_index = -1;
  bool saw_running = false;
  for (const auto& r : h.robot) {
    if (r.mode == robot_status_t::MODE_RUNNING) {
      saw_running = true;
      EXPECT_EQ(r.job_id, "job1");
      EXPECT_GE(r.path_index, last_index);
      last_index = r.path_index;
    }
  }
  EXPECT_TRUE(saw_running);
  EXPECT_EQ(last_index, 2);
  EXPECT_EQ(h.robot.back().mode, +robot_status_t::MODE_IDLE);
  EXPECT_NEAR(h.robot.back().tcp_position[0], 0.8, 1e-12);
  EXPECT_NEAR(h.robot.back().tcp_position[2], 0.3, 1e-12);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
}

TEST(RobotBridgeSim, AbortStopsTheRobot) {
  Harness h;
  h.send("j", job_request_t::ACTION_START);
  h.path(rbtest::three_segment_path("j"));
  h.tick(300);
  h.send("someone-else", job_request_t::ACTION_ABORT);  // not ours: ignored
  EXPECT_EQ(h.bridge->state(), Bridge::State::Running);
  h.send("j", job_request_t::ACTION_ABORT);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_ABORTED);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
  h.tick();
  const double x = h.robot.back().tcp_position[0], z = h.robot.back().tcp_position[2];
  EXPECT_LT(z, 0.3);  // it was on its way down
  h.tick(200);
  EXPECT_EQ(h.robot.back().tcp_position[0], x);
  EXPECT_EQ(h.robot.back().tcp_position[2], z);
  EXPECT_EQ(h.robot.back().mode, +robot_status_t::MODE_IDLE);
  // A new job may start after an abort (no fault).
  h.send("k", job_request_t::ACTION_START);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_ACCEPTED);
}

TEST(RobotBridgeSim, ProtectiveStopFaultsAbortsAndNeedsReset) {
  SimOptions so;
  so.fault = SimFault::ProtectiveStop;
  so.fault_at_index = 1;
  Harness h(so);
  h.send("j1", job_request_t::ACTION_START);
  h.path(rbtest::three_segment_path("j1"));
  ASSERT_TRUE(h.run_until("j1", job_status_t::STATE_ABORTED, 30));
  EXPECT_NE(h.last().message.find("protective stop"), std::string::npos) << h.last().message;
  EXPECT_EQ(h.bridge->state(), Bridge::State::Fault);
  h.tick();
  EXPECT_EQ(h.robot.back().mode, +robot_status_t::MODE_FAULT);
  EXPECT_EQ(h.robot.back().fault_code, +robot_status_t::FAULT_PROTECTIVE_STOP);
  // The robot stopped where the fault hit: at the end of the approach (waypoint 0, z = 0.1).
  EXPECT_NEAR(h.robot.back().tcp_position[2], 0.1, 1e-3);
  const double x = h.robot.back().tcp_position[0];
  h.tick(500);
  EXPECT_EQ(h.robot.back().tcp_position[0], x);  // nothing resumes on its own
  h.send("j2", job_request_t::ACTION_START);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_REFUSED);
  EXPECT_NE(h.last().message.find("FAULT"), std::string::npos);
  h.send("r1", job_request_t::ACTION_RESET);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_DONE) << h.last().message;
  EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
  h.send("j3", job_request_t::ACTION_START);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_ACCEPTED);
  h.path(rbtest::make_path("j3", {{0.5, 0, 0.3, 0.1, 4}}));
  EXPECT_TRUE(h.run_until("j3", job_status_t::STATE_DONE));  // the injected fault hits the first job only
}

TEST(RobotBridgeSim, ConnectionLossRetriesWithBackoffAndResetWaitsForTheLink) {
  SimOptions so;
  so.fault = SimFault::ConnectionLoss;
  so.fault_at_time = 1.0;
  so.outage = 2.0;
  so.backoff_initial = 0.2;
  so.backoff_max = 5.0;
  Harness h(so);
  h.send("j", job_request_t::ACTION_START);
  h.path(rbtest::three_segment_path("j"));
  ASSERT_TRUE(h.run_until("j", job_status_t::STATE_ABORTED, 5));
  const double lost_at = h.now;
  EXPECT_NE(h.last().message.find("connection lost"), std::string::npos);
  h.tick();
  EXPECT_EQ(h.robot.back().mode, +robot_status_t::MODE_FAULT);
  EXPECT_EQ(h.robot.back().fault_code, +robot_status_t::FAULT_CONNECTION_LOST);
  h.send("r", job_request_t::ACTION_RESET);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_REFUSED);
  // Attempts after 0.2, 0.6, 1.4, 3.0 s (doubling); the link is back from 2.0 s, so the 4th succeeds.
  while (h.sim->state().connected == false && h.now < lost_at + 10) h.tick();
  EXPECT_EQ(h.sim->reconnect_attempts(), 4);
  EXPECT_GE(h.now - lost_at, 3.0 - 1e-9);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Fault);  // back, but still FAULT until RESET
  h.send("r2", job_request_t::ACTION_RESET);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_DONE);
}

TEST(RobotBridgeSim, Refusals) {
  Harness h;
  // A path for a job never started.
  h.path(rbtest::three_segment_path("ghost"));
  EXPECT_EQ(h.last().state, +job_status_t::STATE_REFUSED);
  EXPECT_EQ(h.last().job_id, "ghost");
  EXPECT_NE(h.last().message.find("not accepted"), std::string::npos);
  // Busy.
  h.send("a", job_request_t::ACTION_START);
  h.send("b", job_request_t::ACTION_START);
  EXPECT_EQ(h.last().job_id, "b");
  EXPECT_EQ(h.last().state, +job_status_t::STATE_REFUSED);
  EXPECT_NE(h.last().message.find("busy with job a"), std::string::npos);
  // A path for another job than the accepted one.
  h.path(rbtest::three_segment_path("b"));
  EXPECT_EQ(h.last().state, +job_status_t::STATE_REFUSED);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Accepted);
  // Out of the workspace: refused, the robot never moves.
  h.path(rbtest::make_path("a", {{0.5, 0, 0.1, 0.05, 0}, {2.5, 0, 0.1, 0.05, 2}}));
  EXPECT_EQ(h.last().state, +job_status_t::STATE_REFUSED);
  EXPECT_NE(h.last().message.find("outside the workspace"), std::string::npos) << h.last().message;
  h.tick(100);
  for (const auto& r : h.robot) {
    EXPECT_EQ(r.tcp_position[0], 0.5);
    EXPECT_EQ(r.tcp_position[2], 0.3);
    EXPECT_EQ(r.mode, +robot_status_t::MODE_IDLE);
  }
  // Too fast.
  h.send("c", job_request_t::ACTION_START);
  h.path(rbtest::make_path("c", {{0.5, 0, 0.1, 1.0, 0}}));
  EXPECT_EQ(h.last().state, +job_status_t::STATE_REFUSED);
  EXPECT_NE(h.last().message.find("exceeds the limit"), std::string::npos) << h.last().message;
  EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
  // Empty job id.
  h.send("", job_request_t::ACTION_START);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_REFUSED);
}

TEST(RobotBridgeSim, AcceptedJobIsReleasedWhenThePathNeverComes) {
  BridgeConfig cfg = auto_cfg();
  cfg.path_timeout = 5;
  Harness h({}, cfg);
  h.send("p", job_request_t::ACTION_START);
  ASSERT_TRUE(h.run_until("p", job_status_t::STATE_FAILED, 10));
  EXPECT_NE(h.last().message.find("no grind path"), std::string::npos);
  // The planner failing the job releases it at once.
  h.send("q", job_request_t::ACTION_START);
  job_status_t planner{};
  planner.job_id = "q";
  planner.source = "hg-path-planner";
  planner.state = job_status_t::STATE_FAILED;
  h.bridge->on_job_status(planner, h.now);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
}

TEST(RobotBridgeSim, RestartDuringAJobReportsItAndHoldsFault) {
  BridgeConfig cfg = auto_cfg();
  cfg.state_file = ::testing::TempDir() + "rb_state_" + std::to_string(getpid());
  {
    Harness h({}, cfg);
    h.send("crash", job_request_t::ACTION_START);
    h.path(rbtest::three_segment_path("crash"));
    h.tick(10);
    ASSERT_TRUE(std::ifstream(cfg.state_file).good());
  }  // the process "dies" here without finishing the job
  Harness h2({}, cfg);
  ASSERT_FALSE(h2.statuses.empty());
  EXPECT_EQ(h2.statuses[0].job_id, "crash");
  EXPECT_EQ(h2.statuses[0].state, +job_status_t::STATE_ABORTED);
  EXPECT_NE(h2.statuses[0].message.find("restarted"), std::string::npos);
  EXPECT_EQ(h2.bridge->state(), Bridge::State::Fault);
  h2.send("r", job_request_t::ACTION_RESET);
  EXPECT_EQ(h2.bridge->state(), Bridge::State::Idle);
  EXPECT_FALSE(std::ifstream(cfg.state_file).good());
}

namespace {

// Requests of the test that the bridge acted on, not answers to repeats.
int count(const std::vector<job_status_t>& v, const std::string& job, std::int8_t state, bool answers) {
  int n = 0;
  for (const auto& s : v)
    n += s.job_id == job && s.state == state &&
         (s.message.find("repeated") != std::string::npos || s.message.find("ignored") != std::string::npos) == answers;
  return n;
}

// Times the robot started moving a path (robot_status_t mode going to RUNNING).
int executions(const std::vector<robot_status_t>& v) {
  int n = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    n += v[i].mode == robot_status_t::MODE_RUNNING && (i == 0 || v[i - 1].mode != robot_status_t::MODE_RUNNING);
  return n;
}

}  // namespace

TEST(RobotBridgeJobIds, RepeatedStartRunsTheJobOnce) {
  Harness h;
  for (int i = 0; i < 10; ++i) {  // a retrying writer, interleaved with another requester's job
    h.send("j", job_request_t::ACTION_START);
    h.send("k", job_request_t::ACTION_START);
  }
  EXPECT_EQ(count(h.statuses, "j", job_status_t::STATE_ACCEPTED, false), 1);
  EXPECT_EQ(count(h.statuses, "j", job_status_t::STATE_ACCEPTED, true), 9);  // each repeat answered
  EXPECT_EQ(count(h.statuses, "k", job_status_t::STATE_REFUSED, false), 1);  // busy with j
  EXPECT_EQ(count(h.statuses, "k", job_status_t::STATE_REFUSED, true), 9);
  h.path(rbtest::three_segment_path("j"));
  h.path(rbtest::three_segment_path("j"));  // the planner of old planned once per START
  h.tick(100);
  for (int i = 0; i < 10; ++i) h.send("j", job_request_t::ACTION_START);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_RUNNING);
  ASSERT_TRUE(h.run_until("j", job_status_t::STATE_DONE));
  // Done: repeats, and another path for it, are answered DONE and nothing moves.
  for (int i = 0; i < 10; ++i) {
    h.send("j", job_request_t::ACTION_START);
    EXPECT_EQ(h.last().state, +job_status_t::STATE_DONE);
    EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
  }
  h.path(rbtest::three_segment_path("j"));
  EXPECT_EQ(h.last().state, +job_status_t::STATE_DONE);
  h.path(rbtest::three_segment_path("k"));  // k was refused: its path never runs either
  EXPECT_EQ(h.last().state, +job_status_t::STATE_REFUSED);
  h.tick(500);
  EXPECT_EQ(executions(h.robot), 1);
  EXPECT_EQ(count(h.statuses, "j", job_status_t::STATE_DONE, false), 1);
  EXPECT_NEAR(h.robot.back().tcp_position[0], 0.8, 1e-12);  // where the one run ended
  // A new id is a new job.
  h.send("l", job_request_t::ACTION_START);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_ACCEPTED);
}

TEST(RobotBridgeJobIds, RepeatedAbortAndResetAnswerWithTheStateAndChangeNothing) {
  SimOptions so;
  so.fault = SimFault::ProtectiveStop;
  so.fault_at_index = 1;
  so.fault_every_job = true;
  Harness h(so);
  h.send("a", job_request_t::ACTION_START);
  h.send("a", job_request_t::ACTION_ABORT);
  EXPECT_EQ(count(h.statuses, "a", job_status_t::STATE_ABORTED, false), 1);
  for (int i = 0; i < 5; ++i) {
    h.send("a", job_request_t::ACTION_ABORT);
    EXPECT_EQ(h.last().state, +job_status_t::STATE_ABORTED);
    EXPECT_NE(h.last().message.find("repeated ABORT"), std::string::npos) << h.last().message;
  }
  h.send("a", job_request_t::ACTION_START);  // an aborted job id is not started again
  EXPECT_EQ(h.last().state, +job_status_t::STATE_ABORTED);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
  // A fault, cleared by r1.
  h.send("b", job_request_t::ACTION_START);
  h.path(rbtest::three_segment_path("b"));
  ASSERT_TRUE(h.run_until("b", job_status_t::STATE_ABORTED, 30));
  ASSERT_EQ(h.bridge->state(), Bridge::State::Fault);
  h.send("r1", job_request_t::ACTION_RESET);
  ASSERT_EQ(h.last().state, +job_status_t::STATE_DONE) << h.last().message;
  const std::string cleared = h.last().message;
  ASSERT_EQ(h.bridge->state(), Bridge::State::Idle);
  // A second fault; a repeat of r1 answers r1's result and does not clear it.
  h.send("c", job_request_t::ACTION_START);
  h.path(rbtest::make_path("c", {{0.5, 0, 0.2, 0.02, 0}, {0.6, 0, 0.2, 0.02, 2}}));  // from where b stopped
  ASSERT_TRUE(h.run_until("c", job_status_t::STATE_ABORTED, 60)) << h.last().message;
  ASSERT_EQ(h.bridge->state(), Bridge::State::Fault);
  for (int i = 0; i < 5; ++i) {
    h.send("r1", job_request_t::ACTION_RESET);
    EXPECT_EQ(h.last().state, +job_status_t::STATE_DONE);
    EXPECT_NE(h.last().message.find(cleared), std::string::npos) << h.last().message;
    EXPECT_EQ(h.bridge->state(), Bridge::State::Fault);
  }
  h.send("c", job_request_t::ACTION_RESET);  // the faulted job's own id names that job, not a reset
  EXPECT_EQ(h.last().state, +job_status_t::STATE_ABORTED);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Fault);
  h.send("r2", job_request_t::ACTION_RESET);
  EXPECT_EQ(h.last().state, +job_status_t::STATE_DONE);
  EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
  EXPECT_EQ(count(h.statuses, "r2", job_status_t::STATE_DONE, false), 1);
}

namespace {
// The simulated robot under another driver's name: the bridge treats it as a real robot.
struct RealRobot : Driver {
  SimDriver sim{SimOptions{}};
  const char* name() const override { return "ur"; }
  void update(double now) override { sim.update(now); }
  const RobotState& state() const override { return sim.state(); }
  std::string start(const Path& path, double now) override { return sim.start(path, now); }
  void stop(double now) override { sim.stop(now); }
  std::string reset(double now) override { return sim.reset(now); }
};
}  // namespace

TEST(RobotBridgeJobIds, SimStartsCleanAfterAnotherRunARealRobotStaysInFault) {
  BridgeConfig cfg = auto_cfg();
  cfg.state_file = ::testing::TempDir() + "rb_run_state_" + std::to_string(getpid());
  cfg.run_id = "run-1";
  auto crash = [&](const std::string& job) {
    Harness h({}, cfg);
    h.send(job, job_request_t::ACTION_START);
    h.path(rbtest::three_segment_path(job));
    h.tick(10);
    ASSERT_TRUE(std::ifstream(cfg.state_file).good());
  };
  crash("x1");
  {  // the same run (a supervisor restart): FAULT as before
    Harness h({}, cfg);
    EXPECT_EQ(h.bridge->state(), Bridge::State::Fault);
    ASSERT_FALSE(h.statuses.empty());
    EXPECT_NE(h.statuses[0].message.find("restarted"), std::string::npos) << h.statuses[0].message;
  }
  crash("x2");
  cfg.run_id = "run-2";
  {  // the next run of the simulated robot: the job reported interrupted, and the robot ready
    Harness h({}, cfg);
    EXPECT_EQ(h.bridge->state(), Bridge::State::Idle);
    ASSERT_FALSE(h.statuses.empty());
    EXPECT_EQ(h.statuses[0].job_id, "x2");
    EXPECT_EQ(h.statuses[0].state, +job_status_t::STATE_ABORTED);
    EXPECT_NE(h.statuses[0].message.find("interrupted"), std::string::npos) << h.statuses[0].message;
    EXPECT_FALSE(std::ifstream(cfg.state_file).good());
    h.send("x3", job_request_t::ACTION_START);
    EXPECT_EQ(h.last().state, +job_status_t::STATE_ACCEPTED);
    h.path(rbtest::three_segment_path("x3"));
    EXPECT_TRUE(h.run_until("x3", job_status_t::STATE_RUNNING));
  }  // dies mid-job again, in run-2
  cfg.run_id = "run-3";
  {  // a real robot may have stopped anywhere: FAULT whatever the run
    std::vector<job_status_t> statuses;
    BridgeOutputs out;
    out.job_status = [&](job_status_t& s) { statuses.push_back(s); };
    Bridge b(cfg, std::make_unique<RealRobot>(), out, 0);
    EXPECT_EQ(b.state(), Bridge::State::Fault);
    ASSERT_FALSE(statuses.empty());
    EXPECT_EQ(statuses[0].job_id, "x3");
    EXPECT_NE(statuses[0].message.find("restarted"), std::string::npos) << statuses[0].message;
  }
  std::remove(cfg.state_file.c_str());
}
