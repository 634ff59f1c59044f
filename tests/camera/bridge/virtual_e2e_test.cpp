// End to end through OpenNI2: our virtual OpenNI2 device (libhg-virtual.so.0, loaded by Debian's libOpenNI2
// from the private folder) -> hg-camera-bridge --source openni2 -> HG_PLATE_CLOUD, decoded here, in a
// private network namespace. The virtual device serves frame n as render(scene, profile, n), so the test
// recomputes each received cloud from that frame through the segmentation library and compares point by
// point (which also checks the scan-line order, asserted strictly by the segmentation suite).
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <sys/wait.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include "sim/scene/scene.hpp"
#include "camera_bridge/segment.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/plate_cloud_t.hpp"
#include "tests/common/camera_bus.hpp"
#include "tests/common/child_process.hpp"

using namespace std::chrono_literals;
using namespace hg::camera_bridge;
using namespace hg::sim;
using Clock = std::chrono::steady_clock;

namespace {

using Bus = hg::test::CameraBus;

// hg-camera-bridge on the virtual OpenNI2 device at `uri`, every part published, frames as they come.
struct Bridge : hg::test::ChildProcess {
  explicit Bridge(const std::string& uri, const std::vector<std::string>& extra = {})
      : ChildProcess(
            [&] {
              std::vector<std::string> args{std::string(HG_BIN_DIR) + "/hg-camera-bridge",
                                            "--source",
                                            "openni2",
                                            "--openni2.uri",
                                            uri,
                                            "--parts",
                                            "all",
                                            "--rate",
                                            "0",
                                            "--log-level",
                                            "warn"};
              args.insert(args.end(), extra.begin(), extra.end());
              return args;
            }(),
            // libOpenNI2 + OpenNI2/Drivers/libhg-virtual.so.0
            hg::test::ChildOptions().set_env("LD_LIBRARY_PATH", HG_OPENNI2_PRIVATE_DIR)) {}
};

// The renderer's 8-bit intensity image as docs/openni2.md says it reaches the bridge through the virtual
// device's default IR mode: GRAY16 with 10 bits (round(i * 1023 / 255)), scaled by the source so that the
// stream's MAX_VALUE 1023 is 65535.
cv::Mat intensity_through_openni2(const cv::Mat& intensity8) {
  cv::Mat ten(intensity8.size(), CV_16UC1), out;
  for (int y = 0; y < ten.rows; ++y)
    for (int x = 0; x < ten.cols; ++x)
      ten.at<std::uint16_t>(y, x) = std::uint16_t(std::lround(intensity8.at<std::uint8_t>(y, x) * 1023.0 / 255.0));
  ten.convertTo(out, CV_16UC1, 65535.0 / 1023.0);
  return out;
}

// `with_intensity`: the bridge had the frame's intensity image (the device's IR stream).
void expect_matches_recomputed(const hullgrind::plate_cloud_t& m, const std::string& scene, const std::string& profile,
                               bool with_intensity = false) {
  ASSERT_EQ(m.status, +hullgrind::plate_cloud_t::STATUS_OK) << m.status_text;
  const RenderedFrame f =
      render(scene_preset(scene), camera_profile(profile), static_cast<std::uint64_t>(m.source_frame_seq));
  SegmentParams p;
  p.all_parts = true;
  const Segmentation s =
      segment(f.depth, f.intrinsics, p, with_intensity ? intensity_through_openni2(f.intensity) : cv::Mat());
  EXPECT_EQ(m.dropout_filled, s.dropout_filled) << "frame " << m.source_frame_seq;
  ASSERT_EQ(s.status, SegmentStatus::Ok);
  EXPECT_EQ(m.num_parts, s.num_parts);
  // The device reports fx through a float field of view (1e-7 relative): the same pixels, the same order,
  // coordinates equal to well under a micrometre... allow 10 um.
  ASSERT_EQ(m.n, static_cast<int>(s.size())) << "frame " << m.source_frame_seq;
  double worst = 0;
  for (int i = 0; i < m.n; ++i) {
    worst = std::max({worst, std::abs(double(m.u[i]) - s.u[i]), std::abs(double(m.v[i]) - s.v[i])});
    ASSERT_EQ(m.part[i], s.part[i]) << "point " << i;
  }
  EXPECT_LT(worst, 1e-5) << "frame " << m.source_frame_seq;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.plane_normal[k], s.normal[k], 1e-6);
}

TEST(CameraBridgeVirtualDevice, OpenNI2ToPlateCloud) {
  Bus bus;
  Bridge bridge("hg-virtual://three-parts?profile=pm806&fps=5");
  ASSERT_TRUE(bus.until([&] { return bus.clouds.size() >= 2; })) << "no clouds through OpenNI2";
  for (const auto& m : bus.clouds) expect_matches_recomputed(m, "three-parts", "pm806");
  EXPECT_EQ(bus.clouds[0].num_parts, 3);
  EXPECT_EQ(bridge.stop(), 0);
}

// A realistic scene's glints (saturated, no depth) are steel only with the intensity image: the bridge gets
// it from the device's IR stream, and without it (--openni2.ir false) the cloud is the depth-only one.
TEST(CameraBridgeVirtualDevice, TheIrStreamReachesTheSegmentation) {
  const std::string scene = "plate-hole-slot-realistic";
  for (const bool ir : {true, false}) {
    Bus bus;
    Bridge bridge("hg-virtual://" + scene + "?profile=pm806&fps=5", {"--openni2.ir", ir ? "true" : "false"});
    ASSERT_TRUE(bus.until([&] { return !bus.clouds.empty(); })) << "no cloud through OpenNI2, ir " << ir;
    const hullgrind::plate_cloud_t& m = bus.clouds.front();
    expect_matches_recomputed(m, scene, "pm806", ir);
    if (ir) {  // and the intensity image made a difference: depth alone gives another cloud
      const RenderedFrame f = render(scene_preset(scene), camera_profile("pm806"), std::uint64_t(m.source_frame_seq));
      SegmentParams p;
      p.all_parts = true;
      EXPECT_NE(m.n, static_cast<int>(segment(f.depth, f.intrinsics, p).size()));
    }
    EXPECT_EQ(bridge.stop(), 0);
  }
}

TEST(CameraBridgeVirtualDevice, DeviceLossAndRecoveryThroughOpenNI2) {
  Bus bus;
  // The virtual device disconnects after 4 frames and comes back 2 s later (OpenNI2 events).
  Bridge bridge("hg-virtual://l-bracket?profile=pm806&fps=10&disconnect_after=4&reconnect_after=2",
                {"--retry-min", "0.25", "--retry-max", "1"});
  auto state_is = [&](std::int8_t s) { return !bus.beats.empty() && bus.beats.back().state == s; };
  ASSERT_TRUE(bus.until([&] { return !bus.clouds.empty(); }));
  ASSERT_TRUE(bus.until([&] { return state_is(hullgrind::heartbeat_t::STATE_ERROR); }));
  EXPECT_FALSE(bus.beats.back().state_text.empty());
  const size_t before = bus.clouds.size();
  ASSERT_TRUE(bus.until([&] { return state_is(hullgrind::heartbeat_t::STATE_OK) && bus.clouds.size() > before; }))
      << "state text: " << (bus.beats.empty() ? "" : bus.beats.back().state_text);
  expect_matches_recomputed(bus.clouds.back(), "l-bracket", "pm806");
  EXPECT_EQ(bridge.stop(), 0);
}

}  // namespace
