// The virtual OpenNI2 device as any OpenNI2 application sees it: enumerated, opened by URI, streaming the
// renderer's frames with the profile's field of view, and its URI grammar.
#include <cmath>
#include <stdexcept>

#include "sim/virtual_device/virtual_config.hpp"
#include "openni2_test_util.hpp"

namespace hg::camera_bridge {
namespace {

using namespace testing;
using sim::virtual_device::parse_virtual_uri;
using sim::virtual_device::to_uri;
using sim::virtual_device::VirtualDeviceConfig;

TEST(OpenNI2VirtualUri, ParsesEveryOption) {
  const auto c = parse_virtual_uri(
      "hg-virtual://three-parts?profile=lsr-l&fps=2.5&seed=9&disconnect_after=4&reconnect_after=0.25&cropping=0");
  EXPECT_EQ(c.scene, "three-parts");
  EXPECT_EQ(c.profile, "lsr-l");
  EXPECT_EQ(c.fps, 2.5);
  EXPECT_EQ(c.seed, 9u);
  EXPECT_EQ(c.disconnect_after, 4u);
  EXPECT_EQ(c.reconnect_after, 0.25);
  EXPECT_FALSE(c.cropping_property);
  const auto d = parse_virtual_uri("hg-virtual://demo");
  EXPECT_EQ(d.profile, VirtualDeviceConfig{}.profile);
  EXPECT_FALSE(d.seed.has_value());
  EXPECT_TRUE(d.cropping_property);
}

TEST(OpenNI2VirtualUri, CanonicalFormRoundTrips) {
  VirtualDeviceConfig c;
  c.scene = "ring-flange";
  c.profile = "lsr-l";
  c.fps = 7.5;
  c.seed = 3;
  c.reconnect_after = 1.5;
  const auto back = parse_virtual_uri(to_uri(c));
  EXPECT_EQ(back.scene, c.scene);
  EXPECT_EQ(back.profile, c.profile);
  EXPECT_EQ(back.fps, c.fps);
  EXPECT_EQ(back.seed, c.seed);
  EXPECT_EQ(back.reconnect_after, c.reconnect_after);
  EXPECT_FALSE(back.disconnect_after.has_value());
}

TEST(OpenNI2VirtualUri, BadUrisNameTheByte) {
  auto message = [](const std::string& uri) {
    try {
      parse_virtual_uri(uri);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("file://x").find("byte 0"), std::string::npos);
  EXPECT_NE(message("hg-virtual://").find("no scene"), std::string::npos);
  // "hg-virtual://demo?" is 18 bytes; the value of fps starts at byte 22.
  EXPECT_NE(message("hg-virtual://demo?fps=abc").find("byte 22"), std::string::npos);
  EXPECT_NE(message("hg-virtual://demo?fps=0").find("(0, 120]"), std::string::npos);
  EXPECT_NE(message("hg-virtual://demo?colour=red").find("unknown option 'colour'"), std::string::npos);
  EXPECT_NE(message("hg-virtual://demo?profile").find("key=value"), std::string::npos);
  EXPECT_NE(message("hg-virtual://demo?cropping=2").find("0 or 1"), std::string::npos);
}

TEST(OpenNI2VirtualDevice, EnumeratedByOpenNI) {
  init_openni_from_private_folder();
  const std::string announced = sim::virtual_device::announced_uri_from_environment();
  openni::Array<openni::DeviceInfo> list;
  openni::OpenNI::enumerateDevices(&list);
  bool found = false;
  for (int i = 0; i < list.getSize(); ++i)
    if (announced == list[i].getUri()) {
      found = true;
      EXPECT_STREQ(list[i].getVendor(), "hullgrind");
    }
  EXPECT_TRUE(found) << "announced " << announced << ", OpenNI lists " << list.getSize() << " device(s)";
}

TEST(OpenNI2VirtualDevice, StreamsTheRenderersFrames) {
  init_openni_from_private_folder();
  const std::string uri = "hg-virtual://plate-hole-slot?profile=pm806&fps=20&seed=7";
  openni::Device device;
  ASSERT_EQ(device.open(uri.c_str()), openni::STATUS_OK) << openni::OpenNI::getExtendedError();
  EXPECT_EQ(std::string(device.getDeviceInfo().getUri()), uri);
  openni::VideoStream stream;
  ASSERT_EQ(stream.create(device, openni::SENSOR_DEPTH), openni::STATUS_OK);
  const sim::CameraProfile profile = sim::camera_profile("pm806");
  const openni::VideoMode mode = stream.getVideoMode();
  EXPECT_EQ(mode.getResolutionX(), profile.width);
  EXPECT_EQ(mode.getResolutionY(), profile.height);
  EXPECT_EQ(mode.getFps(), 20);
  EXPECT_EQ(mode.getPixelFormat(),
            profile.depth_unit == 0.001 ? openni::PIXEL_FORMAT_DEPTH_1_MM : openni::PIXEL_FORMAT_DEPTH_100_UM);
  ASSERT_EQ(stream.start(), openni::STATUS_OK);
  int checked = 0, last_index = 0;
  for (int attempt = 0; attempt < 50 && checked < 3; ++attempt) {
    openni::VideoStream* s = &stream;
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream(&s, 1, &ready, 5000) != openni::STATUS_OK) continue;
    openni::VideoFrameRef f;
    ASSERT_EQ(stream.readFrame(&f), openni::STATUS_OK);
    ASSERT_GT(f.getFrameIndex(), last_index);  // frames arrive in order (a slow reader may skip some)
    last_index = f.getFrameIndex();
    // Device clock: frame n at (n - 1) / fps seconds.
    EXPECT_EQ(f.getTimestamp(), std::uint64_t(std::llround((f.getFrameIndex() - 1) * 1e6 / 20)));
    const cv::Mat got(f.getHeight(), f.getWidth(), CV_16UC1, const_cast<void*>(f.getData()), f.getStrideInBytes());
    EXPECT_EQ(differing_pixels(got, expected_depth("plate-hole-slot", "pm806", 7, f.getFrameIndex())), 0)
        << "frame " << f.getFrameIndex();
    ++checked;
  }
  EXPECT_EQ(checked, 3);
  stream.stop();
  stream.destroy();
  device.close();
}

TEST(OpenNI2VirtualDevice, OtherDepthUnitIsRecountedFromTheSameFrame) {
  init_openni_from_private_folder();
  const std::string uri = "hg-virtual://l-bracket?profile=pm806&fps=20&seed=11";
  openni::Device device;
  ASSERT_EQ(device.open(uri.c_str()), openni::STATUS_OK) << openni::OpenNI::getExtendedError();
  openni::VideoStream stream;
  ASSERT_EQ(stream.create(device, openni::SENSOR_DEPTH), openni::STATUS_OK);
  const sim::CameraProfile profile = sim::camera_profile("pm806");
  const bool native_mm = profile.depth_unit == 0.001;
  openni::VideoMode mode = stream.getVideoMode();
  mode.setPixelFormat(native_mm ? openni::PIXEL_FORMAT_DEPTH_100_UM : openni::PIXEL_FORMAT_DEPTH_1_MM);
  ASSERT_EQ(stream.setVideoMode(mode), openni::STATUS_OK);
  ASSERT_EQ(stream.start(), openni::STATUS_OK);
  openni::VideoFrameRef f;
  ASSERT_EQ(stream.readFrame(&f), openni::STATUS_OK);
  EXPECT_EQ(f.getVideoMode().getPixelFormat(), mode.getPixelFormat());
  const cv::Mat native = expected_depth("l-bracket", "pm806", 11, f.getFrameIndex());
  const double ratio = profile.depth_unit / (native_mm ? 0.0001 : 0.001);
  cv::Mat want(native.size(), CV_16UC1);
  for (int y = 0; y < native.rows; ++y)
    for (int x = 0; x < native.cols; ++x)
      want.at<std::uint16_t>(y, x) =
          std::uint16_t(std::min<long>(std::lround(native.at<std::uint16_t>(y, x) * ratio), 65534));
  const cv::Mat got(f.getHeight(), f.getWidth(), CV_16UC1, const_cast<void*>(f.getData()), f.getStrideInBytes());
  EXPECT_EQ(differing_pixels(got, want), 0);
  f.release();  // the frame belongs to the stream: released before the stream is destroyed
  stream.stop();
  stream.destroy();
  device.close();
}

TEST(OpenNI2VirtualDevice, FieldOfViewGivesTheProfilesFocalLengths) {
  init_openni_from_private_folder();
  for (const char* name : {"pm806", "lsr-l"}) {
    const sim::CameraProfile profile = sim::camera_profile(name);
    const std::string uri = std::string("hg-virtual://empty?profile=") + name;
    openni::Device device;
    ASSERT_EQ(device.open(uri.c_str()), openni::STATUS_OK) << openni::OpenNI::getExtendedError();
    openni::VideoStream stream;
    ASSERT_EQ(stream.create(device, openni::SENSOR_DEPTH), openni::STATUS_OK);
    const double fx = profile.width / (2.0 * std::tan(stream.getHorizontalFieldOfView() / 2.0));
    const double fy = profile.height / (2.0 * std::tan(stream.getVerticalFieldOfView() / 2.0));
    EXPECT_NEAR(fx / profile.fx, 1.0, 1e-6) << name;
    EXPECT_NEAR(fy / profile.fy, 1.0, 1e-6) << name;
    stream.destroy();
    device.close();
  }
}

TEST(OpenNI2VirtualDevice, UnknownSceneIsRefusedAtOpen) {
  init_openni_from_private_folder();
  openni::Device device;
  EXPECT_NE(device.open("hg-virtual://no-such-scene?profile=pm806"), openni::STATUS_OK);
  // Our driver's own message (not just OpenNI's "couldn't open"), saying why.
  EXPECT_NE(std::string(openni::OpenNI::getExtendedError()).find("hg-virtual: "), std::string::npos)
      << openni::OpenNI::getExtendedError();
}

}  // namespace
}  // namespace hg::camera_bridge
