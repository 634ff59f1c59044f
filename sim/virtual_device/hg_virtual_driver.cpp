// libhg-virtual.so.0: the project's own OpenNI2 driver. It serves depth frames rendered from the
// synthetic scenes (virtual_config.hpp), and their intensity images as an IR stream where the scene renders
// one, so the bridge's real OpenNI2 code path runs without hardware.
// Devices are named by hg-virtual:// URIs; the driver announces one at start-up (from the environment)
// and any other valid URI on demand (tryDevice), so Device::open("hg-virtual://...") just works.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

// OniDriverAPI.h's ONI_EXPORT_DRIVER uses XnLib's allocation macros, which Debian does not ship.
#define XN_NEW(type, ...) new type(__VA_ARGS__)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>

#include "sim/virtual_device/virtual_config.hpp"
#include "sim/virtual_device/virtual_properties.hpp"

namespace hg::sim::virtual_device {
namespace {

using Clock = std::chrono::steady_clock;

// Largest depth count the stream reports (ONI_STREAM_PROPERTY_MAX_VALUE). OpenNI's recorder builds its 16z
// value table for values below it and indexes a static 65535-entry table by pixel value, so counts must
// stay <= 65534 (the driver clamps) and 65535 is the right claim.
constexpr int kMaxDepthCount = 65535;
constexpr std::uint16_t kLargestCount = 65534;

// OpenNI 2.2's 16z encoders (XnStreamCompressDepth16Z[WithEmbTable]) flush a trailing half byte before a
// pending run of unchanged pairs, so when a frame ends with such a run and one odd value, the run decodes
// as that last value: up to 29 pixels at the end of a recorded frame come back wrong. Every frame
// therefore carries these guard counts after its last row (OpenNI frames may be larger than
// width x height; readers use width, height and stride). The last step, from 0 to the largest count, is
// more than 6 apart in the encoder's value ranks (>= 9 distinct values), which flushes the run and
// leaves nothing pending, so the image itself is always recorded losslessly.
constexpr std::uint16_t kGuardTail[] = {1, 2, 3, 4, 5, 6, 7, 0, kLargestCount};
constexpr int kGuardBytes = sizeof kGuardTail;

OniPixelFormat pixel_format_for_unit(double unit) {
  if (std::abs(unit - 0.001) < 1e-12) return ONI_PIXEL_FORMAT_DEPTH_1_MM;
  if (std::abs(unit - 0.0001) < 1e-12) return ONI_PIXEL_FORMAT_DEPTH_100_UM;
  throw std::invalid_argument("depth unit " + std::to_string(unit) + " m has no OpenNI2 pixel format");
}
double unit_of(OniPixelFormat f) { return f == ONI_PIXEL_FORMAT_DEPTH_100_UM ? 0.0001 : 0.001; }

// The IR stream's GRAY16 is 10 bits in 16, as PrimeSense and Orbbec devices send it (their MAX_VALUE is
// 1023): the renderer's 8-bit intensity i becomes round(i * 1023 / 255), so full scale stays full scale.
constexpr int kIrMaxValue16 = 1023;
int bytes_per_pixel(OniPixelFormat f) { return f == ONI_PIXEL_FORMAT_GRAY8 ? 1 : 2; }

class VirtualDriver;

// One hg-virtual:// URI known to the driver. Lives as long as the driver (OpenNI keeps pointers to info).
struct DeviceEntry {
  std::string uri;
  VirtualDeviceConfig config;
  OniDeviceInfo info{};
  bool connected = false;                         // guarded by the driver's mutex
  std::optional<Clock::time_point> reconnect_at;  // when a lost device comes back
};

class VirtualDevice;

// A stream of the device: depth (ONI_SENSOR_DEPTH) or the intensity image (ONI_SENSOR_IR) of the same
// frames. Each runs its own clock from its start; frame n of either is the device's rendered frame n.
class VirtualStream : public oni::driver::StreamBase {
 public:
  VirtualStream(VirtualDevice& device, std::shared_ptr<const FrameRenderer> renderer, OniSensorType sensor,
                const std::vector<OniVideoMode>& modes, bool cropping_property)
      : device_(device),
        renderer_(std::move(renderer)),
        sensor_(sensor),
        mode_(modes.front()),
        modes_(modes),
        cropping_property_(cropping_property) {}
  ~VirtualStream() override { stop(); }

  OniStatus start() override {
    std::lock_guard lock(mutex_);
    if (running_) return ONI_STATUS_OK;
    running_ = true;
    thread_ = std::thread([this] { run(); });
    return ONI_STATUS_OK;
  }

  void stop() override {
    {
      std::lock_guard lock(mutex_);
      running_ = false;
    }
    wake_.notify_all();
    if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
  }

  int getRequiredFrameSize() override {
    const int image = mode_.resolutionX * mode_.resolutionY * bytes_per_pixel(mode_.pixelFormat);
    return sensor_ == ONI_SENSOR_DEPTH ? image + kGuardBytes : image;
  }

  OniBool isPropertySupported(int id) override {
    switch (id) {
      case ONI_STREAM_PROPERTY_VIDEO_MODE:
      case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
      case ONI_STREAM_PROPERTY_VERTICAL_FOV:
      case ONI_STREAM_PROPERTY_MAX_VALUE:
      case ONI_STREAM_PROPERTY_MIN_VALUE:
      case ONI_STREAM_PROPERTY_MIRRORING:
      case ONI_STREAM_PROPERTY_STRIDE:
      case kStreamPropertyPrincipalPoint: return TRUE;
      case ONI_STREAM_PROPERTY_CROPPING: return cropping_property_ ? TRUE : FALSE;
      default: return FALSE;
    }
  }

  OniStatus getProperty(int id, void* data, int* size) override {
    const camera::Intrinsics& in = renderer_->intrinsics();
    switch (id) {
      case ONI_STREAM_PROPERTY_VIDEO_MODE: return put(data, size, mode_);
      // OpenNI's pinhole model: tan(fov/2) = (resolution/2) / focal length.
      case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
        return put(data, size, static_cast<float>(2.0 * std::atan(in.width / (2.0 * in.fx))));
      case ONI_STREAM_PROPERTY_VERTICAL_FOV:
        return put(data, size, static_cast<float>(2.0 * std::atan(in.height / (2.0 * in.fy))));
      case ONI_STREAM_PROPERTY_MAX_VALUE: return put(data, size, max_value());
      case ONI_STREAM_PROPERTY_MIN_VALUE: return put(data, size, 0);
      case ONI_STREAM_PROPERTY_MIRRORING: return put(data, size, OniBool(FALSE));
      case ONI_STREAM_PROPERTY_STRIDE: return put(data, size, mode_.resolutionX * bytes_per_pixel(mode_.pixelFormat));
      case ONI_STREAM_PROPERTY_CROPPING:
        if (!cropping_property_) return ONI_STATUS_NOT_SUPPORTED;
        return put(data, size, OniCropping{FALSE, 0, 0, mode_.resolutionX, mode_.resolutionY});
      case kStreamPropertyPrincipalPoint: {
        const double pp[2] = {in.cx, in.cy};
        if (*size != static_cast<int>(sizeof pp)) return ONI_STATUS_BAD_PARAMETER;
        std::memcpy(data, pp, sizeof pp);
        return ONI_STATUS_OK;
      }
      default: return ONI_STATUS_NOT_SUPPORTED;
    }
  }

  OniStatus setProperty(int id, const void* data, int size) override {
    switch (id) {
      case ONI_STREAM_PROPERTY_VIDEO_MODE: {
        if (size != static_cast<int>(sizeof(OniVideoMode))) return ONI_STATUS_BAD_PARAMETER;
        OniVideoMode wanted;
        std::memcpy(&wanted, data, sizeof wanted);
        const bool known = std::any_of(modes_.begin(), modes_.end(), [&](const OniVideoMode& m) {
          return m.pixelFormat == wanted.pixelFormat && m.resolutionX == wanted.resolutionX &&
                 m.resolutionY == wanted.resolutionY && m.fps == wanted.fps;
        });
        if (!known) return ONI_STATUS_NOT_SUPPORTED;
        std::lock_guard lock(mutex_);
        if (running_) return ONI_STATUS_OUT_OF_FLOW;  // the frame size would change under OpenNI's feet
        mode_ = wanted;
        return ONI_STATUS_OK;
      }
      case ONI_STREAM_PROPERTY_MIRRORING: {
        if (size != static_cast<int>(sizeof(OniBool))) return ONI_STATUS_BAD_PARAMETER;
        return *static_cast<const OniBool*>(data) ? ONI_STATUS_NOT_SUPPORTED : ONI_STATUS_OK;
      }
      case ONI_STREAM_PROPERTY_CROPPING: {
        if (!cropping_property_) return ONI_STATUS_NOT_SUPPORTED;
        if (size != static_cast<int>(sizeof(OniCropping))) return ONI_STATUS_BAD_PARAMETER;
        return static_cast<const OniCropping*>(data)->enabled ? ONI_STATUS_NOT_SUPPORTED : ONI_STATUS_OK;
      }
      default: return ONI_STATUS_NOT_SUPPORTED;
    }
  }

 private:
  template <class T>
  static OniStatus put(void* data, int* size, const T& value) {
    if (*size != static_cast<int>(sizeof(T))) return ONI_STATUS_BAD_PARAMETER;
    std::memcpy(data, &value, sizeof(T));
    return ONI_STATUS_OK;
  }

  int max_value() const {
    if (sensor_ == ONI_SENSOR_DEPTH) return kMaxDepthCount;
    return mode_.pixelFormat == ONI_PIXEL_FORMAT_GRAY8 ? 255 : kIrMaxValue16;
  }

  void run();
  void fill_depth(OniFrame& frame, cv::Mat counts) const;
  void fill_ir(OniFrame& frame, const cv::Mat& intensity) const;

  VirtualDevice& device_;
  std::shared_ptr<const FrameRenderer> renderer_;
  OniSensorType sensor_;
  OniVideoMode mode_;
  std::vector<OniVideoMode> modes_;
  bool cropping_property_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool running_ = false;
  std::thread thread_;
};

class VirtualDevice : public oni::driver::DeviceBase {
 public:
  VirtualDevice(VirtualDriver& driver, DeviceEntry& entry, std::shared_ptr<const FrameRenderer> renderer)
      : driver_(driver), entry_(entry), renderer_(std::move(renderer)) {
    const camera::Intrinsics& in = renderer_->intrinsics();
    const int fps = std::max(1, static_cast<int>(std::lround(entry.config.fps)));
    const OniPixelFormat native = pixel_format_for_unit(in.depth_unit);
    const OniPixelFormat other =
        native == ONI_PIXEL_FORMAT_DEPTH_1_MM ? ONI_PIXEL_FORMAT_DEPTH_100_UM : ONI_PIXEL_FORMAT_DEPTH_1_MM;
    modes_ = {{native, in.width, in.height, fps}, {other, in.width, in.height, fps}};  // native first: default
    // The IR image is registered to depth (the renderer's pixels); GRAY16 first, as real devices default.
    ir_modes_ = {{ONI_PIXEL_FORMAT_GRAY16, in.width, in.height, fps},
                 {ONI_PIXEL_FORMAT_GRAY8, in.width, in.height, fps}};
    sensors_[0] = {ONI_SENSOR_DEPTH, static_cast<int>(modes_.size()), modes_.data()};
    sensors_[1] = {ONI_SENSOR_IR, static_cast<int>(ir_modes_.size()), ir_modes_.data()};
    sensor_count_ = renderer_->has_intensity() ? 2 : 1;
  }
  ~VirtualDevice() override {
    for (auto* s : streams_) delete s;
  }

  OniStatus getSensorInfoList(OniSensorInfo** sensors, int* count) override {
    *sensors = sensors_;
    *count = sensor_count_;
    return ONI_STATUS_OK;
  }

  oni::driver::StreamBase* createStream(OniSensorType type) override {
    if (type != ONI_SENSOR_DEPTH && !(type == ONI_SENSOR_IR && sensor_count_ == 2)) return nullptr;
    auto* s = new VirtualStream(*this, renderer_, type, type == ONI_SENSOR_DEPTH ? modes_ : ir_modes_,
                                entry_.config.cropping_property);
    std::lock_guard lock(mutex_);
    streams_.push_back(s);
    return s;
  }

  void destroyStream(oni::driver::StreamBase* stream) override {
    {
      std::lock_guard lock(mutex_);
      streams_.erase(std::remove(streams_.begin(), streams_.end(), stream), streams_.end());
    }
    delete stream;
  }

  OniStatus getProperty(int id, void* data, int* size) override {
    if (id == ONI_DEVICE_PROPERTY_DRIVER_VERSION) {
      if (*size != static_cast<int>(sizeof(OniVersion))) return ONI_STATUS_BAD_PARAMETER;
      *static_cast<OniVersion*>(data) = OniVersion{0, 1, 0, 0};
      return ONI_STATUS_OK;
    }
    if (id == ONI_DEVICE_PROPERTY_SERIAL_NUMBER) {
      const std::string serial = "hg-virtual-" + entry_.config.profile;
      if (*size < static_cast<int>(serial.size() + 1)) return ONI_STATUS_BAD_PARAMETER;
      std::memcpy(data, serial.c_str(), serial.size() + 1);
      *size = static_cast<int>(serial.size() + 1);
      return ONI_STATUS_OK;
    }
    return ONI_STATUS_NOT_SUPPORTED;
  }
  OniBool isPropertySupported(int id) override {
    return id == ONI_DEVICE_PROPERTY_DRIVER_VERSION || id == ONI_DEVICE_PROPERTY_SERIAL_NUMBER;
  }

  const DeviceEntry& entry() const { return entry_; }
  VirtualDriver& driver() { return driver_; }

  // Counts a served frame; false once the fault injection says the device is gone.
  bool may_serve_frame() {
    if (lost_.load()) return false;
    if (entry_.config.disconnect_after && served_.load() >= *entry_.config.disconnect_after) {
      if (!lost_.exchange(true)) report_lost();
      return false;
    }
    return true;
  }
  void frame_served() { ++served_; }

  // Rendered frame n, shared by the streams: rendered once, by whichever stream asks first.
  std::shared_ptr<const FrameRenderer::Frame> frame(std::uint64_t n) {
    std::lock_guard lock(render_mutex_);
    for (const auto& [index, f] : rendered_)
      if (index == n) return f;
    auto f = std::make_shared<const FrameRenderer::Frame>(renderer_->render_frame(n));
    rendered_.emplace_back(n, f);
    if (rendered_.size() > 4) rendered_.erase(rendered_.begin());  // the streams run a frame or so apart
    return f;
  }

 private:
  void report_lost();

  VirtualDriver& driver_;
  DeviceEntry& entry_;
  std::shared_ptr<const FrameRenderer> renderer_;
  std::vector<OniVideoMode> modes_, ir_modes_;
  OniSensorInfo sensors_[2]{};
  int sensor_count_ = 1;
  std::mutex mutex_;
  std::mutex render_mutex_;
  std::vector<std::pair<std::uint64_t, std::shared_ptr<const FrameRenderer::Frame>>> rendered_;
  std::vector<oni::driver::StreamBase*> streams_;
  std::atomic<std::uint64_t> served_{0};
  std::atomic<bool> lost_{false};
};

class VirtualDriver : public oni::driver::DriverBase {
 public:
  explicit VirtualDriver(OniDriverServices* services) : DriverBase(services) {}
  ~VirtualDriver() override { shutdown(); }

  OniStatus initialize(oni::driver::DeviceConnectedCallback connected,
                       oni::driver::DeviceDisconnectedCallback disconnected,
                       oni::driver::DeviceStateChangedCallback state_changed, void* cookie) override {
    OniStatus rc = DriverBase::initialize(connected, disconnected, state_changed, cookie);
    if (rc != ONI_STATUS_OK) return rc;
    events_ = std::thread([this] { event_loop(); });
    try {
      announce(announced_uri_from_environment());
    } catch (const std::exception& e) {
      // A bad environment must not take OpenNI down: the driver loads, announces nothing, and says why.
      getServices().errorLoggerAppend("hg-virtual: %s", e.what());
      log_error(e.what());
    }
    return ONI_STATUS_OK;
  }

  OniStatus tryDevice(const char* uri) override {
    if (std::strncmp(uri, kUriScheme, std::strlen(kUriScheme)) != 0) return ONI_STATUS_ERROR;
    try {
      return announce(uri) ? ONI_STATUS_OK : ONI_STATUS_ERROR;
    } catch (const std::exception& e) {
      getServices().errorLoggerAppend("hg-virtual: %s", e.what());
      return ONI_STATUS_ERROR;
    }
  }

  oni::driver::DeviceBase* deviceOpen(const char* uri, const char* /*mode*/) override {
    DeviceEntry* entry = nullptr;
    {
      std::lock_guard lock(mutex_);
      auto it = entries_.find(uri);
      if (it == entries_.end() || !it->second->connected) {
        getServices().errorLoggerAppend("hg-virtual: device '%s' is not connected", uri);
        return nullptr;
      }
      entry = it->second.get();
    }
    try {
      auto renderer = std::make_shared<const FrameRenderer>(entry->config);
      return new VirtualDevice(*this, *entry, std::move(renderer));
    } catch (const std::exception& e) {
      getServices().errorLoggerAppend("hg-virtual: cannot open '%s': %s", uri, e.what());
      return nullptr;
    }
  }

  void deviceClose(oni::driver::DeviceBase* device) override { delete device; }

  void shutdown() override {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (events_.joinable()) events_.join();
  }

  // Called from a stream thread: the device is gone. OpenNI is told from the event thread, so that a
  // stream's stop() (which joins the stream thread) never waits on OpenNI's own locks.
  void device_lost(DeviceEntry& entry) {
    {
      std::lock_guard lock(mutex_);
      entry.connected = false;
      if (entry.config.reconnect_after)
        entry.reconnect_at = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                std::chrono::duration<double>(*entry.config.reconnect_after));
      pending_.push_back({&entry, false});
    }
    wake_.notify_all();
  }

  void log_error(const std::string& message) {
    getServices().log(3 /* error */, __FILE__, __LINE__, "hg-virtual", message.c_str());
  }

 private:
  struct Event {
    DeviceEntry* entry;
    bool connected;
  };

  // Registers the URI (validating it) and announces it as connected. False while it is lost.
  bool announce(const std::string& uri) {
    DeviceEntry* to_announce = nullptr;
    {
      std::lock_guard lock(mutex_);
      auto it = entries_.find(uri);
      if (it != entries_.end()) return it->second->connected;  // already known to OpenNI
      if (uri.size() >= ONI_MAX_STR) throw std::invalid_argument("URI longer than OpenNI's 255 bytes: " + uri);
      auto entry = std::make_unique<DeviceEntry>();
      entry->uri = uri;
      entry->config = parse_virtual_uri(uri);
      FrameRenderer check(entry->config);  // unknown scene or profile: refuse now, not at open
      std::snprintf(entry->info.uri, ONI_MAX_STR, "%s", uri.c_str());
      std::snprintf(entry->info.vendor, ONI_MAX_STR, "%s", "hullgrind");
      std::snprintf(entry->info.name, ONI_MAX_STR, "virtual %s / %s", entry->config.profile.c_str(),
                    entry->config.scene.c_str());
      entry->connected = true;
      to_announce = entry.get();
      entries_.emplace(uri, std::move(entry));
    }
    deviceConnected(&to_announce->info);
    return true;
  }

  void event_loop() {
    std::unique_lock lock(mutex_);
    while (!stopping_) {
      // Due reconnections become events.
      std::optional<Clock::time_point> next;
      const auto now = Clock::now();
      for (auto& [uri, entry] : entries_) {
        if (!entry->reconnect_at) continue;
        if (*entry->reconnect_at <= now) {
          entry->reconnect_at.reset();
          entry->connected = true;
          pending_.push_back({entry.get(), true});
        } else if (!next || *entry->reconnect_at < *next) {
          next = entry->reconnect_at;
        }
      }
      while (!pending_.empty() && !stopping_) {
        const Event e = pending_.front();
        pending_.erase(pending_.begin());
        lock.unlock();
        if (e.connected) deviceConnected(&e.entry->info);
        else
          deviceDisconnected(&e.entry->info);
        lock.lock();
      }
      if (stopping_) break;
      if (next) wake_.wait_until(lock, *next);
      else
        wake_.wait(lock);
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::map<std::string, std::unique_ptr<DeviceEntry>> entries_;
  std::vector<Event> pending_;
  std::thread events_;
};

void VirtualDevice::report_lost() { driver_.device_lost(entry_); }

void VirtualStream::run() {
  const double fps = device_.entry().config.fps;
  const auto period = std::chrono::duration<double>(1.0 / fps);
  const auto t0 = Clock::now();
  for (std::uint64_t n = 1;; ++n) {
    {
      std::unique_lock lock(mutex_);
      wake_.wait_until(lock, t0 + std::chrono::duration_cast<Clock::duration>(period * double(n - 1)),
                       [this] { return !running_; });
      if (!running_) return;
    }
    if (!device_.may_serve_frame()) return;

    std::shared_ptr<const FrameRenderer::Frame> rendered;
    try {
      rendered = device_.frame(n);
    } catch (const std::exception& e) {
      device_.driver().log_error(std::string("render failed: ") + e.what());
      return;
    }
    OniFrame* frame = getServices().acquireFrame();
    if (frame == nullptr) continue;
    const OniVideoMode mode = mode_;
    frame->sensorType = sensor_;
    frame->frameIndex = static_cast<int>(n);
    // Device clock: microseconds since stream start at the nominal rate (deterministic, like a camera's
    // hardware timestamp; OpenNI timestamps are not wall-clock times). Frame n has the same time on both.
    frame->timestamp = static_cast<uint64_t>(std::llround((n - 1) * 1e6 / fps));
    frame->videoMode = mode;
    frame->width = mode.resolutionX;
    frame->height = mode.resolutionY;
    frame->croppingEnabled = FALSE;
    frame->cropOriginX = frame->cropOriginY = 0;
    frame->stride = mode.resolutionX * bytes_per_pixel(mode.pixelFormat);
    if (sensor_ == ONI_SENSOR_DEPTH) fill_depth(*frame, rendered->depth);
    else
      fill_ir(*frame, rendered->intensity);
    raiseNewFrame(frame);
    getServices().releaseFrame(frame);
    if (sensor_ == ONI_SENSOR_DEPTH) device_.frame_served();  // the fault injection counts depth frames
  }
}

void VirtualStream::fill_depth(OniFrame& frame, cv::Mat counts) const {
  const camera::Intrinsics& in = renderer_->intrinsics();
  if (pixel_format_for_unit(in.depth_unit) != frame.videoMode.pixelFormat) {
    // The other unit: same metres re-counted, x10 or /10 rounded half up, clamped to the reported range.
    const bool finer = unit_of(frame.videoMode.pixelFormat) < in.depth_unit;
    cv::Mat converted(counts.size(), CV_16UC1);
    for (int y = 0; y < counts.rows; ++y) {
      const auto* src = counts.ptr<std::uint16_t>(y);
      auto* dst = converted.ptr<std::uint16_t>(y);
      for (int x = 0; x < counts.cols; ++x) {
        const std::uint32_t v = finer ? std::uint32_t(src[x]) * 10u : (std::uint32_t(src[x]) + 5u) / 10u;
        dst[x] = static_cast<std::uint16_t>(std::min<std::uint32_t>(v, kLargestCount));
      }
    }
    counts = converted;
  }
  frame.dataSize = frame.stride * counts.rows + kGuardBytes;
  char* out = static_cast<char*>(frame.data);
  for (int y = 0; y < counts.rows; ++y) {
    auto* row = reinterpret_cast<std::uint16_t*>(out + y * frame.stride);
    std::memcpy(row, counts.ptr(y), frame.stride);
    for (int x = 0; x < counts.cols; ++x) row[x] = std::min(row[x], kLargestCount);  // 65535: see above
  }
  std::memcpy(out + counts.rows * frame.stride, kGuardTail, kGuardBytes);
}

void VirtualStream::fill_ir(OniFrame& frame, const cv::Mat& intensity) const {
  frame.dataSize = frame.stride * intensity.rows;
  char* out = static_cast<char*>(frame.data);
  const bool gray8 = frame.videoMode.pixelFormat == ONI_PIXEL_FORMAT_GRAY8;
  for (int y = 0; y < intensity.rows; ++y) {
    const auto* src = intensity.ptr<std::uint8_t>(y);
    if (gray8) {
      std::memcpy(out + y * frame.stride, src, intensity.cols);
      continue;
    }
    auto* row = reinterpret_cast<std::uint16_t*>(out + y * frame.stride);
    for (int x = 0; x < intensity.cols; ++x) row[x] = static_cast<std::uint16_t>((src[x] * kIrMaxValue16 + 127) / 255);
  }
}

}  // namespace
}  // namespace hg::sim::virtual_device

using HgVirtualDriver = hg::sim::virtual_device::VirtualDriver;
ONI_EXPORT_DRIVER(HgVirtualDriver)
