// The `openni2` DepthSource over the virtual device: frames, intrinsics, device loss and recovery.
#include <chrono>
#include <thread>

#include "camera_bridge/openni2/openni2_source.hpp"
#include "openni2_test_util.hpp"

namespace hg::camera_bridge {
namespace {

using namespace testing;
using namespace std::chrono_literals;

TEST(OpenNI2Source, DeliversTheVirtualDevicesFramesWithIntrinsics) {
  init_openni_from_private_folder();
  OpenNI2Options o;
  o.uri = "hg-virtual://three-parts?profile=lsr-l&fps=10&seed=5";
  auto source = make_openni2_source(o);
  EXPECT_FALSE(source->is_open());
  source->open();
  ASSERT_TRUE(source->is_open());
  const sim::CameraProfile profile = sim::camera_profile("lsr-l");
  std::optional<camera::DepthFrame> first;
  for (int i = 0; i < 3; ++i) {
    std::optional<camera::DepthFrame> f;
    for (int attempt = 0; attempt < 10 && !f; ++attempt) f = source->grab(5s);
    ASSERT_TRUE(f) << "no frame";
    const camera::Intrinsics& in = f->intrinsics;
    EXPECT_EQ(in.width, profile.width);
    EXPECT_EQ(in.height, profile.height);
    EXPECT_NEAR(in.fx / profile.fx, 1.0, 1e-6);  // from the field of view
    EXPECT_NEAR(in.fy / profile.fy, 1.0, 1e-6);
    EXPECT_EQ(in.cx, profile.cx);  // the virtual device's private principal-point property
    EXPECT_EQ(in.cy, profile.cy);
    EXPECT_EQ(in.depth_unit, profile.depth_unit);
    EXPECT_EQ(differing_pixels(f->depth, expected_depth("three-parts", "lsr-l", 5, f->seq)), 0) << "frame " << f->seq;
    if (!first) {
      first = f;
    } else {
      // Device timestamps (frame n at (n - 1) / 10 s) carried into wall-clock microseconds.
      EXPECT_GT(f->seq, first->seq);
      EXPECT_EQ(f->utime - first->utime, (f->seq - first->seq) * 100000);
    }
  }
  source->close();
  EXPECT_FALSE(source->is_open());
}

TEST(OpenNI2Source, EmptyUriOpensTheFirstDevice) {
  init_openni_from_private_folder();
  auto source = make_openni2_source({});
  source->open();
  EXPECT_NE(source->describe().find("first device"), std::string::npos) << source->describe();
  std::optional<camera::DepthFrame> f;
  for (int attempt = 0; attempt < 10 && !f; ++attempt) f = source->grab(5s);
  ASSERT_TRUE(f);
  EXPECT_FALSE(f->depth.empty());
  EXPECT_EQ(f->depth.type(), CV_16UC1);
}

TEST(OpenNI2Source, VideoModePreferenceIsHonouredOrRefused) {
  init_openni_from_private_folder();
  const sim::CameraProfile profile = sim::camera_profile("pm806");
  OpenNI2Options o;
  o.uri = "hg-virtual://demo?profile=pm806&fps=10";
  o.depth_unit = profile.depth_unit == 0.001 ? OpenNI2Options::DepthUnit::tenth_mm : OpenNI2Options::DepthUnit::mm;
  {
    OpenNI2Source source(o);
    source.open();
    std::optional<camera::DepthFrame> f;
    for (int attempt = 0; attempt < 10 && !f; ++attempt) f = source.grab(5s);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->intrinsics.depth_unit, profile.depth_unit == 0.001 ? 0.0001 : 0.001);
  }
  o.width = 640;  // not offered
  OpenNI2Source source(o);
  try {
    source.open();
    FAIL() << "expected SourceError";
  } catch (const camera::SourceError& e) {
    EXPECT_NE(std::string(e.what()).find("device offers: 1280x960"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(source.is_open());
}

TEST(OpenNI2Source, MissingRecordingAndUnknownDeviceAreSourceErrors) {
  init_openni_from_private_folder();
  OpenNI2Options o;
  o.uri = std::string(HG_TEST_TMP) + "/does-not-exist.oni";
  auto source = make_openni2_source(o);
  try {
    source->open();
    FAIL() << "expected SourceError";
  } catch (const camera::SourceError& e) {
    EXPECT_NE(std::string(e.what()).find("does-not-exist.oni"), std::string::npos) << e.what();
  }
  o.uri = "hg-virtual://no-such-scene";
  EXPECT_THROW(make_openni2_source(o)->open(), camera::SourceError);
  o.uri = "usb://nothing-here";
  EXPECT_THROW(make_openni2_source(o)->open(), camera::SourceError);
}

// Grabs until the source throws; returns the frames delivered before (or -1 if it never threw).
int frames_until_loss(camera::DepthSource& source) {
  int frames = 0;
  for (int attempt = 0; attempt < 100; ++attempt) {
    try {
      if (source.grab(2s)) ++frames;
    } catch (const camera::SourceError& e) {
      EXPECT_NE(std::string(e.what()).find("lost"), std::string::npos) << e.what();
      return frames;
    }
  }
  return -1;
}

TEST(OpenNI2Source, LostDeviceThrowsAndStaysLostWithoutReconnect) {
  init_openni_from_private_folder();
  OpenNI2Options o;
  o.uri = "hg-virtual://plate-hole-slot?profile=pm806&fps=30&seed=21&disconnect_after=3";
  auto source = make_openni2_source(o);
  source->open();
  const int frames = frames_until_loss(*source);
  EXPECT_GE(frames, 1);
  EXPECT_LE(frames, 3);                                    // the device serves exactly 3; a slow reader may see fewer
  EXPECT_THROW(source->grab(100ms), camera::SourceError);  // keeps saying so, no crash
  source->close();
  EXPECT_THROW(source->open(), camera::SourceError);  // never comes back: reconnect_after not given
  EXPECT_FALSE(source->is_open());
}

TEST(OpenNI2Source, LostDeviceReopensAfterReconnect) {
  init_openni_from_private_folder();
  OpenNI2Options o;
  o.uri = "hg-virtual://plate-hole-slot?profile=pm806&fps=30&seed=22&disconnect_after=3&reconnect_after=0.3";
  auto source = make_openni2_source(o);
  source->open();
  EXPECT_GE(frames_until_loss(*source), 1);
  source->close();
  // The bridge's retry with back-off, in small: re-open until the device is back (bounded attempts).
  bool reopened = false;
  for (int attempt = 0; attempt < 100 && !reopened; ++attempt) {
    try {
      source->open();
      reopened = true;
    } catch (const camera::SourceError&) {
      std::this_thread::sleep_for(100ms);
    }
  }
  ASSERT_TRUE(reopened);
  std::optional<camera::DepthFrame> f;
  for (int attempt = 0; attempt < 10 && !f; ++attempt) f = source->grab(5s);
  ASSERT_TRUE(f);
  // A new session counts from frame 1 again; its frames are still the renderer's.
  EXPECT_LE(f->seq, 3);
  EXPECT_EQ(differing_pixels(f->depth, expected_depth("plate-hole-slot", "pm806", 22, f->seq)), 0);
}

}  // namespace
}  // namespace hg::camera_bridge
