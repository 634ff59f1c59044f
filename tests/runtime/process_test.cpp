// A real process on the shared runtime (the hg-robot-bridge skeleton), observed over LCM from this test
// process, inside a private network namespace: heartbeat rate and counters, garbage survived, clean
// shutdown on SIGTERM.
#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <csignal>
#include <thread>

#include <lcm/lcm-cpp.hpp>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "runtime/node.hpp"
#include "tests/common/child_process.hpp"

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

struct Beat {
  hullgrind::heartbeat_t msg;
  Clock::time_point at;
};

class Listener {
 public:
  explicit Listener(lcm::LCM& lcm) { lcm.subscribe("HG_HEARTBEAT", &Listener::on, this); }
  void on(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::heartbeat_t* m) {
    beats.push_back({*m, Clock::now()});
  }
  std::vector<Beat> beats;
};

void pump(lcm::LCM& lcm, std::chrono::milliseconds d) {
  auto end = Clock::now() + d;
  while (Clock::now() < end) lcm.handleTimeout(20);
}

// Waits until a heartbeat of `pid` satisfying pred arrives; returns it.
template <class Pred>
std::optional<hullgrind::heartbeat_t> wait_beat(lcm::LCM& lcm, Listener& l, pid_t pid, Pred pred,
                                                std::chrono::milliseconds limit) {
  auto end = Clock::now() + limit;
  std::size_t seen = l.beats.size();
  while (Clock::now() < end) {
    lcm.handleTimeout(20);
    for (; seen < l.beats.size(); ++seen)
      if (l.beats[seen].msg.pid == pid && pred(l.beats[seen].msg)) return l.beats[seen].msg;
  }
  return std::nullopt;
}

class RuntimeProcess : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(lcm.good()) << "no LCM: the test must run inside tests/netns.sh";
    process = hg::test::ChildProcess({std::string(HG_BIN_DIR) + "/hg-robot-bridge", "--log-level", "warn", "--cell",
                                      std::string(HG_SOURCE_DIR) + "/config/cell.yaml"});
    pid = process.pid();
    ASSERT_GT(pid, 0);
  }
  lcm::LCM lcm{hg::runtime::default_lcm_url()};
  Listener listener{lcm};
  hg::test::ChildProcess process;  // killed at the end of the test if still running
  pid_t pid = -1;                  // its heartbeats' pid, kept after it has exited
};

TEST_F(RuntimeProcess, HeartbeatAtOneHertzWithIdentity) {
  auto first = wait_beat(
      lcm, listener, pid, [](auto&) { return true; }, 5s);
  ASSERT_TRUE(first) << "no heartbeat within 5 s";
  pump(lcm, 4200ms);
  std::vector<Beat> mine;
  for (auto& b : listener.beats)
    if (b.msg.pid == pid) mine.push_back(b);
  ASSERT_GE(mine.size(), 4u);
  ASSERT_LE(mine.size(), 7u);
  for (std::size_t i = 1; i < mine.size(); ++i) {
    double dt = std::chrono::duration<double>(mine[i].at - mine[i - 1].at).count();
    EXPECT_GT(dt, 0.6) << "beat " << i;
    EXPECT_LT(dt, 1.4) << "beat " << i;
    EXPECT_EQ(mine[i].msg.header.seq, mine[i - 1].msg.header.seq + 1);
    EXPECT_GE(mine[i].msg.uptime, mine[i - 1].msg.uptime);
  }
  EXPECT_EQ(mine.back().msg.process, "hg-robot-bridge");
  EXPECT_EQ(mine.back().msg.state, +hullgrind::heartbeat_t::STATE_OK);
  EXPECT_EQ(mine.back().msg.decode_errors, 0);
}

TEST_F(RuntimeProcess, GarbageIsCountedAndSurvived) {
  ASSERT_TRUE(wait_beat(
      lcm, listener, pid, [](auto&) { return true; }, 5s));
  // Garbage of every kind on channels the process decodes.
  const uint8_t junk[] = {1, 2, 3};
  lcm.publish("HG_JOB_REQUEST", junk, sizeof junk);
  std::vector<uint8_t> random(4000);
  for (std::size_t i = 0; i < random.size(); ++i) random[i] = uint8_t(i * 37 + 11);
  lcm.publish("HG_GRIND_PATH", random.data(), unsigned(random.size()));
  hullgrind::grind_path_t path{};
  path.n = 2;
  path.position = {{1, 2, 3}, {4, 5, 6}};
  path.orientation = {{1, 0, 0, 0}, {1, 0, 0, 0}};
  path.speed = {0.1, 0.1};
  path.kind = {2, 2};
  path.loop_index = {0, 0};
  std::vector<uint8_t> bytes(path.getEncodedSize());
  path.encode(bytes.data(), 0, int(bytes.size()));
  lcm.publish("HG_GRIND_PATH", bytes.data(), unsigned(bytes.size() / 2));  // truncated
  hullgrind::heartbeat_t wrong_type{};
  lcm.publish("HG_JOB_REQUEST", &wrong_type);  // another type's fingerprint

  auto after = wait_beat(
      lcm, listener, pid, [](auto& m) { return m.decode_errors >= 4; }, 4s);
  ASSERT_TRUE(after) << "decode errors not reported in the heartbeat";
  EXPECT_EQ(after->decode_errors, 4);
  EXPECT_FALSE(process.wait().has_value()) << "the process died on garbage";

  hullgrind::job_request_t good{};
  good.job_id = "after-garbage";
  lcm.publish("HG_JOB_REQUEST", &good);
  auto later = wait_beat(
      lcm, listener, pid, [&](auto& m) { return m.received >= after->received + 1; }, 4s);
  ASSERT_TRUE(later) << "a valid message after garbage was not received";
  EXPECT_EQ(later->decode_errors, 4);
}

TEST_F(RuntimeProcess, SigtermStopsCleanlyWithinOneSecond) {
  ASSERT_TRUE(wait_beat(
      lcm, listener, pid, [](auto&) { return true; }, 5s));
  auto t0 = Clock::now();
  process.signal(SIGTERM);
  const std::optional<int> code = process.wait(3s);
  double took = std::chrono::duration<double>(Clock::now() - t0).count();
  ASSERT_TRUE(code.has_value()) << "still running 3 s after SIGTERM";
  EXPECT_LT(took, 1.0);
  EXPECT_EQ(*code, 0);
  auto last = wait_beat(
      lcm, listener, pid, [](auto& m) { return m.state == hullgrind::heartbeat_t::STATE_STOPPING; }, 500ms);
  bool stopping_seen = last.has_value();
  for (auto& b : listener.beats)
    stopping_seen |= b.msg.pid == pid && b.msg.state == hullgrind::heartbeat_t::STATE_STOPPING;
  EXPECT_TRUE(stopping_seen) << "no STOPPING heartbeat before exit";
}

TEST_F(RuntimeProcess, SigintStopsCleanlyToo) {
  ASSERT_TRUE(wait_beat(
      lcm, listener, pid, [](auto&) { return true; }, 5s));
  process.signal(SIGINT);
  const std::optional<int> code = process.wait(3s);
  ASSERT_TRUE(code.has_value()) << "still running 3 s after SIGINT";
  EXPECT_EQ(*code, 0);
}

}  // namespace

// A burst of job requests while the process's loop is held (stopped, as a busy planner's loop is) is
// received whole when it runs again: LCM would keep only 30 of them queued, the runtime keeps many more on
// the job channels.
TEST_F(RuntimeProcess, BurstOfJobRequestsWhileTheLoopIsHeldIsReceivedWhole) {
  auto before = wait_beat(
      lcm, listener, pid, [](auto&) { return true; }, 5s);
  ASSERT_TRUE(before) << "no heartbeat within 5 s";
  pump(lcm, 1500ms);  // a heartbeat after the one above, so `before` counts everything so far
  auto settled = wait_beat(
      lcm, listener, pid, [](auto&) { return true; }, 3s);
  ASSERT_TRUE(settled);
  ASSERT_EQ(::kill(pid, SIGSTOP), 0);
  constexpr int kBurst = 300;
  for (int i = 0; i < kBurst; ++i) {
    hullgrind::job_request_t r{};
    r.job_id = "burst-" + std::to_string(i);
    r.action = hullgrind::job_request_t::ACTION_ABORT;  // of a job never seen: changes nothing
    lcm.publish("HG_JOB_REQUEST", &r);
  }
  pump(lcm, 200ms);
  ASSERT_EQ(::kill(pid, SIGCONT), 0);
  auto after = wait_beat(
      lcm, listener, pid, [&](auto& m) { return m.received >= settled->received + kBurst; }, 5s);
  ASSERT_TRUE(after) << "job requests sent while the loop was held were lost";
  EXPECT_EQ(after->decode_errors, 0);
}
