// hg-dds-gateway as a process, observed from this test through LCM and a DDS participant of its own, in a
// private network namespace: a recorded log crosses with equal content, late joiners get the current state,
// job requests cross checked, invalid ones are refused and never reach LCM.
#include <cmath>
#include <limits>

#include "compare.hpp"
#include "helpers.hpp"
#include "hullgrind/job_request_t.hpp"

using namespace hgtest;
using namespace hg::dds_gateway;

namespace {

constexpr int kDomain = 0;
const std::string kPrefix = "hg_";

// What the tests read with: the topic's own QoS, but keep-all so that the reader itself never drops.
Qos collect_qos(bool state) {
  Qos q = state ? state_qos() : stream_qos();
  dds_qset_history(q.get(), DDS_HISTORY_KEEP_ALL, 0);
  return q;
}

class DdsGatewayBridge : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(lcm.good()) << "no LCM: the test must run inside tests/netns.sh";
    gateway = std::make_unique<GatewayProcess>(kDomain, extra_args());
    pp = make_participant(kDomain, cyclone_config(), {});
    Qos state = collect_qos(true), stream = collect_qos(false);
    outline = std::make_unique<Reader<hgdds_Outline>>(pp, &hgdds_Outline_desc, kPrefix + "outline", state.get());
    part_pose = std::make_unique<Reader<hgdds_PartPose>>(pp, &hgdds_PartPose_desc, kPrefix + "part_pose", stream.get());
    grind_path =
        std::make_unique<Reader<hgdds_GrindPath>>(pp, &hgdds_GrindPath_desc, kPrefix + "grind_path", state.get());
    job_status =
        std::make_unique<Reader<hgdds_JobStatus>>(pp, &hgdds_JobStatus_desc, kPrefix + "job_status", state.get());
    robot_status = std::make_unique<Reader<hgdds_RobotStatus>>(pp, &hgdds_RobotStatus_desc, kPrefix + "robot_status",
                                                               stream.get());
    health = std::make_unique<Reader<hgdds_Health>>(pp, &hgdds_Health_desc, kPrefix + "health", state.get());
    // Up and matched: the gateway's own heartbeat came back as health, and every reader sees its writer.
    ASSERT_TRUE(wait_until([&] { return gateway_health() != nullptr && all_matched(); }, [&] { pump(); }, 20s))
        << "the gateway did not come up on DDS";
    // A reader that sees the writer is not yet seen by it, and the volatile topics send nothing to a reader
    // they do not know: warm them up until one of each crosses, then forget the warm-up samples.
    hullgrind::part_pose_t pose{};
    pose.header.frame_id = "warm-up";
    hullgrind::robot_status_t robot{};
    robot.header.frame_id = "warm-up";
    ASSERT_TRUE(wait_until([&] { return !part_pose->samples.empty() && !robot_status->samples.empty(); },
                           [&] {
                             lcm.publish("HG_PART_POSE", &pose);
                             lcm.publish("HG_ROBOT_STATUS", &robot);
                             wait_until([] { return false; }, [&] { pump(); }, 20ms);
                           },
                           20s))
        << "no part pose or robot status crossed during warm-up";
    wait_until([] { return false; }, [&] { pump(); }, 300ms);  // stragglers
    part_pose->samples.clear();
    robot_status->samples.clear();
  }
  void TearDown() override {
    outline.reset();
    part_pose.reset();
    grind_path.reset();
    job_status.reset();
    robot_status.reset();
    health.reset();
    if (pp > 0) dds_delete(pp);
    if (gateway) {
      EXPECT_TRUE(gateway->running()) << "the gateway died during the test";
    }
    gateway.reset();
  }
  virtual std::vector<std::string> extra_args() { return {"--robot-status-max-rate", "0"}; }

  void pump() {
    lcm.handleTimeout(5);
    outline->take();
    part_pose->take();
    grind_path->take();
    job_status->take();
    robot_status->take();
    health->take();
  }
  bool all_matched() const {
    return outline->matched() > 0 && part_pose->matched() > 0 && grind_path->matched() > 0 &&
           job_status->matched() > 0 && robot_status->matched() > 0 && health->matched() > 0;
  }
  const hgdds_Health* gateway_health() const {
    for (auto it = health->samples.rbegin(); it != health->samples.rend(); ++it)
      if (str((*it)->s.process) == "hg-dds-gateway") return &(*it)->s;
    return nullptr;
  }

  lcm::LCM lcm{hg::runtime::default_lcm_url()};
  std::unique_ptr<GatewayProcess> gateway;
  dds_entity_t pp = 0;
  std::unique_ptr<Reader<hgdds_Outline>> outline;
  std::unique_ptr<Reader<hgdds_PartPose>> part_pose;
  std::unique_ptr<Reader<hgdds_GrindPath>> grind_path;
  std::unique_ptr<Reader<hgdds_JobStatus>> job_status;
  std::unique_ptr<Reader<hgdds_RobotStatus>> robot_status;
  std::unique_ptr<Reader<hgdds_Health>> health;
};

// Every message of a recorded log, decoded by channel.
struct Expected {
  std::vector<hullgrind::outline_t> outline;
  std::vector<hullgrind::part_pose_t> part_pose;
  std::vector<hullgrind::grind_path_t> grind_path;
  std::vector<hullgrind::job_status_t> job_status;
  std::vector<hullgrind::robot_status_t> robot_status;
  std::vector<hullgrind::heartbeat_t> heartbeat;
  std::size_t events = 0;
};

template <class T>
void decode_into(const lcm::LogEvent* ev, std::vector<T>& out) {
  T m;
  ASSERT_EQ(m.decode(ev->data, 0, ev->datalen), ev->datalen) << "log event " << ev->eventnum << " on " << ev->channel;
  out.push_back(m);
}

Expected read_log(const std::string& path) {
  Expected e;
  lcm::LogFile log(path, "r");
  EXPECT_TRUE(log.good()) << path;
  while (const lcm::LogEvent* ev = log.readNextEvent()) {
    ++e.events;
    if (ev->channel == "HG_OUTLINE") decode_into(ev, e.outline);
    else if (ev->channel == "HG_PART_POSE")
      decode_into(ev, e.part_pose);
    else if (ev->channel == "HG_GRIND_PATH")
      decode_into(ev, e.grind_path);
    else if (ev->channel == "HG_JOB_STATUS")
      decode_into(ev, e.job_status);
    else if (ev->channel == "HG_ROBOT_STATUS")
      decode_into(ev, e.robot_status);
    else if (ev->channel == "HG_HEARTBEAT")
      decode_into(ev, e.heartbeat);
  }
  return e;
}

TEST_F(DdsGatewayBridge, ReplayedLogCrossesWithEqualContent) {
  const std::string log = std::string(HG_TEST_DATA) + "/dds_gateway/replay.lcmlog";
  Expected e = read_log(log);
  ASSERT_GT(e.outline.size(), 1u);
  ASSERT_GT(e.grind_path.size(), 1u);
  ASSERT_EQ(e.events, e.outline.size() + e.part_pose.size() + e.grind_path.size() + e.job_status.size() +
                          e.robot_status.size() + e.heartbeat.size())
      << "the log holds channels this test does not check";

  hg::test::ChildProcess player({"/usr/bin/lcm-logplayer", log});
  ASSERT_TRUE(player.started());
  std::optional<int> played;
  ASSERT_TRUE(wait_until([&] { return (played = player.wait()).has_value(); }, [&] { pump(); }, 60s));
  ASSERT_EQ(*played, 0) << "lcm-logplayer failed";

  auto replayed_health = [&] {
    std::vector<const hgdds_Health*> out;
    for (auto& s : health->samples)
      if (str(s->s.process) != "hg-dds-gateway") out.push_back(&s->s);
    return out;
  };
  bool all = wait_until(
      [&] {
        return outline->samples.size() >= e.outline.size() && part_pose->samples.size() >= e.part_pose.size() &&
               grind_path->samples.size() >= e.grind_path.size() && job_status->samples.size() >= e.job_status.size() &&
               robot_status->samples.size() >= e.robot_status.size() && replayed_health().size() >= e.heartbeat.size();
      },
      [&] { pump(); }, 20s);
  EXPECT_TRUE(all) << "missing samples";
  pump();  // anything beyond the expected count would be a duplicate
  ASSERT_EQ(outline->samples.size(), e.outline.size());
  ASSERT_EQ(part_pose->samples.size(), e.part_pose.size());
  ASSERT_EQ(grind_path->samples.size(), e.grind_path.size());
  ASSERT_EQ(job_status->samples.size(), e.job_status.size());
  ASSERT_EQ(robot_status->samples.size(), e.robot_status.size());
  auto hs = replayed_health();
  ASSERT_EQ(hs.size(), e.heartbeat.size());
  // One LCM publisher per channel, one DDS writer per topic: the order is kept.
  for (std::size_t i = 0; i < e.outline.size(); ++i) expect_same(e.outline[i], outline->samples[i]->s);
  for (std::size_t i = 0; i < e.part_pose.size(); ++i) expect_same(e.part_pose[i], part_pose->samples[i]->s);
  for (std::size_t i = 0; i < e.grind_path.size(); ++i) expect_same(e.grind_path[i], grind_path->samples[i]->s);
  for (std::size_t i = 0; i < e.job_status.size(); ++i) expect_same(e.job_status[i], job_status->samples[i]->s);
  for (std::size_t i = 0; i < e.robot_status.size(); ++i) expect_same(e.robot_status[i], robot_status->samples[i]->s);
  for (std::size_t i = 0; i < e.heartbeat.size(); ++i) expect_same(e.heartbeat[i], *hs[i]);
}

hullgrind::outline_t make_outline(int64_t seq, int64_t cloud_seq) {
  hullgrind::outline_t o{};
  o.header.seq = seq;
  o.header.utime = 1700000000000000 + seq;
  o.header.frame_id = "camera";
  o.cloud_seq = cloud_seq;
  o.plane_normal[2] = 1;
  o.plane_u_axis[0] = 1;
  o.plane_v_axis[1] = 1;
  o.alpha_radius = 0.01;
  o.num_loops = 1;
  o.loops.resize(1);
  o.loops[0].n = 4;
  o.loops[0].u = {0, 1, 1, 0};
  o.loops[0].v = {0, 0, 0.5 + 0.1 * double(seq), 0.5 + 0.1 * double(seq)};
  o.loops[0].area = 0.5 + 0.1 * double(seq);
  o.loops[0].perimeter = 2 + 2 * (0.5 + 0.1 * double(seq));
  o.points_used = 100;
  return o;
}

hullgrind::job_status_t make_status(int64_t seq, const std::string& job, int8_t state) {
  hullgrind::job_status_t s{};
  s.header.seq = seq;
  s.header.utime = 1700000000000000 + seq;
  s.job_id = job;
  s.part_id = "part-" + job;
  s.source = "hg-path-planner";
  s.state = state;
  s.progress = 0.25 * double(seq);
  s.message = "step " + std::to_string(seq);
  return s;
}

TEST_F(DdsGatewayBridge, LateJoinerGetsLastOutlineAndJobStatusPerJob) {
  std::vector<hullgrind::outline_t> outlines = {make_outline(0, 100), make_outline(1, 101), make_outline(2, 102)};
  std::vector<hullgrind::job_status_t> statuses = {make_status(0, "job-A", hullgrind::job_status_t::STATE_ACCEPTED),
                                                   make_status(1, "job-B", hullgrind::job_status_t::STATE_ACCEPTED),
                                                   make_status(2, "job-A", hullgrind::job_status_t::STATE_PLANNING),
                                                   make_status(3, "job-A", hullgrind::job_status_t::STATE_PLANNED),
                                                   make_status(4, "job-B", hullgrind::job_status_t::STATE_RUNNING)};
  for (auto& o : outlines) {
    lcm.publish("HG_OUTLINE", &o);
    ASSERT_TRUE(
        wait_until([&] { return outline->samples.size() >= std::size_t(o.header.seq + 1); }, [&] { pump(); }, 10s));
  }
  for (auto& s : statuses) {
    lcm.publish("HG_JOB_STATUS", &s);
    ASSERT_TRUE(
        wait_until([&] { return job_status->samples.size() >= std::size_t(s.header.seq + 1); }, [&] { pump(); }, 10s));
  }

  // A plant system joining now, with a keep-all reader: it must get exactly the current state.
  dds_entity_t late_pp = make_participant(kDomain, cyclone_config(), {});
  Qos q = collect_qos(true);
  Reader<hgdds_Outline> late_outline(late_pp, &hgdds_Outline_desc, kPrefix + "outline", q.get());
  Reader<hgdds_JobStatus> late_status(late_pp, &hgdds_JobStatus_desc, kPrefix + "job_status", q.get());
  auto late_pump = [&] {
    lcm.handleTimeout(5);
    late_outline.take();
    late_status.take();
  };
  ASSERT_TRUE(
      wait_until([&] { return late_outline.samples.size() >= 1 && late_status.samples.size() >= 2; }, late_pump, 10s))
      << "late joiner got " << late_outline.samples.size() << " outlines, " << late_status.samples.size()
      << " statuses";
  // Historical data comes in one go; give stray extra samples a chance to show before counting.
  wait_until([] { return false; }, late_pump, 500ms);
  ASSERT_EQ(late_outline.samples.size(), 1u);
  expect_same(outlines.back(), late_outline.samples[0]->s);
  ASSERT_EQ(late_status.samples.size(), 2u);
  for (auto& s : late_status.samples) {
    const hullgrind::job_status_t& want = str(s->s.job_id) == "job-A" ? statuses[3] : statuses[4];
    expect_same(want, s->s);
  }
  dds_delete(late_pp);
}

hgdds_JobRequest request(const char* job_id) {
  hgdds_JobRequest r{};
  r.header.frame_id = const_cast<char*>("");
  r.job_id = const_cast<char*>(job_id);
  r.part_id = const_cast<char*>("plate 17/B");
  return r;
}

dds_entity_t job_writer(dds_entity_t pp) {
  Qos q = stream_qos();
  return make_writer(pp, make_topic(pp, &hgdds_JobRequest_desc, kPrefix + "job_request"), q.get());
}

bool writer_matched(dds_entity_t w) {
  dds_publication_matched_status_t st{};
  dds_get_publication_matched_status(w, &st);
  return st.current_count > 0;
}

TEST_F(DdsGatewayBridge, JobRequestFromDdsAppearsOnLcm) {
  Collector<hullgrind::job_request_t> requests(lcm, "HG_JOB_REQUEST");
  dds_entity_t w = job_writer(pp);
  ASSERT_TRUE(wait_until([&] { return writer_matched(w); }, [&] { pump(); }, 10s));
  hgdds_JobRequest r = request("MES-2024-0042");
  r.header.utime = 1712345678000000;
  r.action = hullgrind::job_request_t::ACTION_START;
  r.tool_radius = 0.025;
  r.tilt = 0.5;
  r.grind_speed = 0.05;
  r.travel_speed = 0.3;
  r.step = 0.002;
  r.safe_height = 0.05;
  r.direction = hullgrind::job_request_t::DIRECTION_CONVENTIONAL;
  r.flipped = true;
  ASSERT_EQ(dds_write(w, &r), DDS_RETCODE_OK);
  ASSERT_TRUE(wait_until([&] { return !requests.msgs.empty(); }, [&] { pump(); }, 10s)) << "nothing on HG_JOB_REQUEST";
  const hullgrind::job_request_t& m = requests.msgs[0];
  EXPECT_EQ(m.job_id, "MES-2024-0042");
  EXPECT_EQ(m.part_id, "plate 17/B");
  EXPECT_EQ(m.header.utime, 1712345678000000);
  EXPECT_EQ(m.action, +hullgrind::job_request_t::ACTION_START);
  EXPECT_EQ(m.tool_radius, 0.025);
  EXPECT_EQ(m.tilt, 0.5);
  EXPECT_EQ(m.grind_speed, 0.05);
  EXPECT_EQ(m.travel_speed, 0.3);
  EXPECT_EQ(m.step, 0.002);
  EXPECT_EQ(m.safe_height, 0.05);
  EXPECT_EQ(m.direction, +hullgrind::job_request_t::DIRECTION_CONVENTIONAL);
  EXPECT_TRUE(m.flipped);
  wait_until([] { return false; }, [&] { pump(); }, 300ms);
  EXPECT_EQ(requests.msgs.size(), 1u) << "one request must cross once";
}

TEST_F(DdsGatewayBridge, InvalidJobRequestsAreRefusedAndNeverReachLcm) {
  Collector<hullgrind::job_request_t> requests(lcm, "HG_JOB_REQUEST");
  Collector<hullgrind::job_status_t> statuses(lcm, "HG_JOB_STATUS");
  dds_entity_t w = job_writer(pp);
  ASSERT_TRUE(wait_until([&] { return writer_matched(w); }, [&] { pump(); }, 10s));

  struct Case {
    hgdds_JobRequest r;
    std::string status_job_id;  // the key of the refusal
    std::string reason;         // a fragment the refusal must contain
  };
  const std::string long_id(100, 'a');
  std::vector<Case> cases;
  cases.push_back({request(""), "", "job_id is empty"});
  cases.push_back({request("bad id!"), "bad id!", "job_id has a character"});
  cases.push_back({request(long_id.c_str()), std::string(64, 'a'), "more than 64"});
  {
    Case c{request("speed-1"), "speed-1", "grind_speed"};
    c.r.grind_speed = 5.0;
    cases.push_back(c);
  }
  {
    Case c{request("nan-1"), "nan-1", "step is not a finite number"};
    c.r.step = std::numeric_limits<double>::quiet_NaN();
    cases.push_back(c);
  }
  {
    Case c{request("act-1"), "act-1", "action 7"};
    c.r.action = 7;
    cases.push_back(c);
  }
  {
    Case c{request("dir-1"), "dir-1", "direction 3"};
    c.r.direction = 3;
    cases.push_back(c);
  }
  {
    Case c{request("neg-1"), "neg-1", "tool_radius"};
    c.r.tool_radius = -0.01;
    cases.push_back(c);
  }
  {
    Case c{request("part-1"), "part-1", "part_id has a control character"};
    c.r.part_id = const_cast<char*>("a\nb");
    cases.push_back(c);
  }
  for (auto& c : cases) ASSERT_EQ(dds_write(w, &c.r), DDS_RETCODE_OK);
  // A valid request last: once it is on LCM, every earlier one has been handled (one writer, in order).
  hgdds_JobRequest ok = request("marker-ok");
  ASSERT_EQ(dds_write(w, &ok), DDS_RETCODE_OK);
  ASSERT_TRUE(
      wait_until([&] { return !requests.msgs.empty() && statuses.msgs.size() >= cases.size(); }, [&] { pump(); }, 10s));
  ASSERT_EQ(requests.msgs.size(), 1u) << "an invalid request reached HG_JOB_REQUEST";
  EXPECT_EQ(requests.msgs[0].job_id, "marker-ok");

  ASSERT_EQ(statuses.msgs.size(), cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto& s = statuses.msgs[i];
    SCOPED_TRACE("case " + std::to_string(i));
    EXPECT_EQ(s.state, +hullgrind::job_status_t::STATE_REFUSED);
    EXPECT_EQ(s.source, "hg-dds-gateway");
    EXPECT_EQ(s.job_id, cases[i].status_job_id);
    EXPECT_NE(s.message.find(cases[i].reason), std::string::npos) << s.message;
  }
  // The same refusals on DDS, one per key (the last one per job id), none for the valid request.
  ASSERT_TRUE(wait_until([&] { return job_status->samples.size() >= cases.size(); }, [&] { pump(); }, 10s));
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const hgdds_JobStatus& d = job_status->samples[i]->s;
    EXPECT_EQ(d.state, +hullgrind::job_status_t::STATE_REFUSED);
    EXPECT_EQ(str(d.job_id), cases[i].status_job_id);
    EXPECT_EQ(str(d.message), statuses.msgs[i].message);
  }
}

TEST_F(DdsGatewayBridge, UnsecuredGatewayReportsDegradedHealth) {
  ASSERT_TRUE(wait_until([&] { return gateway_health() && gateway_health()->state != 0; }, [&] { pump(); }, 5s));
  const hgdds_Health* h = gateway_health();
  EXPECT_EQ(h->state, +hullgrind::heartbeat_t::STATE_DEGRADED);
  EXPECT_NE(str(h->state_text).find("unauthenticated"), std::string::npos) << str(h->state_text);
}

class DdsGatewayRateLimit : public DdsGatewayBridge {
 protected:
  std::vector<std::string> extra_args() override { return {"--robot-status-max-rate", "5"}; }
};

TEST_F(DdsGatewayRateLimit, RobotStatusIsThinnedAndTheLastAlwaysCrosses) {
  constexpr int kCount = 200;
  for (int i = 0; i < kCount; ++i) {
    hullgrind::robot_status_t r{};
    r.header.seq = i;
    r.mode = hullgrind::robot_status_t::MODE_RUNNING;
    r.path_index = i;
    lcm.publish("HG_ROBOT_STATUS", &r);
    std::this_thread::sleep_for(1ms);
  }
  ASSERT_TRUE(wait_until(
      [&] { return !robot_status->samples.empty() && robot_status->samples.back()->s.header.seq == kCount - 1; },
      [&] { pump(); }, 10s))
      << "the newest robot status did not cross";
  // 200 statuses in >= 0.2 s at 5 Hz: a handful cross, never all; they stay in order.
  EXPECT_LT(robot_status->samples.size(), std::size_t(kCount / 2));
  for (std::size_t i = 1; i < robot_status->samples.size(); ++i)
    EXPECT_GT(robot_status->samples[i]->s.header.seq, robot_status->samples[i - 1]->s.header.seq);
}

// Thinning is deliberate, not a loss: every robot status either crossed or was thinned, and the gateway's
// Health says which, with nothing counted as dropped.
TEST_F(DdsGatewayRateLimit, ThinnedStatusesAreCountedApartFromDropped) {
  constexpr int kCount = 100;
  // The warm-up's statuses were thinned too: start from a heartbeat sent after the warm-up was over.
  ASSERT_TRUE(gateway_health());
  const auto seq0 = gateway_health()->header.seq;
  ASSERT_TRUE(wait_until([&] { return gateway_health()->header.seq >= seq0 + 2; }, [&] { pump(); }, 10s));
  const long long thinned0 = gateway_health()->thinned;
  EXPECT_EQ(gateway_health()->dropped, 0);
  for (int i = 0; i < kCount; ++i) {
    hullgrind::robot_status_t r{};
    r.header.seq = i;
    r.path_index = i;
    lcm.publish("HG_ROBOT_STATUS", &r);
    std::this_thread::sleep_for(1ms);
  }
  ASSERT_TRUE(wait_until(
      [&] { return !robot_status->samples.empty() && robot_status->samples.back()->s.header.seq == kCount - 1; },
      [&] { pump(); }, 10s));
  const long long crossed = static_cast<long long>(robot_status->samples.size());
  // The gateway's next heartbeat (1 Hz) carries the counters of all of them.
  ASSERT_TRUE(
      wait_until([&] { return gateway_health()->thinned - thinned0 + crossed == kCount; }, [&] { pump(); }, 10s))
      << "thinned " << gateway_health()->thinned - thinned0 << ", crossed " << crossed;
  EXPECT_GT(gateway_health()->thinned - thinned0, 0);
  EXPECT_EQ(gateway_health()->dropped, 0) << "thinning counted as loss";
}

}  // namespace
