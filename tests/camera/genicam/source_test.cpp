// The `genicam` source against Aravis's GigE Vision fake camera with our 3-D camera description
// (sim/fake_genicam/hg-fake-3d-camera.xml), inside this test's own network namespace: discovery
// (GVCP broadcast), register access (GVCP) and streaming (GVSP) run for real, on 127.0.0.1.
//  - the namespace has only `lo`, so Aravis's discovery, which enumerates the up IPv4 interfaces, cannot
//    reach any other network;
//  - discovery finds the fake camera as the first 3-D camera; Scan3d features -> intrinsics as served;
//  - frames through `genicam` give the same plate cloud as the same rendering through the `synthetic` path
//    (scenes x seeds, with noise; Coord3D_C16 at 0.05 mm steps and an offset holds the renderer's 1 mm
//    counts exactly);
//  - a coarse step and an offset off the step: depth within the quantisation, the same plate to within it;
//  - Coord3D_ABC32f organized clouds: same depth and plate cloud; the count conversions of both formats;
//  - software trigger: no frame without a trigger;
//  - lost packets: incomplete buffers counted and skipped, good frames again after;
//  - camera gone: SourceError from grab(); back: re-opened, frames again.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <net/if.h>

#include <chrono>
#include <limits>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "sim/fake_genicam/fake_camera.hpp"
#include "camera_bridge/genicam/genicam_source.hpp"
#include "sim/scene/scene.hpp"
#include "camera_bridge/segment.hpp"

using namespace std::chrono_literals;
using namespace hg::camera_bridge;
using namespace hg::camera;
using namespace hg::sim;
using Clock = std::chrono::steady_clock;

namespace {

// A profile whose principal point is not the image centre, as on a real calibrated camera.
CameraProfile off_centre_profile(const std::string& name = "pm806") {
  CameraProfile p = camera_profile(name);
  p.cx += 23.375;
  p.cy -= 11.625;
  return p;
}

FakeGenicamOptions fake_options(const std::string& scene, std::uint64_t seed, std::int64_t frame_index = 2) {
  FakeGenicamOptions o;
  o.scene = scene_preset(scene);
  o.scene.seed = seed;
  o.profile = off_centre_profile();
  o.scale_mm = 0.05;
  o.offset_mm = 400.0;
  o.fixed_frame_index = frame_index;
  return o;
}

// Grabs until a frame comes (bounded: a failure, not a timing, when it never does).
std::optional<DepthFrame> next_frame(GenicamSource& src, int attempts = 40) {
  for (int i = 0; i < attempts; ++i)
    if (auto f = src.grab(1000ms)) return f;
  return std::nullopt;
}

// Pixels whose depth in metres differs between the camera's frame and the rendering it was served from.
int pixels_differing(const DepthFrame& f, const RenderedFrame& r) {
  if (f.depth.size() != r.depth.size()) return -1;
  int diff = 0;
  for (int y = 0; y < r.depth.rows; ++y)
    for (int x = 0; x < r.depth.cols; ++x)
      diff += std::abs(f.depth.at<std::uint16_t>(y, x) * f.intrinsics.depth_unit -
                       r.depth.at<std::uint16_t>(y, x) * r.intrinsics.depth_unit) > 1e-9;
  return diff;
}

std::set<std::string> interfaces_up_ipv4() {
  std::set<std::string> names;
  ifaddrs* ifa = nullptr;
  if (getifaddrs(&ifa) != 0) return names;
  for (ifaddrs* i = ifa; i; i = i->ifa_next)
    if ((i->ifa_flags & IFF_UP) && i->ifa_addr && i->ifa_addr->sa_family == AF_INET) names.insert(i->ifa_name);
  freeifaddrs(ifa);
  return names;
}

std::set<std::string> all_interfaces() {
  std::ifstream dev("/proc/net/dev");
  std::set<std::string> names;
  std::string line;
  while (std::getline(dev, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::istringstream name(line.substr(0, colon));
    std::string n;
    name >> n;
    names.insert(n);
  }
  return names;
}

}  // namespace

TEST(GenicamSource, NamespaceHasOnlyLoopbackSoDiscoveryStaysLocal) {
  // Aravis's GigE Vision discovery sends its broadcast on every up IPv4 interface (getifaddrs). In the
  // test's namespace that set is {lo}, and no other interface exists at all.
  EXPECT_EQ(all_interfaces(), std::set<std::string>{"lo"});
  EXPECT_EQ(interfaces_up_ipv4(), std::set<std::string>{"lo"});
  FakeGenicamCamera cam(fake_options("plate-hole-slot", 1));
  GenicamSource src({});
  ASSERT_NO_THROW(src.open());
  EXPECT_EQ(all_interfaces(), std::set<std::string>{"lo"});
}

TEST(GenicamSource, FindsTheFirst3dCameraAndReadsScan3dIntrinsics) {
  FakeGenicamCamera cam(fake_options("plate-hole-slot", 1));
  GenicamSource src({});
  src.open();
  EXPECT_EQ(src.opened_device(), cam.device_id());
  const CameraProfile& p = cam.options().profile;
  const Intrinsics& in = src.intrinsics();
  EXPECT_EQ(in.width, p.width);
  EXPECT_EQ(in.height, p.height);
  EXPECT_DOUBLE_EQ(in.fx, p.fx);
  EXPECT_DOUBLE_EQ(in.fy, p.fx);
  EXPECT_DOUBLE_EQ(in.cx, p.cx);  // the served principal point, not the image centre
  EXPECT_DOUBLE_EQ(in.cy, p.cy);
  EXPECT_NE(in.cx, (p.width - 1) / 2.0);
  EXPECT_DOUBLE_EQ(in.depth_unit, 0.05e-3);
  src.close();
  // Opened by its id, and by its address, as well.
  for (const std::string id : {cam.device_id(), std::string("127.0.0.1")}) {
    GenicamSource named({id, false});
    EXPECT_NO_THROW(named.open()) << id;
    EXPECT_TRUE(named.is_open()) << id;
  }
}

TEST(GenicamSource, NoDeviceIsASourceErrorNamingIt) {
  GenicamSource first({});
  EXPECT_THROW(first.open(), SourceError);
  GenicamSource named({"Nobody-0000", false});
  try {
    named.open();
    FAIL() << "opened a device that does not exist";
  } catch (const SourceError& e) {
    EXPECT_NE(std::string(e.what()).find("Nobody-0000"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(named.is_open());
}

TEST(GenicamSource, SamePlateCloudAsTheSyntheticPath) {
  const SegmentParams params;
  int compared = 0;
  for (const std::string scene : {"plate-hole-slot", "l-bracket", "ring-flange"}) {
    for (std::uint64_t seed : {3u, 17u}) {
      SCOPED_TRACE(scene + " seed " + std::to_string(seed));
      FakeGenicamCamera cam(fake_options(scene, seed));
      GenicamSource src({});
      src.open();
      const std::optional<DepthFrame> f = next_frame(src);
      ASSERT_TRUE(f.has_value()) << "no frame from the fake camera";
      const RenderedFrame r = render(cam.options().scene, cam.options().profile, 2);
      // Depth in metres pixel by pixel: 1 mm counts are whole multiples of the 0.05 mm step.
      EXPECT_EQ(pixels_differing(*f, r), 0);
      const Segmentation a = segment(f->depth, f->intrinsics, params), b = segment(r.depth, r.intrinsics, params);
      ASSERT_EQ(a.status, SegmentStatus::Ok) << a.text;
      ASSERT_EQ(b.status, SegmentStatus::Ok) << b.text;
      EXPECT_EQ(a.pixel, b.pixel);
      ASSERT_EQ(a.size(), b.size());
      double worst = 0;
      for (std::size_t i = 0; i < a.size(); ++i)
        worst = std::max({worst, std::abs(double(a.u[i]) - b.u[i]), std::abs(double(a.v[i]) - b.v[i])});
      EXPECT_LE(worst, 1e-6);
      EXPECT_NEAR(a.thickness, b.thickness, 1e-6);
      EXPECT_LE((a.normal - b.normal).norm(), 1e-6);
      ++compared;
    }
  }
  EXPECT_EQ(compared, 6);
}

// A step that does not divide the renderer's counts, and an offset that is no whole number of steps: each
// pixel's depth is within half a step (0.15 mm) plus the offset's rounding (|834 x 0.3 - 250.1| = 0.1 mm),
// and the plate comes out the same to within that.
TEST(GenicamSource, CoarseStepDepthWithinItsQuantisation) {
  FakeGenicamOptions o = fake_options("collar-notch", 8);
  o.scale_mm = 0.3;
  o.offset_mm = 250.1;
  FakeGenicamCamera cam(o);
  GenicamSource src({});
  src.open();
  const std::optional<DepthFrame> f = next_frame(src);
  ASSERT_TRUE(f.has_value());
  const RenderedFrame r = render(o.scene, o.profile, 2);
  const double bound = 0.15e-3 + 0.1e-3 + 1e-9;
  double worst = 0;
  int mismatched_validity = 0;
  for (int y = 0; y < r.depth.rows; ++y)
    for (int x = 0; x < r.depth.cols; ++x) {
      const int a = f->depth.at<std::uint16_t>(y, x), b = r.depth.at<std::uint16_t>(y, x);
      mismatched_validity += (a == 0) != (b == 0);
      if (a && b) worst = std::max(worst, std::abs(a * f->intrinsics.depth_unit - b * r.intrinsics.depth_unit));
    }
  EXPECT_EQ(mismatched_validity, 0);
  EXPECT_LE(worst, bound);
  EXPECT_GT(worst, 0.05e-3);  // the step really is coarser than the rendering's
  const SegmentParams params;
  const Segmentation a = segment(f->depth, f->intrinsics, params), b = segment(r.depth, r.intrinsics, params);
  ASSERT_EQ(a.status, SegmentStatus::Ok) << a.text;
  ASSERT_EQ(b.status, SegmentStatus::Ok) << b.text;
  EXPECT_NEAR(a.thickness, b.thickness, bound);
  EXPECT_NEAR(double(a.size()), double(b.size()), 0.01 * b.size());
}

// Organized point clouds: the bridge keeps C (Z) on the camera's pixel grid, in 0.1 mm counts, which hold
// the renderer's 1 mm counts exactly; X and Y are the same pinhole the intrinsics give.
TEST(GenicamSource, Abc32fCloudsGiveTheSameDepthAndPlateCloud) {
  const SegmentParams params;
  for (std::uint64_t seed : {5u, 6u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    FakeGenicamCamera cam(fake_options("knee-scallop", seed));
    GenicamSource src({"", false, GenicamFormat::abc32f});
    src.open();
    EXPECT_DOUBLE_EQ(src.intrinsics().depth_unit, kAbc32fDepthUnit);
    EXPECT_DOUBLE_EQ(src.intrinsics().cx, cam.options().profile.cx);
    const std::optional<DepthFrame> f = next_frame(src);
    ASSERT_TRUE(f.has_value()) << "no frame (incomplete " << src.counters().incomplete.load() << ")";
    const RenderedFrame r = render(cam.options().scene, cam.options().profile, 2);
    EXPECT_EQ(pixels_differing(*f, r), 0);
    const Segmentation a = segment(f->depth, f->intrinsics, params), b = segment(r.depth, r.intrinsics, params);
    ASSERT_EQ(a.status, SegmentStatus::Ok) << a.text;
    EXPECT_EQ(a.pixel, b.pixel);
    ASSERT_EQ(a.size(), b.size());
    double worst = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      worst = std::max({worst, std::abs(double(a.u[i]) - b.u[i]), std::abs(double(a.v[i]) - b.v[i])});
    EXPECT_LE(worst, 1e-6);
  }
}

TEST(GenicamSource, CountConversionsFollowTheScan3dRule) {
  bool oor = false;
  // C16: raw + offset / scale counts; the invalid value and results past 16 bits are no data.
  EXPECT_EQ(c16_to_count(100, 8000, 0, oor), 8100);
  EXPECT_FALSE(oor);
  EXPECT_EQ(c16_to_count(0, 8000, 0, oor), 0);
  EXPECT_FALSE(oor);
  EXPECT_EQ(c16_to_count(65535, 8000, 0, oor), 0);
  EXPECT_TRUE(oor);
  EXPECT_EQ(c16_to_count(7, -8, 0, oor), 0);
  EXPECT_TRUE(oor);
  // ABC32f: (C * scale + offset) mm in 0.1 mm counts.
  EXPECT_EQ(abc32f_to_count(1234.56f, 1.0, 0.0, 0.0, oor), 12346);
  EXPECT_FALSE(oor);
  EXPECT_EQ(abc32f_to_count(100.0f, 2.0, 300.0, 0.0, oor), 5000);
  EXPECT_EQ(abc32f_to_count(std::numeric_limits<float>::quiet_NaN(), 1.0, 0.0, 0.0, oor), 0);
  EXPECT_FALSE(oor);
  EXPECT_EQ(abc32f_to_count(0.0f, 1.0, 0.0, 0.0, oor), 0);     // the invalid value
  EXPECT_EQ(abc32f_to_count(7000.0f, 1.0, 0.0, 0.0, oor), 0);  // 7 m: past 16 bits of 0.1 mm
  EXPECT_TRUE(oor);
}

TEST(GenicamSource, SoftwareTriggerGivesNoFrameWithoutATrigger) {
  FakeGenicamOptions o = fake_options("l-bracket", 5);
  o.frame_rate = 50;  // free-running, it would send many
  FakeGenicamCamera cam(o);
  GenicamSource src({cam.device_id(), true});
  src.open();
  int triggers = 0, frames = 0;
  while (frames < 3 && triggers < 60) {
    ++triggers;  // every grab() sends one TriggerSoftware
    if (src.grab(1000ms)) ++frames;
  }
  EXPECT_EQ(frames, 3);
  std::this_thread::sleep_for(300ms);  // a free-running device would go on sending meanwhile
  EXPECT_LE(cam.frames_served(), triggers);
  EXPECT_GE(cam.frames_served(), 3);
}

TEST(GenicamSource, IncompleteBuffersAreCountedAndSkipped) {
  FakeGenicamCamera cam(fake_options("plate-hole-slot", 9));
  GenicamSource src({});
  src.open();
  ASSERT_TRUE(next_frame(src).has_value());
  cam.set_packet_loss(0.5);  // every frame (~1750 packets) loses packets; the fake device never resends
  int delivered = 0;
  for (int i = 0; i < 20 && src.counters().incomplete.load() < 2; ++i) delivered += src.grab(1000ms).has_value();
  EXPECT_EQ(delivered, 0);
  EXPECT_GE(src.counters().incomplete.load(), 2);
  cam.set_packet_loss(0.0);
  const auto f = next_frame(src);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(pixels_differing(*f, render(cam.options().scene, cam.options().profile, 2)), 0);
  EXPECT_GE(src.counters().frames.load(), 2);
}

TEST(GenicamSource, LostCameraIsAnErrorAndReopensWhenBack) {
  auto cam = std::make_unique<FakeGenicamCamera>(fake_options("plate-hole-slot", 4));
  const std::string id = cam->device_id();
  GenicamSource src({});
  src.open();
  ASSERT_TRUE(next_frame(src).has_value());
  cam.reset();  // the camera goes away: no more answers to heartbeats
  bool lost = false;
  std::string what;
  for (int i = 0; i < 60 && !lost; ++i) {
    try {
      src.grab(500ms);
    } catch (const SourceError& e) {
      lost = true;
      what = e.what();
    }
  }
  ASSERT_TRUE(lost) << "grab() never reported the lost camera";
  EXPECT_NE(what.find(id), std::string::npos) << what;
  src.close();
  EXPECT_THROW(src.open(), SourceError);  // not there
  cam = std::make_unique<FakeGenicamCamera>(fake_options("plate-hole-slot", 4));
  src.open();
  EXPECT_EQ(src.opened_device(), id);
  EXPECT_TRUE(next_frame(src).has_value());
}
