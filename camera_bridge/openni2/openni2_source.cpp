#include "camera_bridge/openni2/openni2_source.hpp"

#include <OpenNI.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "runtime/log.hpp"
#include "sim/virtual_device/virtual_properties.hpp"

namespace hg::camera_bridge {
namespace {

using runtime::Level;
using runtime::logf;

using Clock = std::chrono::steady_clock;

std::int64_t wall_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// OpenNI2 keeps one process-wide context; it is initialised once and kept for the life of the process
// (shutting it down unloads the drivers, which other sources in the process may still use).
void ensure_openni() {
  static std::mutex mutex;
  static bool done = false;
  std::lock_guard lock(mutex);
  if (done) return;
  if (openni::OpenNI::initialize() != openni::STATUS_OK)
    throw camera::SourceError(std::string("openni2: OpenNI2 did not initialise: ") +
                              openni::OpenNI::getExtendedError());
  done = true;
}

bool ends_with_oni(const std::string& s) {
  if (s.size() < 4) return false;
  std::string tail = s.substr(s.size() - 4);
  std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return std::tolower(c); });
  return tail == ".oni";
}

double unit_of(openni::PixelFormat f) {
  switch (f) {
    case openni::PIXEL_FORMAT_DEPTH_1_MM: return 0.001;
    case openni::PIXEL_FORMAT_DEPTH_100_UM: return 0.0001;
    default: return 0;
  }
}

std::string mode_text(const openni::VideoMode& m) {
  std::ostringstream s;
  s << m.getResolutionX() << "x" << m.getResolutionY() << "@" << m.getFps() << " "
    << (m.getPixelFormat() == openni::PIXEL_FORMAT_DEPTH_1_MM     ? "DEPTH_1_MM"
        : m.getPixelFormat() == openni::PIXEL_FORMAT_DEPTH_100_UM ? "DEPTH_100_UM"
                                                                  : "format " + std::to_string(m.getPixelFormat()));
  return s.str();
}

bool is_gray(openni::PixelFormat f) { return f == openni::PIXEL_FORMAT_GRAY8 || f == openni::PIXEL_FORMAT_GRAY16; }

// One IR frame read ahead of its depth frame, kept until the depth frame of its exposure comes.
struct IrFrame {
  cv::Mat image;  // empty: none pending
  int index = 0;
  std::uint64_t device_us = 0;
};

}  // namespace

struct OpenNI2Source::Impl : openni::OpenNI::DeviceDisconnectedListener, openni::OpenNI::DeviceStateChangedListener {
  OpenNI2Options options;
  bool recording = false;
  bool open = false;
  openni::Device device;
  openni::VideoStream stream;
  openni::VideoStream ir_stream;  // valid while the IR stream is read
  double ir_scale = 1;            // GRAY16: to full scale (65535 = the stream's MAX_VALUE, saturated)
  IrFrame ir_pending;
  bool ir_said = false;    // the log has said once why there is no intensity image
  int unpaired = 0;        // depth frames in a row without their IR frame
  std::string device_uri;  // as OpenNI2 names the opened device
  camera::Intrinsics intrinsics;
  std::atomic<bool> lost{false};
  std::string lost_reason;
  std::int64_t frames_in_recording = 0;
  std::int64_t last_index = 0;
  bool played_through = false;  // without loop: a frame of the player's next pass came (its last was dropped)
  std::int64_t skipped = 0;
  bool have_anchor = false;
  std::uint64_t anchor_device_us = 0, last_device_us = 0;
  std::int64_t anchor_wall_us = 0;

  // OpenNI calls these from its own threads; they only raise a flag that grab() turns into a SourceError.
  void onDeviceDisconnected(const openni::DeviceInfo* info) override {
    if (info && device_uri == info->getUri()) lost = true;
  }
  void onDeviceStateChanged(const openni::DeviceInfo* info, openni::DeviceState state) override {
    if (info && device_uri == info->getUri() && state == openni::DEVICE_STATE_ERROR) lost = true;
  }

  std::string name() const {
    if (options.uri.empty()) return "first device";
    return (recording ? "recording '" : "'") + options.uri + "'";
  }

  [[noreturn]] void fail(const std::string& what) {
    const std::string detail = openni::OpenNI::getExtendedError();
    throw camera::SourceError("openni2 " + name() + ": " + what + (detail.empty() ? "" : " (" + detail + ")"));
  }

  openni::VideoMode choose_mode() {
    const openni::SensorInfo& info = stream.getSensorInfo();
    const auto& modes = info.getSupportedVideoModes();
    const auto want_format = options.depth_unit == OpenNI2Options::DepthUnit::mm ? openni::PIXEL_FORMAT_DEPTH_1_MM
                             : options.depth_unit == OpenNI2Options::DepthUnit::tenth_mm
                                 ? openni::PIXEL_FORMAT_DEPTH_100_UM
                                 : openni::PixelFormat(0);
    const bool has_preference = options.width || options.height || options.fps || want_format;
    const openni::VideoMode current = stream.getVideoMode();
    if (!has_preference && unit_of(current.getPixelFormat()) > 0) return current;
    std::string listed;
    for (int i = 0; i < modes.getSize(); ++i) {
      const openni::VideoMode& m = modes[i];
      listed += (i ? ", " : "") + mode_text(m);
      if (unit_of(m.getPixelFormat()) == 0) continue;
      if (options.width && m.getResolutionX() != options.width) continue;
      if (options.height && m.getResolutionY() != options.height) continue;
      if (options.fps && m.getFps() != options.fps) continue;
      if (want_format && m.getPixelFormat() != want_format) continue;
      return m;
    }
    fail("no depth video mode matches the preference (device offers: " + (listed.empty() ? "none" : listed) + ")");
  }

  void open_now() {
    ensure_openni();
    recording = ends_with_oni(options.uri);
    if (recording && !std::filesystem::is_regular_file(options.uri)) fail("no such file");
    if (options.uri.empty()) {
      openni::Array<openni::DeviceInfo> list;
      openni::OpenNI::enumerateDevices(&list);
      if (list.getSize() == 0) fail("no OpenNI2 device found");
    }
    if (device.open(options.uri.empty() ? openni::ANY_DEVICE : options.uri.c_str()) != openni::STATUS_OK)
      fail("cannot open the device");
    device_uri = device.getDeviceInfo().getUri();
    lost = false;
    openni::OpenNI::addDeviceDisconnectedListener(this);
    openni::OpenNI::addDeviceStateChangedListener(this);
    try {
      if (recording) {
        // Speed <= 0: OpenNI's manual mode (-1), where the player hands over one frame each time a reader
        // waits for one, so a slow reader never loses frames.
        device.getPlaybackControl()->setSpeed(options.playback_speed > 0 ? float(options.playback_speed) : -1.0f);
      }
      if (!device.hasSensor(openni::SENSOR_DEPTH)) fail("the device has no depth sensor");
      if (stream.create(device, openni::SENSOR_DEPTH) != openni::STATUS_OK) fail("cannot create the depth stream");
      const openni::VideoMode mode = choose_mode();
      const openni::VideoMode current = stream.getVideoMode();
      const bool same = current.getPixelFormat() == mode.getPixelFormat() &&
                        current.getResolutionX() == mode.getResolutionX() &&
                        current.getResolutionY() == mode.getResolutionY() && current.getFps() == mode.getFps();
      if (!same && stream.setVideoMode(mode) != openni::STATUS_OK) fail("cannot set video mode " + mode_text(mode));
      set_intrinsics(stream.getVideoMode());
      if (recording) prepare_playback();
      if (stream.start() != openni::STATUS_OK) fail("cannot start the depth stream");
      open_ir();
    } catch (...) {
      close_now();
      throw;
    }
    last_index = 0;
    played_through = false;
    have_anchor = false;
    open = true;
  }

  // A recording's depth stream: refused when OpenNI2's player would drop all its frames (docs/openni2.md,
  // "Why the DummyDevice recording played back no frames").
  void prepare_playback() {
    OniCropping cropping{};
    int size = sizeof cropping;
    if (stream.getProperty(ONI_STREAM_PROPERTY_CROPPING, &cropping, &size) != openni::STATUS_OK)
      fail(
          "the recording's depth stream has no cropping property, so OpenNI2's file player drops every frame "
          "(recorded from a driver that does not report ONI_STREAM_PROPERTY_CROPPING; docs/openni2.md)");
    frames_in_recording = device.getPlaybackControl()->getNumberOfFrames(stream);
    if (frames_in_recording <= 0) fail("the recording holds no depth frames");
    device.getPlaybackControl()->setRepeatEnabled(true);  // park_player
  }

  // OpenNI2's player thread walks its device's stream list without a lock before every frame; destroying a
  // stream during a walk crashes it (docs/openni2.md, "Closing a playback"). At the end of a file that does
  // not repeat it closes the file and walks without pause, so the player always repeats (prepare_playback)
  // and this source ends a recording without loop itself (at_end). Parked, in manual mode, the player waits
  // at its next frame for a reader's trigger, walking the list only under the lock, once in 2 s; this
  // source triggers nothing after the end.
  void park_player() { device.getPlaybackControl()->setSpeed(-1.0f); }

  void set_intrinsics(const openni::VideoMode& mode) {
    camera::Intrinsics in;
    in.width = mode.getResolutionX();
    in.height = mode.getResolutionY();
    in.depth_unit = unit_of(mode.getPixelFormat());
    if (in.depth_unit == 0)
      fail("pixel format " + std::to_string(mode.getPixelFormat()) + " is not a depth in mm or 0.1 mm");
    // OpenNI2's pinhole model (VideoStream::convertDepthToWorld): tan(fov/2) = (resolution/2) / focal.
    const double hfov = stream.getHorizontalFieldOfView(), vfov = stream.getVerticalFieldOfView();
    if (!(hfov > 0 && hfov < M_PI && vfov > 0 && vfov < M_PI))
      fail("the stream reports no usable field of view (h " + std::to_string(hfov) + ", v " + std::to_string(vfov) +
           " rad)");
    in.fx = in.width / (2.0 * std::tan(hfov / 2.0));
    in.fy = in.height / (2.0 * std::tan(vfov / 2.0));
    // The principal point: exact from our virtual device, else OpenNI2's assumption, the image centre.
    in.cx = in.width / 2.0;
    in.cy = in.height / 2.0;
    if (stream.isPropertySupported(sim::virtual_device::kStreamPropertyPrincipalPoint)) {
      double pp[2];
      int size = sizeof pp;
      if (stream.getProperty(sim::virtual_device::kStreamPropertyPrincipalPoint, pp, &size) == openni::STATUS_OK) {
        in.cx = pp[0];
        in.cy = pp[1];
      }
    }
    intrinsics = in;
  }

  void say_no_ir(const std::string& why) {
    if (ir_said) return;
    ir_said = true;
    logf(Level::Info, "openni2 %s: no intensity image (%s); dropout and holes are told apart by depth alone",
         name().c_str(), why.c_str());
  }

  // The IR stream at the depth's resolution, when the device has one and options.ir allows it.
  void open_ir() {
    ir_pending = {};
    unpaired = 0;
    if (!options.ir) return say_no_ir("--openni2.ir false");
    if (!device.hasSensor(openni::SENSOR_IR)) return say_no_ir("the device has no IR stream");
    if (ir_stream.create(device, openni::SENSOR_IR) != openni::STATUS_OK)
      return say_no_ir(std::string("cannot create the IR stream: ") + openni::OpenNI::getExtendedError());
    const openni::VideoMode depth = stream.getVideoMode();
    const auto fits = [&](const openni::VideoMode& m) {
      return is_gray(m.getPixelFormat()) && m.getResolutionX() == depth.getResolutionX() &&
             m.getResolutionY() == depth.getResolutionY();
    };
    std::optional<openni::VideoMode> mode;
    if (fits(ir_stream.getVideoMode())) mode = ir_stream.getVideoMode();  // the device's default first
    const auto& modes = ir_stream.getSensorInfo().getSupportedVideoModes();
    for (int i = 0; i < modes.getSize() && !mode; ++i)
      if (fits(modes[i])) mode = modes[i];
    if (!mode || ir_stream.setVideoMode(*mode) != openni::STATUS_OK || ir_stream.start() != openni::STATUS_OK) {
      ir_stream.destroy();
      return say_no_ir(mode ? "cannot start the IR stream" : "no GRAY8/GRAY16 IR mode at the depth's resolution");
    }
    const int max = ir_stream.getMaxPixelValue();
    const bool gray16 = mode->getPixelFormat() == openni::PIXEL_FORMAT_GRAY16;
    ir_scale = gray16 && max > 0 && max < 65535 ? 65535.0 / max : 1.0;
    logf(Level::Info, "openni2 %s: intensity image from the IR stream (%s, max value %d)", name().c_str(),
         gray16 ? "GRAY16" : "GRAY8", max);
  }

  // Reads the next IR frame within `wait`; false when none came.
  bool read_ir(std::chrono::milliseconds wait) {
    openni::VideoStream* streams[] = {&ir_stream};
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream(streams, 1, &ready, int(std::max<std::int64_t>(wait.count(), 0))) !=
        openni::STATUS_OK)
      return false;
    openni::VideoFrameRef ref;
    if (ir_stream.readFrame(&ref) != openni::STATUS_OK) return false;
    const int w = ref.getWidth(), h = ref.getHeight(), stride = ref.getStrideInBytes();
    const bool gray8 = ref.getVideoMode().getPixelFormat() == openni::PIXEL_FORMAT_GRAY8;
    const int bpp = gray8 ? 1 : 2;
    if (w <= 0 || h <= 0 || stride < w * bpp || ref.getDataSize() < stride * (h - 1) + w * bpp) return true;
    const cv::Mat raw(h, w, gray8 ? CV_8UC1 : CV_16UC1, const_cast<void*>(ref.getData()), stride);
    ir_pending.index = ref.getFrameIndex();
    ir_pending.device_us = ref.getTimestamp();
    raw.convertTo(ir_pending.image, raw.type(), gray8 ? 1.0 : ir_scale);  // saturates at 65535
    return true;
  }

  // Pairs the depth frame `f` (device time `device_us`) with the IR frame of the same exposure: the same
  // frame index, or the same device time within half a frame period. An older IR frame is dropped, a newer
  // one kept for the next depth frame. False when `f` has no IR frame (none within two frame periods, or
  // only a newer one).
  bool pair_ir(camera::DepthFrame& f, std::uint64_t device_us) {
    const int fps = std::max(1, stream.getVideoMode().getFps());
    const std::int64_t half_us = 500000 / fps;
    const auto deadline = Clock::now() + std::chrono::milliseconds(2000 / fps + 100);
    for (;;) {
      if (ir_pending.image.empty()) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        if (left.count() <= 0 || !read_ir(left)) return false;
        if (ir_pending.image.empty()) continue;  // a malformed frame
      }
      const std::int64_t dt = std::int64_t(ir_pending.device_us) - std::int64_t(device_us);
      if (ir_pending.index == f.seq || std::abs(dt) <= half_us) {
        const bool fits = ir_pending.image.size() == f.depth.size();
        if (fits) f.intensity = std::move(ir_pending.image);
        ir_pending = {};
        return fits;
      }
      if (dt > 0 && dt < 1000000) return false;  // a later depth frame's (a second ahead: a clock restart)
      ir_pending = {};
    }
  }

  // False: skip the depth frame `f`, whose IR frame was lost (OpenNI keeps a stream's latest frame only, and
  // the two streams' frames arrive apart), so that the next frame comes with its intensity image. After
  // kUnpairedSkipped such frames in a row, frames go without it.
  bool attach_ir(camera::DepthFrame& f, std::uint64_t device_us) {
    static constexpr int kUnpairedSkipped = 5;
    if (!ir_stream.isValid() || pair_ir(f, device_us)) {
      unpaired = 0;
      return true;
    }
    if (++unpaired <= kUnpairedSkipped) return false;
    if (unpaired == kUnpairedSkipped + 1)
      logf(Level::Warn, "openni2 %s: %d depth frames in a row without their IR frame; frames go without intensity",
           name().c_str(), kUnpairedSkipped);
    return true;
  }

  void close_now() {
    if (recording && device.isValid()) {
      park_player();
      std::this_thread::sleep_for(std::chrono::milliseconds(50));  // time to get there on a busy machine
    }
    if (ir_stream.isValid()) {
      ir_stream.stop();
      ir_stream.destroy();
    }
    ir_pending = {};
    if (stream.isValid()) {
      stream.stop();
      stream.destroy();
    }
    if (device.isValid()) {
      openni::OpenNI::removeDeviceDisconnectedListener(this);
      openni::OpenNI::removeDeviceStateChangedListener(this);
      device.close();
    }
    open = false;
  }

  bool at_end() const {
    return recording && !options.loop &&
           (played_through || (frames_in_recording > 0 && last_index >= frames_in_recording));
  }
};

OpenNI2Source::OpenNI2Source(OpenNI2Options options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  impl_->recording = ends_with_oni(impl_->options.uri);
}

OpenNI2Source::~OpenNI2Source() {
  if (impl_->open || impl_->device.isValid()) impl_->close_now();
}

std::string OpenNI2Source::describe() const {
  std::string d = "openni2 " + impl_->name();
  if (impl_->recording) {
    std::ostringstream s;
    s << " (speed " << (impl_->options.playback_speed > 0 ? impl_->options.playback_speed : 0)
      << (impl_->options.playback_speed > 0 ? "" : " = frame by frame") << (impl_->options.loop ? ", loop" : "") << ")";
    d += s.str();
  }
  return d;
}

void OpenNI2Source::open() {
  if (!impl_->open) impl_->open_now();
}
bool OpenNI2Source::is_open() const { return impl_->open; }
void OpenNI2Source::close() {
  if (impl_->open || impl_->device.isValid()) impl_->close_now();
}
bool OpenNI2Source::is_recording() const { return impl_->recording; }
bool OpenNI2Source::end_of_recording() const { return impl_->at_end(); }
std::int64_t OpenNI2Source::recorded_frames() const { return impl_->frames_in_recording; }
std::int64_t OpenNI2Source::skipped_frames() const { return impl_->skipped; }
bool OpenNI2Source::reads_ir() const { return impl_->open && impl_->ir_stream.isValid(); }

std::optional<camera::DepthFrame> OpenNI2Source::grab(std::chrono::milliseconds timeout) {
  Impl& m = *impl_;
  if (!m.open) throw camera::SourceError("openni2 " + m.name() + ": grab() on a closed source");
  const auto deadline = Clock::now() + timeout;
  openni::VideoFrameRef ref;
  for (;;) {
    if (m.at_end()) {
      m.park_player();
      return std::nullopt;
    }
    if (m.lost)
      throw camera::SourceError("openni2 " + m.name() + ": device '" + m.device_uri + "' lost (disconnected)");
    // Wait in short slices so that a disconnection is noticed soon even with a long timeout.
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    const int slice = int(std::clamp<std::int64_t>(left.count(), 0, 100));
    openni::VideoStream* streams[] = {&m.stream};
    int ready = -1;
    const openni::Status rc = openni::OpenNI::waitForAnyStream(streams, 1, &ready, slice);
    if (rc == openni::STATUS_OK) {
      if (m.stream.readFrame(&ref) != openni::STATUS_OK) m.fail("reading a frame failed");
      if (m.recording && !m.options.loop && ref.getFrameIndex() <= m.last_index) {
        m.played_through = true;  // the player repeats (park_player); this source does not
        continue;
      }
      m.last_index = ref.getFrameIndex();  // a malformed last frame ends a recording too
      const int w = ref.getWidth(), h = ref.getHeight(), stride = ref.getStrideInBytes();
      if (w <= 0 || h <= 0 || stride < w * 2 || ref.getDataSize() < stride * (h - 1) + w * 2) {
        ++m.skipped;  // a frame whose data does not fit its own header: never read past it
        continue;
      }
      camera::DepthFrame f;
      f.seq = ref.getFrameIndex();
      f.intrinsics = m.intrinsics;
      cv::Mat(h, w, CV_16UC1, const_cast<void*>(ref.getData()), stride).copyTo(f.depth);
      // Device timestamps are microseconds on the device's clock: anchor them to the wall clock at the
      // first frame (and again whenever the clock restarts, e.g. a looping recording).
      const std::uint64_t ts = ref.getTimestamp();
      if (!m.have_anchor || ts < m.last_device_us) {
        m.have_anchor = true;
        m.anchor_device_us = ts;
        m.anchor_wall_us = wall_us();
      }
      m.last_device_us = ts;
      f.utime = m.anchor_wall_us + std::int64_t(ts - m.anchor_device_us);
      if (!m.attach_ir(f, ts)) {
        ++m.skipped;
        continue;
      }
      if (m.at_end()) m.park_player();
      return f;
    }
    if (rc != openni::STATUS_TIME_OUT) m.fail("waiting for a frame failed");
    if (Clock::now() >= deadline) return std::nullopt;
  }
}

std::unique_ptr<camera::DepthSource> make_openni2_source(const OpenNI2Options& options) {
  return std::make_unique<OpenNI2Source>(options);
}

}  // namespace hg::camera_bridge
