// hg-outline-service as a process on the bus (inside tests/netns.sh): clouds in, outlines and poses out,
// newest cloud wins under load, garbage and empty clouds answered with error statuses, never a crash.
#include <gtest/gtest.h>

#include <chrono>

#include <lcm/lcm-cpp.hpp>

#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/outline_t.hpp"
#include "hullgrind/part_pose_t.hpp"
#include "runtime/node.hpp"
#include "tests/common/child_process.hpp"
#include "test_clouds.hpp"

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

struct Inbox {
  std::vector<hullgrind::outline_t> outlines;
  std::vector<hullgrind::part_pose_t> poses;
  std::vector<hullgrind::heartbeat_t> beats;
  void on_outline(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::outline_t* m) {
    outlines.push_back(*m);
  }
  void on_pose(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::part_pose_t* m) { poses.push_back(*m); }
  void on_beat(const lcm::ReceiveBuffer*, const std::string&, const hullgrind::heartbeat_t* m) {
    if (m->process == "hg-outline-service") beats.push_back(*m);
  }
};

class OutlineServiceProcess : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(lcm.good());
    lcm.subscribe("HG_OUTLINE", &Inbox::on_outline, &inbox);
    lcm.subscribe("HG_PART_POSE", &Inbox::on_pose, &inbox);
    lcm.subscribe("HG_HEARTBEAT", &Inbox::on_beat, &inbox);
    service = hg::test::ChildProcess(
        {std::string(HG_BIN_DIR) + "/hg-outline-service", "--alpha-radius", "0.012", "--log-level", "warn"});
    ASSERT_TRUE(until([&] { return !inbox.beats.empty(); }, 5s)) << "service did not start";
  }
  void TearDown() override { EXPECT_EQ(service.stop(), 0) << "did not stop cleanly"; }
  template <class F>
  bool until(F done, std::chrono::milliseconds limit) {
    auto end = Clock::now() + limit;
    while (Clock::now() < end) {
      if (done()) return true;
      lcm.handleTimeout(20);
    }
    return done();
  }
  lcm::LCM lcm{hg::runtime::default_lcm_url()};
  Inbox inbox;
  hg::test::ChildProcess service;
};

TEST_F(OutlineServiceProcess, CloudInOutlineAndPoseOut) {
  auto cloud = hg::test::plate_with_hole(0.4, 0.2, 0.1, 0.2, 0.05, 0.15, 0.005);
  cloud.header.seq = 7;
  lcm.publish("HG_PLATE_CLOUD", &cloud);
  ASSERT_TRUE(until([&] { return !inbox.outlines.empty() && !inbox.poses.empty(); }, 10s));
  const auto& o = inbox.outlines.back();
  EXPECT_EQ(o.status, +hullgrind::outline_t::STATUS_OK) << o.error_text;
  EXPECT_EQ(o.cloud_seq, 7);
  EXPECT_EQ(o.num_loops, 2);
  EXPECT_DOUBLE_EQ(o.alpha_radius, 0.012);
  EXPECT_EQ(o.mode, "dshi");  // the process defaults
  EXPECT_EQ(o.order, "brio");
  EXPECT_EQ(o.header.frame_id, "camera");
  // Hole corners chamfered and the edge's inset restored: see compute_test.cpp.
  EXPECT_NEAR(inbox.poses.back().area, 0.0702 + 0.5 * o.point_spacing * (1.2 + 0.4 - 8 * 0.005), 1e-6);
  EXPECT_EQ(inbox.poses.back().cloud_seq, 7);
  // The heartbeat reports the latency of that cloud.
  ASSERT_TRUE(until([&] { return !inbox.beats.empty() && inbox.beats.back().last_latency > 0; }, 3s));
}

TEST_F(OutlineServiceProcess, NewestCloudWinsAndOlderAreCountedAsDropped) {
  // Clouds of ~60k points every 5 ms: the service needs longer than that for each, so clouds waiting
  // for the worker are superseded. (Paced, so that the UDP receive buffer does not overflow: a burst of
  // large messages would be lost in the kernel, before the service could count it.)
  auto big = hg::test::plate_with_hole(0.5, 0.3, 0.1, 0.2, 0.1, 0.2, 0.0015);
  const int sent = 10;
  for (int i = 0; i < sent; ++i) {
    big.header.seq = 100 + i;
    lcm.publish("HG_PLATE_CLOUD", &big);
    lcm.handleTimeout(5);
  }
  ASSERT_TRUE(until([&] { return !inbox.outlines.empty() && inbox.outlines.back().cloud_seq == 100 + sent - 1; }, 60s))
      << "the newest cloud was never answered";
  ASSERT_TRUE(until(
      [&] {
        return !inbox.beats.empty() && inbox.beats.back().received == sent &&
               inbox.beats.back().dropped + int64_t(inbox.outlines.size()) == sent;
      },
      5s))
      << "received != sent or computed + dropped != received";
  EXPECT_GT(inbox.beats.back().dropped, 0);
  for (std::size_t i = 1; i < inbox.outlines.size(); ++i)
    EXPECT_GT(inbox.outlines[i].cloud_seq, inbox.outlines[i - 1].cloud_seq) << "answered out of order";
}

TEST_F(OutlineServiceProcess, GarbageAndEmptyCloudsGiveErrorsNotCrashes) {
  const uint8_t junk[] = {9, 9, 9, 9, 9, 9, 9, 9, 9};
  lcm.publish("HG_PLATE_CLOUD", junk, sizeof junk);
  hullgrind::plate_cloud_t empty{};
  empty.header.seq = 3;
  empty.status = hullgrind::plate_cloud_t::STATUS_NO_PART;
  empty.status_text = "no part on the table";
  lcm.publish("HG_PLATE_CLOUD", &empty);
  ASSERT_TRUE(until([&] { return !inbox.outlines.empty(); }, 5s));
  EXPECT_EQ(inbox.outlines.back().status, +hullgrind::outline_t::STATUS_NO_LOOP);
  EXPECT_EQ(inbox.outlines.back().num_loops, 0);
  EXPECT_NE(inbox.outlines.back().error_text.find("no part on the table"), std::string::npos);
  ASSERT_TRUE(until([&] { return !inbox.beats.empty() && inbox.beats.back().decode_errors == 1; }, 3s));
  EXPECT_FALSE(service.wait().has_value()) << "the service died";
  // Still serving.
  auto cloud = hg::test::plate_with_hole(0.2, 0.2, 1, 1, 1, 1, 0.005);
  cloud.header.seq = 4;
  lcm.publish("HG_PLATE_CLOUD", &cloud);
  ASSERT_TRUE(until([&] { return inbox.outlines.back().cloud_seq == 4; }, 10s));
  EXPECT_EQ(inbox.outlines.back().status, +hullgrind::outline_t::STATUS_OK);
  EXPECT_EQ(inbox.outlines.back().num_loops, 1);
}

}  // namespace
