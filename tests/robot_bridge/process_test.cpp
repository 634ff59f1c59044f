// hg-robot-bridge as a process on LCM (own network namespace): a sim job to DONE with robot_status_t at
// 100 Hz, busy refusal, SIGUSR1 protective stop -> FAULT -> RESET, clean exit on SIGTERM; the one-shot export.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <functional>
#include <mutex>
#include <sstream>
#include <thread>
#include <unistd.h>

#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/robot_status_t.hpp"
#include "test_paths.hpp"
#include "tests/common/cell_file.hpp"
#include "tests/common/child_process.hpp"

using hullgrind::job_request_t;
using hullgrind::job_status_t;
using hullgrind::robot_status_t;

namespace {

const char* kUrl = "udpm://239.255.76.67:7667?ttl=0";

struct Bus {
  lcm::LCM lcm{kUrl};
  std::mutex m;
  std::vector<job_status_t> statuses;
  std::vector<robot_status_t> robot;
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const job_status_t* s) {
    std::lock_guard l(m);
    statuses.push_back(*s);
  }
  void on_robot(const lcm::ReceiveBuffer*, const std::string&, const robot_status_t* s) {
    std::lock_guard l(m);
    robot.push_back(*s);
  }
  Bus() {
    lcm.subscribe("HG_JOB_STATUS", &Bus::on_status, this);
    lcm.subscribe("HG_ROBOT_STATUS", &Bus::on_robot, this);
  }
  bool wait(const std::function<bool()>& pred, double limit = 60) {
    auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit);
    while (std::chrono::steady_clock::now() < end) {
      lcm.handleTimeout(20);
      std::lock_guard l(m);
      if (pred()) return true;
    }
    return false;
  }
  bool has(const std::string& job, std::int8_t state) {
    for (const auto& s : statuses)
      if (s.job_id == job && s.state == state && s.source == "hg-robot-bridge") return true;
    return false;
  }
  void send(const std::string& job, std::int8_t action) {
    auto r = rbtest::request(job, action);
    lcm.publish("HG_JOB_REQUEST", &r);
  }
};

}  // namespace

TEST(RobotBridgeProcess, SimJobFaultResetAndCleanExit) {
  Bus bus;
  ASSERT_TRUE(bus.lcm.good());
  hg::test::ChildProcess bridge({std::string(HG_BIN_DIR) + "/hg-robot-bridge", "--driver", "sim", "--sim-time-scale",
                                 "10", "--lcm-url", kUrl, "--cell", hg::test::shipped_cell()});
  ASSERT_TRUE(bridge.started());
  ASSERT_TRUE(bus.wait([&] { return bus.robot.size() > 5; })) << "no robot_status_t from the bridge";
  bus.send("e1", job_request_t::ACTION_START);
  ASSERT_TRUE(bus.wait([&] { return bus.has("e1", job_status_t::STATE_ACCEPTED); }));
  bus.send("e2", job_request_t::ACTION_START);
  ASSERT_TRUE(bus.wait([&] { return bus.has("e2", job_status_t::STATE_REFUSED); }));
  auto path = rbtest::three_segment_path("e1");
  bus.lcm.publish("HG_GRIND_PATH", &path);
  // The shipped cell says `approval: operator`: the plan waits, the robot stays idle, until an APPROVE.
  ASSERT_TRUE(bus.wait([&] { return bus.has("e1", job_status_t::STATE_AWAITING_APPROVAL); }));
  usleep(300000);
  {
    std::lock_guard l(bus.m);
    for (const auto& r : bus.robot) ASSERT_NE(r.mode, +robot_status_t::MODE_RUNNING);
  }
  auto approve = rbtest::approval("e1", "pat");
  bus.lcm.publish("HG_JOB_REQUEST", &approve);
  ASSERT_TRUE(
      bus.wait([&] { return bus.has("e1", job_status_t::STATE_DONE) || bus.has("e1", job_status_t::STATE_REFUSED); }));
  ASSERT_TRUE(bus.has("e1", job_status_t::STATE_APPROVED));
  ASSERT_TRUE(bus.has("e1", job_status_t::STATE_DONE));
  {
    std::lock_guard l(bus.m);
    double last = -1;
    for (const auto& s : bus.statuses)
      if (s.job_id == "e1" && (s.state == job_status_t::STATE_RUNNING || s.state == job_status_t::STATE_DONE)) {
        EXPECT_GE(s.progress, last);
        last = s.progress;
      }
    EXPECT_EQ(last, 1.0);
    int running = 0;
    for (const auto& r : bus.robot) running += r.mode == robot_status_t::MODE_RUNNING && r.job_id == "e1";
    EXPECT_GT(running, 50);  // ~2.1 s of real time at 100 Hz
  }
  // Protective stop on demand (SIGUSR1) in the middle of a job.
  bus.send("e3", job_request_t::ACTION_START);
  ASSERT_TRUE(bus.wait([&] { return bus.has("e3", job_status_t::STATE_ACCEPTED); }));
  auto back = rbtest::make_path("e3", {{0.5, 0, 0.1, 0.02, 0}, {0.5, 0, 0.3, 0.02, 4}});
  bus.lcm.publish("HG_GRIND_PATH", &back);
  ASSERT_TRUE(bus.wait([&] { return bus.has("e3", job_status_t::STATE_AWAITING_APPROVAL); }));
  auto approve3 = rbtest::approval("e3", "pat");
  bus.lcm.publish("HG_JOB_REQUEST", &approve3);
  ASSERT_TRUE(bus.wait([&] { return bus.has("e3", job_status_t::STATE_RUNNING); }));
  bridge.signal(SIGUSR1);
  ASSERT_TRUE(bus.wait([&] { return bus.has("e3", job_status_t::STATE_ABORTED); }));
  ASSERT_TRUE(bus.wait([&] { return !bus.robot.empty() && bus.robot.back().mode == robot_status_t::MODE_FAULT; }));
  bus.send("r1", job_request_t::ACTION_RESET);
  ASSERT_TRUE(bus.wait([&] { return bus.has("r1", job_status_t::STATE_DONE); }));
  ASSERT_TRUE(bus.wait([&] { return bus.robot.back().mode == robot_status_t::MODE_IDLE; }));
  EXPECT_EQ(bridge.stop(), 0);
}

TEST(RobotBridgeProcess, ExportWritesTheScriptOfAPathFile) {
  const std::string dir = ::testing::TempDir();
  const std::string json = dir + "rb_export_" + std::to_string(getpid()) + ".json";
  const std::string script = dir + "rb_export_" + std::to_string(getpid()) + ".script";
  {
    std::ofstream out(json);
    out << R"({"job_id": "X", "frame": "robot_base", "waypoints": [
      {"position": [0.4, 0, 0.2], "orientation": [0, 1, 0, 0], "speed": 0.05, "kind": "approach"},
      {"position": [0.45, 0.0000004, 0.2], "orientation": [0, 1, 0, 0], "speed": 0.02, "kind": "grind"}]})";
  }
  const std::string cell = " --cell " + hg::test::shipped_cell();
  std::string cmd = std::string(HG_BIN_DIR) + "/hg-robot-export" + cell + " -o " + script + " " + json + " 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream in(script);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("movel(p[0.400000000, 0.000000000, 0.200000000"), std::string::npos) << ss.str();
  EXPECT_NE(ss.str().find("movep(p[0.450000000, 0.000000400, 0.200000000"), std::string::npos) << ss.str();
  EXPECT_NE(ss.str().find("v=0.020000"), std::string::npos);
  // Too fast for the cell's limits: refused, exit 1, no script.
  std::remove(script.c_str());
  const std::string slow = hg::test::write_test_cell(dir + "rb_export_slow_" + std::to_string(getpid()) + ".yaml",
                                                     [](hg::cell::Cell& c) { c.max_speed = 0.01; });
  cmd = std::string(HG_BIN_DIR) + "/hg-robot-export --cell " + slow + " -o " + script + " " + json + " 2>/dev/null";
  EXPECT_EQ(WEXITSTATUS(std::system(cmd.c_str())), 1);
  EXPECT_FALSE(std::ifstream(script).good());
  std::remove(json.c_str());
}

namespace {

// Runs a program to its end, returning the exit code and its output (both streams).
int run_to_end(const std::string& args, std::string& out) {
  const std::string log = ::testing::TempDir() + "rb_start_" + std::to_string(getpid()) + ".txt";
  const int rc = std::system((std::string(HG_BIN_DIR) + "/" + args + " >" + log + " 2>&1").c_str());
  std::stringstream ss;
  ss << std::ifstream(log).rdbuf();
  out = ss.str();
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace

// The bridge's limits live in the cell file: an old key in its config file is refused naming the cell key, a
// commanded acceleration above the cell's max-accel stops the start (exit 2) naming both, and a broken cell
// file names the file and the key. None of these opens the bus (memq://).
TEST(RobotBridgeProcess, StartRefusesWhatContradictsTheCell) {
  const std::string dir = ::testing::TempDir(), cell = hg::test::shipped_cell();
  const std::string bridge = "hg-robot-bridge --lcm-url memq:// --cell ";
  std::string out;
  const std::string old = dir + "rb_old_keys_" + std::to_string(getpid()) + ".yaml";
  for (const auto& [key, cell_key] :
       std::vector<std::pair<std::string, std::string>>{{"table-z: -0.5", "table-z"},
                                                        {"max-accel: 2.0", "max-accel"},
                                                        {"sim-home: [0.5, 0, 0.3]", "home"},
                                                        {"workspace-min: [-1, -1, 0]", "workspace.min"}}) {
    std::ofstream(old) << "driver: sim\n" << key << "\n";
    EXPECT_EQ(run_to_end(bridge + cell + " --config " + old, out), 2) << key;
    EXPECT_NE(out.find("config '" + old + "' line 2: key '" + key.substr(0, key.find(':')) +
                       "': moved: it lives in the cell file (--cell, default config/cell.yaml), key " + cell_key),
              std::string::npos)
        << out;
  }
  EXPECT_EQ(run_to_end(bridge + cell + " --accel 2.5", out), 2);
  EXPECT_NE(out.find("command line: --accel: 2.5 exceeds " + cell + " max-accel 2"), std::string::npos) << out;
  EXPECT_EQ(run_to_end(bridge + cell + " --max-speed 0.1", out), 2);
  EXPECT_NE(out.find("--max-speed moved: it lives in the cell file"), std::string::npos) << out;
  const std::string broken = dir + "rb_broken_cell_" + std::to_string(getpid()) + ".yaml";
  std::ifstream in(cell);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  text.replace(text.find("table-z: 0.0"), 12, "table-z: 1.5");
  std::ofstream(broken) << text;
  EXPECT_EQ(run_to_end(bridge + broken, out), 2);
  EXPECT_NE(out.find(broken + ": table-z: must lie in the workspace's z range"), std::string::npos) << out;
}
