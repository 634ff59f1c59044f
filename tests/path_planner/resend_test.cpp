// The delivery of hg-path-planner's paths on a lossy bus (docs/path_planner.md, "Path delivery"), in a private
// network namespace: a path the robot bridge has not acknowledged is published again, identical, every
// --path-resend-period, at most --path-resends times; a status of the robot bridge with the path's revision,
// or the job's end, stops the copies; a REPLAN's revision is re-sent on its own. End to end: a relay between
// the planner's bus and the robot bridge's drops the first path, and the job still ends DONE long before the
// robot bridge's path timeout.
#include <gtest/gtest.h>
#include <poll.h>

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/job_status_t.hpp"
#include "hullgrind/log_line_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "tests/common/cell_file.hpp"
#include "tests/common/child_process.hpp"
#include "tests/path_planner/camera_plane.hpp"

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using hullgrind::job_request_t;
using S = hullgrind::job_status_t;

namespace {

// The planner's bus, and the robot bridge's own one for the end-to-end case (a group no one else uses).
const char* kPlannerUrl = "udpm://239.255.76.67:7667?ttl=0";
const char* kBridgeUrl = "udpm://239.255.76.68:7668?ttl=0";

double since(Clock::time_point t0, Clock::time_point t) { return std::chrono::duration<double>(t - t0).count(); }

struct PathCopy {
  hullgrind::grind_path_t msg;
  std::vector<std::uint8_t> bytes;  // as on the wire
  Clock::time_point at;
};

// What the test hears on the planner's bus; with `relay`, the robot bridge's bus joined to it: the planner's
// statuses and paths go over (the first path dropped), the robot bridge's statuses and robot reports come back.
struct Bus {
  lcm::LCM a{kPlannerUrl};
  std::optional<lcm::LCM> b;
  std::vector<PathCopy> paths;                           // every copy on the planner's bus
  std::vector<S> statuses;                               // both buses' (the bridge's as relayed)
  std::vector<std::pair<S, Clock::time_point>> relayed;  // the robot bridge's statuses, when relayed
  std::vector<hullgrind::log_line_t> logs;
  std::vector<hullgrind::heartbeat_t> beats;
  int dropped = 0;
  int robot_reports = 0;  // from the robot bridge

  explicit Bus(bool relay = false) {
    a.subscribe("HG_GRIND_PATH", &Bus::on_path, this);
    a.subscribe("HG_JOB_STATUS", &Bus::on_status_a, this);
    a.subscribe("HG_LOG", &Bus::on_log, this);
    a.subscribe("HG_HEARTBEAT", &Bus::on_beat, this);
    if (!relay) return;
    b.emplace(kBridgeUrl);
    b->subscribe("HG_JOB_STATUS", &Bus::on_status_b, this);
    b->subscribe("HG_ROBOT_STATUS", &Bus::on_robot_b, this);
  }
  bool good() { return a.good() && (!b || b->good()); }
  void on_path(const lcm::ReceiveBuffer* rb, const std::string& ch) {
    PathCopy c;
    if (c.msg.decode(rb->data, 0, rb->data_size) < 0) return;
    const auto* p = static_cast<const std::uint8_t*>(rb->data);
    c.bytes.assign(p, p + rb->data_size);
    c.at = Clock::now();
    paths.push_back(std::move(c));
    if (!b) return;
    if (dropped == 0) ++dropped;  // lost on the way to the robot bridge
    else
      b->publish(ch, rb->data, rb->data_size);
  }
  void on_status_a(const lcm::ReceiveBuffer* rb, const std::string& ch, const S* s) {
    if (s->source == "hg-robot-bridge") return;  // relayed here by this bus, counted when it came
    statuses.push_back(*s);
    if (b && s->source == "hg-path-planner") b->publish(ch, rb->data, rb->data_size);
  }
  void on_status_b(const lcm::ReceiveBuffer* rb, const std::string& ch, const S* s) {
    if (s->source != "hg-robot-bridge") return;  // the planner's, relayed there by this bus
    statuses.push_back(*s);
    relayed.emplace_back(*s, Clock::now());
    a.publish(ch, rb->data, rb->data_size);
  }
  void on_robot_b(const lcm::ReceiveBuffer* rb, const std::string& ch) {
    ++robot_reports;
    a.publish(ch, rb->data, rb->data_size);
  }
  void on_log(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::log_line_t* m) { logs.push_back(*m); }
  void on_beat(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::heartbeat_t* m) { beats.push_back(*m); }

  void spin(int ms) {
    pollfd fds[2] = {{a.getFileno(), POLLIN, 0}, {b ? b->getFileno() : -1, POLLIN, 0}};
    if (poll(fds, b ? 2 : 1, ms) <= 0) return;
    if (fds[0].revents & POLLIN) a.handle();
    if (b && (fds[1].revents & POLLIN)) b->handle();
  }
  bool wait_for(const std::function<bool()>& pred, std::chrono::milliseconds limit) {
    const auto end = Clock::now() + limit;
    while (Clock::now() < end) {
      if (pred()) return true;
      spin(10);
    }
    return pred();
  }
  void listen(std::chrono::milliseconds d) {
    wait_for([] { return false; }, d);
  }
  std::vector<const PathCopy*> copies(const std::string& job, int revision = 0) const {
    std::vector<const PathCopy*> out;
    for (const auto& c : paths)
      if (c.msg.job_id == job && (revision == 0 || c.msg.revision == revision)) out.push_back(&c);
    return out;
  }
  // Copies of the job's path (of `revision`, 0: any) received after `t`.
  int copies_after(const std::string& job, Clock::time_point t, int revision = 0) const {
    int n = 0;
    for (const PathCopy* c : copies(job, revision)) n += c->at > t;
    return n;
  }
  bool has(const std::string& job, std::int8_t state, const std::string& source) const {
    for (const auto& s : statuses)
      if (s.job_id == job && s.state == state && s.source == source && !s.answer) return true;
    return false;
  }
};

// A 0.3 x 0.2 m plate seen from the camera 1.19 m above it (as in process_test.cpp).
hullgrind::outline_t plate_outline(std::int64_t seq) {
  hullgrind::outline_t o = hg::path_planner::test::outline_in_camera_plane(seq);
  hullgrind::outline_loop_t l{};
  l.u = {0, 0.3, 0.3, 0};
  l.v = {0, 0, 0.2, 0.2};
  l.n = 4;
  o.loops.push_back(l);
  o.num_loops = 1;
  return o;
}

job_request_t request(const std::string& id, std::int8_t action) {
  job_request_t r{};
  r.job_id = id;
  r.part_id = "plate";
  r.action = action;
  r.tool_radius = 0.005;  // the rest zero: configured defaults
  return r;
}

S bridge_status(const std::string& job, std::int8_t state, int revision, bool answer = false) {
  S s{};
  s.job_id = job;
  s.source = "hg-robot-bridge";
  s.state = state;
  s.plan_revision = revision;
  s.answer = answer;
  return s;
}

class PathResend : public testing::Test {
 protected:
  void start_planner(const std::vector<std::string>& extra) {
    ASSERT_TRUE(bus.good()) << "no LCM: the test must run inside tests/netns.sh";
    std::vector<std::string> cmd = {std::string(HG_BIN_DIR) + "/hg-path-planner",
                                    "--log-level",
                                    "info",
                                    "--outline-max-age",
                                    "30",
                                    "--cell",
                                    hg::test::shipped_cell(),
                                    "--lcm-url",
                                    kPlannerUrl};
    cmd.insert(cmd.end(), extra.begin(), extra.end());
    planner = hg::test::ChildProcess(cmd);
    ASSERT_TRUE(planner.started());
    ASSERT_TRUE(bus.wait_for([&] { return !bus.beats.empty(); }, 5s)) << "no heartbeat from hg-path-planner";
    auto o = plate_outline(7);
    bus.a.publish("HG_OUTLINE", &o);
  }
  // Starts a job on the planner and waits for the first copy of its path.
  void plan(const std::string& job) {
    auto r = request(job, job_request_t::ACTION_START);
    bus.a.publish("HG_JOB_REQUEST", &r);
    ASSERT_TRUE(bus.wait_for([&] { return !bus.copies(job).empty(); }, 10s)) << "no path for " << job;
  }
  // Plans the job, lets the robot bridge hold revision 1 and asks for a REPLAN: the time revision 2 came.
  Clock::time_point replan(const std::string& job) {
    plan(job);
    send_status(bridge_status(job, S::STATE_AWAITING_APPROVAL, 1));  // holds revision 1: REPLAN allowed
    auto r = request(job, job_request_t::ACTION_REPLAN);
    r.tool_radius = 0.004;
    bus.a.publish("HG_JOB_REQUEST", &r);
    EXPECT_TRUE(bus.wait_for([&] { return !bus.copies(job, 2).empty(); }, 10s)) << "no revision 2 of " << job;
    return bus.copies(job, 2).empty() ? Clock::now() : bus.copies(job, 2).front()->at;
  }
  void send_status(const S& s) { bus.a.publish("HG_JOB_STATUS", &s); }
  bool logged(const std::string& text, std::int8_t level) const {
    for (const auto& l : bus.logs)
      if (l.process == "hg-path-planner" && l.level == level && l.text.find(text) != std::string::npos) return true;
    return false;
  }
  void TearDown() override {
    if (HasFailure())
      for (const auto& s : bus.statuses)
        std::fprintf(stderr, "status %s %s %d rev %d%s: %s\n", s.source.c_str(), s.job_id.c_str(), int(s.state),
                     int(s.plan_revision), s.answer ? " (answer)" : "", s.message.c_str());
    if (planner.started()) {
      EXPECT_EQ(planner.stop(), 0) << "unclean exit";
    }
  }
  explicit PathResend(bool relay = false) : bus(relay) {}
  Bus bus;
  hg::test::ChildProcess planner;
};

// Scheduling slack of a busy 2-core machine: a copy is due at a multiple of the period after the first and
// goes out on the planner's next 0.1 s tick.
constexpr double kTick = 0.1, kSlack = 0.4;

}  // namespace

// No robot bridge on the bus: the path goes out once and `path-resends` more times, identical, a period
// apart, then a warning and nothing more.
TEST_F(PathResend, WithoutARobotBridgeThePathIsResentAtThePeriodThenGivenUp) {
  const double period = 0.2;
  const int resends = 5;
  start_planner({"--path-resend-period", "0.2", "--path-resends", "5"});
  plan("lonely");
  ASSERT_TRUE(bus.wait_for([&] { return bus.copies("lonely").size() >= resends + 1u; },
                           std::chrono::milliseconds(int((period + kTick + kSlack) * resends * 1000) + 2000)));
  bus.listen(std::chrono::milliseconds(int((3 * period + kTick + kSlack) * 1000)));
  const auto c = bus.copies("lonely");
  ASSERT_EQ(c.size(), resends + 1u) << "the first publication and path-resends copies";
  for (std::size_t i = 1; i < c.size(); ++i) {
    EXPECT_EQ(c[i]->bytes, c[0]->bytes) << "copy " << i << " differs from the path first published";
    const double gap = since(c[i - 1]->at, c[i]->at);
    EXPECT_GE(gap, period - 0.03) << "copy " << i;  // received: a few ms of jitter either way
    EXPECT_LE(gap, period + kTick + kSlack) << "copy " << i;
  }
  EXPECT_GE(since(c[0]->at, c.back()->at), resends * period - 0.03);
  ASSERT_TRUE(bus.wait_for([&] { return logged("not acknowledged by the robot bridge in", 2); }, 3s))
      << "no warning when the planner gave up";
  EXPECT_TRUE(logged("re-sent (5 of 5)", 1));
  EXPECT_TRUE(logged("5 re-sends since the start", 1));
}

// A status of the robot bridge with the path's revision acknowledges it (ACCEPTED, revision 0, does not);
// so does any end of the job, from anyone, and the robot bridge's answer to a copy.
TEST_F(PathResend, AnAcknowledgedPathIsNotSentAgain) {
  const double period = 0.2;
  start_planner({"--path-resend-period", "0.2", "--path-resends", "20"});
  plan("held");
  send_status(bridge_status("held", S::STATE_ACCEPTED, 0));  // plan revision 0: no acknowledgement
  const std::size_t before = bus.copies("held").size();
  ASSERT_TRUE(bus.wait_for([&] { return bus.copies("held").size() >= before + 2; }, 3s))
      << "ACCEPTED (plan revision 0) stopped the copies";
  send_status(bridge_status("held", S::STATE_AWAITING_APPROVAL, 1));
  auto acked = Clock::now();
  bus.listen(std::chrono::milliseconds(int((5 * period + kSlack) * 1000)));
  // One copy may have been on its way when the status went out; without the acknowledgement, five more.
  EXPECT_LE(bus.copies_after("held", acked), 1);

  plan("ended");  // ended upstream (not the robot bridge): no copy wanted either
  S failed = bridge_status("ended", S::STATE_FAILED, 0);
  failed.source = "hg-dds-gateway";
  send_status(failed);
  acked = Clock::now();
  plan("answered");  // the robot bridge's answer to a copy of a path it already took
  send_status(bridge_status("answered", S::STATE_RUNNING, 1, true));
  const auto answered = Clock::now();
  bus.listen(std::chrono::milliseconds(int((5 * period + kSlack) * 1000)));
  EXPECT_LE(bus.copies_after("ended", acked), 1);
  EXPECT_LE(bus.copies_after("answered", answered), 1);
  EXPECT_FALSE(logged("no more copies", 2));
}

// A REPLAN's revision is re-sent until acknowledged, on its own: the acknowledgement of revision 1 does not
// acknowledge revision 2, and revision 1 is not sent again.
TEST_F(PathResend, AReplansRevisionIsResentUntilAcknowledged) {
  const double period = 0.2;
  start_planner({"--path-resend-period", "0.2", "--path-resends", "20"});
  const auto first2 = replan("r");
  // The robot bridge still speaks of revision 1 (an approval refused): revision 2 is not acknowledged.
  send_status(bridge_status("r", S::STATE_AWAITING_APPROVAL, 1, true));
  ASSERT_TRUE(bus.wait_for([&] { return bus.copies("r", 2).size() >= 4; },
                           std::chrono::milliseconds(int((3 * (period + kTick) + kSlack) * 1000) + 1000)))
      << "revision 2 not re-sent";
  for (const PathCopy* c : bus.copies("r", 1)) EXPECT_LT(c->at, first2) << "revision 1 sent after revision 2";
  send_status(bridge_status("r", S::STATE_AWAITING_APPROVAL, 2));
  const auto acked = Clock::now();
  bus.listen(std::chrono::milliseconds(int((5 * period + kSlack) * 1000)));
  EXPECT_LE(bus.copies_after("r", acked, 2), 1);
  EXPECT_TRUE(logged("path revision 2 acknowledged (hg-robot-bridge, AWAITING_APPROVAL) after", 1));
}

// An operator approved revision 1 while revision 2 was on its way: the robot bridge runs revision 1 and takes
// no other, so its RUNNING ends the copies of revision 2.
TEST_F(PathResend, TheRobotBridgeRunningAnOlderRevisionEndsTheCopies) {
  const double period = 0.2;
  start_planner({"--path-resend-period", "0.2", "--path-resends", "20"});
  replan("q");
  ASSERT_TRUE(bus.wait_for([&] { return bus.copies("q", 2).size() >= 2; }, 3s)) << "revision 2 not re-sent";
  send_status(bridge_status("q", S::STATE_RUNNING, 1));
  const auto running = Clock::now();
  bus.listen(std::chrono::milliseconds(int((5 * period + kSlack) * 1000)));
  EXPECT_LE(bus.copies_after("q", running, 2), 1);
}

namespace {
class PathResendEndToEnd : public PathResend {
 protected:
  PathResendEndToEnd() : PathResend(true) {}
};
}  // namespace

// The real robot bridge (simulated robot, its own bus) misses the first copy of the path: it takes the next
// one, and the job ends DONE, with the shipped defaults (0.5 s, 20 copies), long before its path timeout.
TEST_F(PathResendEndToEnd, TheRobotBridgeMissesTheFirstPathAndTheJobStillEndsDone) {
  const double period = 0.5, path_timeout = 60;  // the shipped defaults (docs/PARAMETERS.md)
  start_planner({});
  hg::test::ChildProcess bridge({std::string(HG_BIN_DIR) + "/hg-robot-bridge", "--driver", "sim", "--sim-time-scale",
                                 "20", "--lcm-url", kBridgeUrl, "--cell", hg::test::shipped_cell(), "--log-level",
                                 "warn"});
  ASSERT_TRUE(bridge.started());
  ASSERT_TRUE(bus.wait_for([&] { return bus.robot_reports > 5; }, 10s)) << "no robot_status_t from the bridge";
  auto start = request("e2e", job_request_t::ACTION_START);
  bus.b->publish("HG_JOB_REQUEST", &start);
  ASSERT_TRUE(bus.wait_for([&] { return bus.has("e2e", S::STATE_ACCEPTED, "hg-robot-bridge"); }, 5s));
  const auto t0 = Clock::now();
  bus.a.publish("HG_JOB_REQUEST", &start);
  ASSERT_TRUE(bus.wait_for([&] { return bus.has("e2e", S::STATE_AWAITING_APPROVAL, "hg-robot-bridge"); }, 20s))
      << "the robot bridge never held the plan";
  EXPECT_EQ(bus.dropped, 1);
  const auto c = bus.copies("e2e");
  ASSERT_GE(c.size(), 2u);
  Clock::time_point held_at{};
  for (const auto& [s, at] : bus.relayed)
    if (s.state == S::STATE_AWAITING_APPROVAL && !s.answer) held_at = at;
  const double held_after = since(c[0]->at, held_at);
  EXPECT_GE(held_after, period - 0.03) << "held before a copy was due: the first copy was not lost";
  EXPECT_LT(held_after, period + kTick + kSlack + 1.0) << "the path took longer than one copy";
  auto approve = request("e2e", job_request_t::ACTION_APPROVE);
  approve.actor = "operator resend_test";
  approve.plan_revision = 1;
  bus.b->publish("HG_JOB_REQUEST", &approve);
  ASSERT_TRUE(bus.wait_for([&] { return bus.has("e2e", S::STATE_DONE, "hg-robot-bridge"); }, 60s))
      << "the job did not end DONE";
  EXPECT_LT(since(t0, Clock::now()), path_timeout);
  EXPECT_FALSE(bus.has("e2e", S::STATE_FAILED, "hg-robot-bridge"));
  // Acknowledged by AWAITING_APPROVAL: no copy after it (one may have been on its way).
  EXPECT_LE(bus.copies_after("e2e", held_at), 1);
  EXPECT_EQ(bridge.stop(), 0);
}
