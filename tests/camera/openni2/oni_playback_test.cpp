// .oni recordings: recorded from our virtual device with openni::Recorder, played back through the
// openni2 source; and the failure mode of a stream without the cropping property (Debian's DummyDevice),
// whose recording is refused (its frames cannot play; docs/openni2.md explains why); closing at the end.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <thread>

#include <unistd.h>

#include "camera_bridge/openni2/openni2_source.hpp"
#include "sim/virtual_device/virtual_config.hpp"
#include "openni2_test_util.hpp"

namespace hg::camera_bridge {
namespace {

using namespace testing;
using namespace std::chrono_literals;

// Records the depth stream of a virtual device until it has read `frames` frames; returns the file.
std::string record(const std::string& uri, const std::string& name, int frames) {
  const std::string path = std::string(HG_TEST_TMP) + "/" + name;
  std::filesystem::remove(path);
  openni::Device device;
  EXPECT_EQ(device.open(uri.c_str()), openni::STATUS_OK) << openni::OpenNI::getExtendedError();
  openni::VideoStream stream;
  EXPECT_EQ(stream.create(device, openni::SENSOR_DEPTH), openni::STATUS_OK);
  openni::Recorder recorder;
  EXPECT_EQ(recorder.create(path.c_str()), openni::STATUS_OK);
  EXPECT_EQ(recorder.attach(stream, false), openni::STATUS_OK);  // lossless
  EXPECT_EQ(recorder.start(), openni::STATUS_OK);
  EXPECT_EQ(stream.start(), openni::STATUS_OK);
  openni::VideoFrameRef f;
  for (int read = 0; read < 100; ++read) {
    if (stream.readFrame(&f) != openni::STATUS_OK) break;
    if (f.getFrameIndex() >= frames) break;
  }
  f.release();    // the frame belongs to the stream: held past stream.destroy(), its release reads freed memory
  stream.stop();  // no frame after this one; then the recorder writes what it has queued and closes
  recorder.stop();
  recorder.destroy();
  stream.destroy();
  device.close();
  return path;
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(OpenNI2Oni, RecordedFromVirtualDevicePlaysBackEveryFrame) {
  init_openni_from_private_folder();
  const std::string path = record("hg-virtual://knee-scallop?profile=pm806&fps=10&seed=3", "roundtrip.oni", 5);
  ASSERT_TRUE(std::filesystem::exists(path));

  OpenNI2Options o;
  o.uri = path;
  o.playback_speed = 0;  // frame by frame: nothing dropped however slow this machine is
  OpenNI2Source source(o);
  source.open();
  ASSERT_TRUE(source.is_recording());
  const std::int64_t n = source.recorded_frames();
  ASSERT_GE(n, 5);  // the recorder saw every frame the device served, at least the 5 read
  const sim::CameraProfile profile = sim::camera_profile("pm806");

  // The recorder numbers its frames from 1; device frames it missed before its thread started shift them
  // by a constant, found on the first frame.
  std::optional<std::int64_t> shift;
  std::int64_t played = 0, first_utime = 0;
  while (!source.end_of_recording() && played < n + 5) {
    std::optional<camera::DepthFrame> f = source.grab(10s);
    ASSERT_TRUE(f) << "playback stalled after " << played << " of " << n << " frames";
    ++played;
    EXPECT_EQ(f->seq, played);
    if (!shift) {
      for (std::int64_t s = 0; s < 10 && !shift; ++s)
        if (differing_pixels(f->depth, expected_depth("knee-scallop", "pm806", 3, f->seq + s)) == 0) shift = s;
      ASSERT_TRUE(shift) << "first played frame matches no rendered frame";
      first_utime = f->utime;
    }
    const cv::Mat want = expected_depth("knee-scallop", "pm806", 3, f->seq + *shift);
    EXPECT_EQ(differing_pixels(f->depth, want), 0) << "played frame " << f->seq;
    if (differing_pixels(f->depth, want) > 0) {
      cv::Mat diff = f->depth != want;
      std::vector<cv::Point> where;
      cv::findNonZero(diff, where);
      for (const auto& p : where)
        ADD_FAILURE() << "at " << p << " got " << f->depth.at<std::uint16_t>(p) << " want "
                      << want.at<std::uint16_t>(p);
    }
    EXPECT_EQ(f->utime - first_utime, (f->seq - 1) * 100000);  // recorded timestamps, 10 fps
    EXPECT_NEAR(f->intrinsics.fx / profile.fx, 1.0, 1e-6);     // field of view is recorded
    EXPECT_NEAR(f->intrinsics.fy / profile.fy, 1.0, 1e-6);
    EXPECT_EQ(f->intrinsics.cx, profile.width / 2.0);  // the private principal point is not
    EXPECT_EQ(f->intrinsics.depth_unit, profile.depth_unit);
  }
  EXPECT_EQ(played, n);
  EXPECT_TRUE(source.end_of_recording());
  EXPECT_FALSE(source.grab(100ms).has_value());

  // Looping: after the last frame the first one comes again. (OpenNI2 shares one player per file, so
  // the first source is closed before the file is opened again.)
  source.close();
  o.loop = true;
  OpenNI2Source looping(o);
  looping.open();
  cv::Mat first_depth;
  std::optional<camera::DepthFrame> f;
  for (std::int64_t i = 0; i <= n; ++i) {
    f = looping.grab(10s);
    ASSERT_TRUE(f) << "loop playback stalled at frame " << i;
    if (i == 0) first_depth = f->depth.clone();
  }
  EXPECT_EQ(differing_pixels(f->depth, first_depth), 0);
  EXPECT_FALSE(looping.end_of_recording());
}

TEST(OpenNI2Oni, StreamWithoutCroppingPropertyRecordsAFileThatIsRefusedWithTheReason) {
  init_openni_from_private_folder();
  const std::string good = record("hg-virtual://collar-notch?profile=pm806&fps=10&seed=4", "cropping.oni", 3);
  const std::string bad =
      record("hg-virtual://collar-notch?profile=pm806&fps=10&seed=4&cropping=0", "no-cropping.oni", 3);
  // The recorder writes "xnCropping" only when the stream answers ONI_STREAM_PROPERTY_CROPPING...
  EXPECT_NE(file_bytes(good).find("xnCropping"), std::string::npos);
  EXPECT_EQ(file_bytes(bad).find("xnCropping"), std::string::npos);

  // ...and OniFile's player drops every frame of a stream without it, so the source says so at open.
  OpenNI2Options o;
  o.uri = bad;
  o.playback_speed = 0;
  OpenNI2Source source(o);
  try {
    source.open();
    ADD_FAILURE() << "a recording whose frames cannot play was opened";
  } catch (const camera::SourceError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(bad), std::string::npos) << what;
    EXPECT_NE(what.find("no cropping property"), std::string::npos) << what;
  }
}

// CPU time (utime + stime, clock ticks) of this process's threads but the calling one.
long other_threads_cpu_ticks() {
  const std::string self = std::to_string(::gettid());
  long ticks = 0;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    if (task.path().filename() == self) continue;
    std::ifstream in(task.path() / "stat");
    std::string stat((std::istreambuf_iterator<char>(in)), {});
    std::istringstream fields(stat.substr(stat.rfind(')') + 2));  // from field 3, the state
    std::string f;
    long utime = 0, stime = 0;
    for (int i = 3; i <= 15 && fields >> f; ++i) {
      if (i == 14) utime = std::stol(f);
      if (i == 15) stime = std::stol(f);
    }
    ticks += utime + stime;
  }
  return ticks;
}

TEST(OpenNI2Oni, AtTheEndOfARecordingNoThreadSpinsAndClosingIsSafe) {
  init_openni_from_private_folder();
  const std::string path = record("hg-virtual://l-bracket?profile=pm806&fps=10&seed=5", "to-the-end.oni", 3);
  for (int round = 0; round < 10; ++round) {  // each close once raced a spinning player (docs/openni2.md)
    OpenNI2Options o;
    o.uri = path;
    o.playback_speed = round % 2 ? 4 : 0;  // frame by frame, or timed at 40 frames a second
    OpenNI2Source source(o);
    source.open();
    std::int64_t played = 0;
    while (!source.end_of_recording() && played < source.recorded_frames() + 5)
      if (source.grab(10s)) ++played;
    ASSERT_TRUE(source.end_of_recording());
    if (o.playback_speed == 0) {
      ASSERT_EQ(played, source.recorded_frames());  // timed: a busy machine drops some
    }
    if (round > 1) continue;
    // OniFile's player at the end of a file that does not repeat spins: 0.5 s of CPU in these 0.5 s on a
    // quiet machine, 0.24 s beside two busy loops on two cores. Parked, it takes nothing.
    const long hz = ::sysconf(_SC_CLK_TCK), before = other_threads_cpu_ticks();
    std::this_thread::sleep_for(500ms);
    const double seconds = double(other_threads_cpu_ticks() - before) / double(hz);
    EXPECT_LT(seconds, 0.05) << "the player's threads kept running at the end of the recording";
  }
}

}  // namespace
}  // namespace hg::camera_bridge
