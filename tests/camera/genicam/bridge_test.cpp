// hg-camera-bridge --source genicam on the bus, with the fake GigE Vision 3-D camera in this test process,
// all inside the test's own network namespace (loopback only):
//  - job trigger: one job -> one software-triggered frame -> the plate cloud the rendering segments to;
//  - packet loss: incomplete frames counted as dropped in the heartbeat and skipped, clouds again after;
//  - the camera goes away: heartbeat ERROR naming the lost camera; it comes back: re-opened (back-off),
//    heartbeat OK and clouds again.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "sim/fake_genicam/fake_camera.hpp"
#include "sim/scene/scene.hpp"
#include "camera_bridge/segment.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"
#include "tests/common/camera_bus.hpp"
#include "tests/common/child_process.hpp"

using namespace std::chrono_literals;
using namespace hg::camera_bridge;
using namespace hg::sim;
using Clock = std::chrono::steady_clock;

namespace {

const std::string kExe = std::string(HG_BIN_DIR) + "/hg-camera-bridge";
using Bus = hg::test::CameraBus;

FakeGenicamOptions fake_options(std::uint64_t seed) {
  FakeGenicamOptions o;
  o.scene = scene_preset("plate-hole-slot");
  o.scene.seed = seed;
  o.profile = camera_profile("pm806");
  o.profile.cx -= 17.5;  // a principal point that is not the image centre
  o.profile.cy += 8.25;
  o.scale_mm = 0.05;
  o.offset_mm = 600.0;
  o.fixed_frame_index = 1;
  o.frame_rate = 4;
  return o;
}

}  // namespace

TEST(GenicamBridgeProcess, JobTriggeredCloudEqualsTheRenderingsSegmentation) {
  FakeGenicamCamera cam(fake_options(21));
  Bus bus;
  hg::test::ChildProcess proc({kExe, "--source", "genicam", "--trigger", "job", "--log-level", "warn"});
  ASSERT_TRUE(bus.until([&] { return bus.last_state_is(hullgrind::heartbeat_t::STATE_OK); })) << "bridge not OK";
  hullgrind::job_request_t j{};
  j.job_id = "genicam-job-1";
  j.part_id = "test";
  j.action = hullgrind::job_request_t::ACTION_START;
  bus.lcm.publish("HG_JOB_REQUEST", &j);
  ASSERT_TRUE(bus.until([&] { return !bus.clouds.empty(); })) << "no cloud for the job";
  const hullgrind::plate_cloud_t& m = bus.clouds[0];
  ASSERT_EQ(m.status, +hullgrind::plate_cloud_t::STATUS_OK) << m.status_text;
  // The expectation: the rendering the device served, segmented here with the bridge's default parameters.
  const RenderedFrame r = render(cam.options().scene, cam.options().profile, 1);
  const Segmentation s = segment(r.depth, r.intrinsics, SegmentParams{});
  ASSERT_EQ(s.status, SegmentStatus::Ok) << s.text;
  ASSERT_EQ(std::size_t(m.n), s.size());
  double worst = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    worst = std::max({worst, std::abs(double(m.u[i]) - s.u[i]), std::abs(double(m.v[i]) - s.v[i])});
  EXPECT_LE(worst, 1e-6);
  EXPECT_NEAR(m.thickness, s.thickness, 1e-6);
  EXPECT_LE(cam.frames_served(), 3) << "job trigger must not free-run the camera";
}

TEST(GenicamBridgeProcess, IncompleteFramesAreDroppedInTheHeartbeatAndSkipped) {
  FakeGenicamCamera cam(fake_options(23));
  Bus bus;
  hg::test::ChildProcess proc(
      {kExe, "--source", "genicam", "--rate", "0", "--depth-rate", "0", "--log-level", "error"});
  ASSERT_TRUE(bus.until([&] { return !bus.clouds.empty(); })) << "no clouds from the free-running camera";
  cam.set_packet_loss(0.5);  // every frame loses packets (the fake device never resends)
  ASSERT_TRUE(bus.until([&] { return !bus.beats.empty() && bus.beats.back().dropped >= 2; }))
      << "incomplete frames not counted as dropped";
  cam.set_packet_loss(0.0);
  const std::size_t before = bus.clouds.size();
  ASSERT_TRUE(bus.until([&] { return bus.clouds.size() >= before + 2; })) << "no clouds after the loss ended";
  EXPECT_EQ(bus.clouds.back().status, +hullgrind::plate_cloud_t::STATUS_OK) << bus.clouds.back().status_text;
  EXPECT_NE(bus.beats.back().state, +hullgrind::heartbeat_t::STATE_ERROR) << bus.beats.back().state_text;
}

TEST(GenicamBridgeProcess, LostCameraSetsErrorAndIsReopened) {
  auto cam = std::make_unique<FakeGenicamCamera>(fake_options(22));
  const std::string id = cam->device_id();
  Bus bus;
  hg::test::ChildProcess proc({kExe, "--source", "genicam", "--rate", "2", "--retry-min", "0.25", "--retry-max", "1",
                               "--depth-rate", "0", "--log-level", "warn"});
  ASSERT_TRUE(bus.until([&] { return bus.clouds.size() >= 2; })) << "no clouds from the free-running camera";
  cam.reset();
  ASSERT_TRUE(bus.until([&] { return bus.last_state_is(hullgrind::heartbeat_t::STATE_ERROR); }))
      << "the lost camera never showed in the heartbeat";
  const std::string why = bus.beats.back().state_text;
  EXPECT_NE(why.find("genicam"), std::string::npos) << why;
  EXPECT_NE(why.find("retrying"), std::string::npos) << why;
  const std::size_t before = bus.clouds.size();
  cam = std::make_unique<FakeGenicamCamera>(fake_options(22));
  ASSERT_TRUE(bus.until([&] { return bus.last_state_is(hullgrind::heartbeat_t::STATE_OK); })) << "never OK again";
  ASSERT_TRUE(bus.until([&] { return bus.clouds.size() >= before + 2; })) << "no clouds after the re-open";
  EXPECT_EQ(bus.clouds.back().status, +hullgrind::plate_cloud_t::STATUS_OK) << bus.clouds.back().status_text;
}
