#include "camera_bridge/genicam/genicam_source.hpp"

#include <arv.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "runtime/log.hpp"
#include "runtime/node.hpp"

namespace hg::camera_bridge {

using runtime::Level;
using runtime::logf;

namespace {

constexpr int kBuffers = 4;

// Aravis reports failures through GError; this turns one into a SourceError naming what was being done.
struct ErrorGuard {
  GError* error = nullptr;
  ~ErrorGuard() { g_clear_error(&error); }
  GError** out() { return &error; }
  void check(const std::string& what) {
    if (!error) return;
    const std::string msg = what + ": " + error->message;
    g_clear_error(&error);
    throw camera::SourceError(msg);
  }
};

bool offers_format(ArvCamera* cam, const char* wanted) {
  GError* err = nullptr;
  guint n = 0;
  const char** formats = arv_camera_dup_available_enumerations_as_strings(cam, "PixelFormat", &n, &err);
  bool found = false;
  for (guint i = 0; formats && i < n; ++i) found = found || std::strcmp(formats[i], wanted) == 0;
  g_free(formats);
  g_clear_error(&err);
  return found;
}

bool has_feature(ArvCamera* cam, const char* name) {
  GError* err = nullptr;
  const bool yes = arv_camera_is_feature_available(cam, name, &err) && !err;
  g_clear_error(&err);
  return yes;
}

bool is_3d_camera(ArvCamera* cam, const char* format) {
  return offers_format(cam, format) && has_feature(cam, "Scan3dCoordinateScale") &&
         has_feature(cam, "Scan3dFocalLength");
}

}  // namespace

const char* genicam_format_name(GenicamFormat f) {
  return f == GenicamFormat::abc32f ? "Coord3D_ABC32f" : "Coord3D_C16";
}

std::uint16_t c16_to_count(std::uint16_t raw, std::int64_t offset_counts, std::int64_t invalid, bool& out_of_range) {
  out_of_range = false;
  if (raw == invalid) return 0;
  const std::int64_t c = std::int64_t(raw) + offset_counts;
  if (c < 1 || c > 65535) {
    out_of_range = true;
    return 0;
  }
  return static_cast<std::uint16_t>(c);
}

struct GenicamSource::Impl {
  ArvCamera* camera = nullptr;
  ArvStream* stream = nullptr;
  gulong lost_handler = 0;
  std::atomic<bool> lost{false};
  std::string device;
  camera::Intrinsics intrinsics;
  std::int64_t offset_counts = 0, invalid_raw = 0;
  double scale_mm = 1, offset_mm = 0, invalid_value = 0;  // Scan3d C coordinate
  guint payload = 0;
  std::int64_t seq = 0;

  static void on_control_lost(ArvDevice*, gpointer self) { static_cast<Impl*>(self)->lost = true; }

  void release() {
    if (camera && lost_handler) g_signal_handler_disconnect(arv_camera_get_device(camera), lost_handler);
    lost_handler = 0;
    if (camera && !lost) {
      GError* err = nullptr;
      arv_camera_stop_acquisition(camera, &err);
      g_clear_error(&err);
    }
    g_clear_object(&stream);
    g_clear_object(&camera);
    device.clear();
  }
};

GenicamSource::GenicamSource(GenicamOptions options) : options_(std::move(options)), impl_(std::make_unique<Impl>()) {}
GenicamSource::~GenicamSource() { close(); }

std::string GenicamSource::describe() const {
  std::string s = "genicam ";
  s += options_.device_id.empty() ? "(first 3-D camera)" : "'" + options_.device_id + "'";
  if (!impl_->device.empty() && impl_->device != options_.device_id) s += " = '" + impl_->device + "'";
  s += std::string(", ") + genicam_format_name(options_.format);
  return s + (options_.software_trigger ? ", software trigger" : ", free-running");
}

bool GenicamSource::is_open() const { return impl_->camera != nullptr; }
const camera::Intrinsics& GenicamSource::intrinsics() const { return impl_->intrinsics; }
std::string GenicamSource::opened_device() const { return impl_->device; }

namespace {

// The first device Aravis finds that is a 3-D camera (see is_3d_camera), with its id.
ArvCamera* first_3d_camera(const char* format, std::string& id, std::string& seen) {
  arv_update_device_list();
  const unsigned n = arv_get_n_devices();
  for (unsigned i = 0; i < n; ++i) {
    const char* dev = arv_get_device_id(i);
    if (!dev) continue;
    seen += (seen.empty() ? "" : ", ") + std::string(dev);
    GError* err = nullptr;
    ArvCamera* cam = arv_camera_new(dev, &err);
    g_clear_error(&err);
    if (!cam) continue;
    if (is_3d_camera(cam, format)) {
      id = dev;
      return cam;
    }
    g_object_unref(cam);
  }
  return nullptr;
}

double get_float(ArvCamera* cam, const char* name) {
  ErrorGuard e;
  const double v = arv_camera_get_float(cam, name, e.out());
  e.check(std::string("reading ") + name);
  return v;
}

void set_string(ArvCamera* cam, const char* name, const char* value) {
  ErrorGuard e;
  arv_camera_set_string(cam, name, value, e.out());
  e.check(std::string("setting ") + name + " to " + value);
}

}  // namespace

void GenicamSource::open() {
  close();
  Impl& m = *impl_;
  m.lost = false;
  if (options_.device_id.empty()) {
    std::string seen;
    m.camera = first_3d_camera(genicam_format_name(options_.format), m.device, seen);
    if (!m.camera)
      throw camera::SourceError(std::string("no GenICam 3-D camera (") + genicam_format_name(options_.format) +
                                " with Scan3d features) found" +
                                (seen.empty() ? std::string(", no devices at all") : "; devices seen: " + seen));
  } else {
    ErrorGuard e;
    m.camera = arv_camera_new(options_.device_id.c_str(), e.out());
    e.check("cannot open GenICam device '" + options_.device_id + "'");
    if (!m.camera) throw camera::SourceError("cannot open GenICam device '" + options_.device_id + "'");
    m.device = options_.device_id;
    if (!is_3d_camera(m.camera, genicam_format_name(options_.format))) {
      close();
      throw camera::SourceError("GenICam device '" + options_.device_id + "' is not a 3-D camera: no PixelFormat " +
                                genicam_format_name(options_.format) +
                                " or no Scan3dCoordinateScale/Scan3dFocalLength");
    }
  }
  try {
    configure();
    start_stream();
  } catch (...) {
    close();
    throw;
  }
  logf(Level::Info, "genicam '%s': %dx%d, f %.3f px, principal point (%.3f, %.3f), %.6g mm per count%s",
       m.device.c_str(), m.intrinsics.width, m.intrinsics.height, m.intrinsics.fx, m.intrinsics.cx, m.intrinsics.cy,
       m.intrinsics.depth_unit * 1000, options_.software_trigger ? ", software trigger" : "");
}

void GenicamSource::configure() {
  Impl& m = *impl_;
  ArvCamera* cam = m.camera;
  set_string(cam, "PixelFormat", genicam_format_name(options_.format));
  if (has_feature(cam, "Scan3dCoordinateSelector")) set_string(cam, "Scan3dCoordinateSelector", "CoordinateC");
  if (has_feature(cam, "Scan3dDistanceUnit")) {
    ErrorGuard e;
    const char* unit = arv_camera_get_string(cam, "Scan3dDistanceUnit", e.out());
    e.check("reading Scan3dDistanceUnit");
    if (!unit || std::strcmp(unit, "Millimeter") != 0)
      throw camera::SourceError(std::string("Scan3dDistanceUnit is '") + (unit ? unit : "") +
                                "', only Millimeter is supported");
  }
  const double scale = get_float(cam, "Scan3dCoordinateScale");
  const double offset = has_feature(cam, "Scan3dCoordinateOffset") ? get_float(cam, "Scan3dCoordinateOffset") : 0.0;
  const double focal = get_float(cam, "Scan3dFocalLength");
  if (!(scale > 0) || !std::isfinite(scale))
    throw camera::SourceError("Scan3dCoordinateScale must be positive, is " + std::to_string(scale));
  if (!(focal > 0) || !std::isfinite(focal))
    throw camera::SourceError("Scan3dFocalLength must be positive, is " + std::to_string(focal));
  if (!std::isfinite(offset)) throw camera::SourceError("Scan3dCoordinateOffset is not finite");
  camera::Intrinsics& in = m.intrinsics;
  ErrorGuard e;
  in.width = static_cast<int>(arv_camera_get_integer(cam, "Width", e.out()));
  e.check("reading Width");
  in.height = static_cast<int>(arv_camera_get_integer(cam, "Height", e.out()));
  e.check("reading Height");
  in.fx = in.fy = focal;
  // A missing principal point is the one thing we may not guess from the image centre silently.
  if (!has_feature(cam, "Scan3dPrincipalPointU") || !has_feature(cam, "Scan3dPrincipalPointV"))
    throw camera::SourceError("the camera has no Scan3dPrincipalPointU/V");
  in.cx = get_float(cam, "Scan3dPrincipalPointU");
  in.cy = get_float(cam, "Scan3dPrincipalPointV");
  m.scale_mm = scale;
  m.offset_mm = offset;
  // Scan3dDistanceUnit Millimeter. C16 keeps the camera's step; float coordinates get a fixed one.
  in.depth_unit = options_.format == GenicamFormat::c16 ? scale * 1e-3 : kAbc32fDepthUnit;
  // Counts keep the raw values' step (scale); an offset that is no whole number of steps costs at most half.
  m.offset_counts = std::llround(offset / scale);
  m.invalid_value = has_feature(cam, "Scan3dInvalidDataValue") ? get_float(cam, "Scan3dInvalidDataValue") : 0.0;
  m.invalid_raw = std::llround(m.invalid_value);
  if (has_feature(cam, "TriggerSelector")) set_string(cam, "TriggerSelector", "FrameStart");
  if (options_.software_trigger) {
    set_string(cam, "TriggerMode", "On");
    set_string(cam, "TriggerSource", "Software");
  } else if (has_feature(cam, "TriggerMode")) {
    set_string(cam, "TriggerMode", "Off");
  }
  if (has_feature(cam, "AcquisitionMode")) set_string(cam, "AcquisitionMode", "Continuous");
}

void GenicamSource::start_stream() {
  Impl& m = *impl_;
  ErrorGuard e;
  m.payload = arv_camera_get_payload(m.camera, e.out());
  e.check("reading PayloadSize");
  if (m.payload < guint(m.intrinsics.width) * guint(m.intrinsics.height) * bytes_per_pixel())
    throw camera::SourceError("PayloadSize " + std::to_string(m.payload) + " is smaller than a " +
                              genicam_format_name(options_.format) + " image");
  m.stream = arv_camera_create_stream(m.camera, nullptr, nullptr, e.out());
  e.check("creating the stream");
  if (!m.stream) throw camera::SourceError("creating the stream failed");
  // A socket buffer of a whole frame: a range image is MBs, the default UDP buffer drops packets.
  if (ARV_IS_GV_STREAM(m.stream)) g_object_set(m.stream, "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_AUTO, nullptr);
  for (int i = 0; i < kBuffers; ++i) arv_stream_push_buffer(m.stream, arv_buffer_new(m.payload, nullptr));
  m.lost_handler =
      g_signal_connect(arv_camera_get_device(m.camera), "control-lost", G_CALLBACK(Impl::on_control_lost), &m);
  arv_camera_start_acquisition(m.camera, e.out());
  e.check("AcquisitionStart");
}

void GenicamSource::close() {
  if (impl_) impl_->release();
}

std::optional<camera::DepthFrame> GenicamSource::grab(std::chrono::milliseconds timeout) {
  Impl& m = *impl_;
  if (!m.camera) throw camera::SourceError("genicam source is not open");
  const auto lost = [&] {
    return camera::SourceError("GenICam camera '" + m.device + "' lost (no answer on its control channel)");
  };
  if (m.lost) throw lost();
  if (options_.software_trigger) {
    ErrorGuard e;
    arv_camera_execute_command(m.camera, "TriggerSoftware", e.out());
    if (m.lost) throw lost();
    e.check("TriggerSoftware");
  }
  ArvBuffer* buf = arv_stream_timeout_pop_buffer(m.stream, guint64(timeout.count()) * 1000);
  if (!buf) {
    ++counters_.timeouts;
    if (m.lost) throw lost();
    return std::nullopt;
  }
  std::optional<camera::DepthFrame> frame = convert(static_cast<void*>(buf));
  arv_stream_push_buffer(m.stream, buf);
  return frame;
}

std::size_t GenicamSource::bytes_per_pixel() const { return options_.format == GenicamFormat::c16 ? 2 : 12; }

std::optional<camera::DepthFrame> GenicamSource::convert(void* arv_buffer) {
  Impl& m = *impl_;
  ArvBuffer* buf = static_cast<ArvBuffer*>(arv_buffer);
  if (arv_buffer_get_status(buf) != ARV_BUFFER_STATUS_SUCCESS) {
    ++counters_.incomplete;
    return std::nullopt;
  }
  const camera::Intrinsics& in = m.intrinsics;
  const ArvPixelFormat want =
      options_.format == GenicamFormat::c16 ? ARV_PIXEL_FORMAT_COORD3D_C_16 : ARV_PIXEL_FORMAT_COORD3D_ABC_32F;
  size_t size = 0;
  const auto* raw = static_cast<const std::uint8_t*>(arv_buffer_get_data(buf, &size));
  if (arv_buffer_get_payload_type(buf) != ARV_BUFFER_PAYLOAD_TYPE_IMAGE ||
      arv_buffer_get_image_pixel_format(buf) != want || arv_buffer_get_image_width(buf) != in.width ||
      arv_buffer_get_image_height(buf) != in.height || !raw ||
      size < size_t(in.width) * size_t(in.height) * bytes_per_pixel()) {
    ++counters_.unusable;
    return std::nullopt;
  }
  camera::DepthFrame f;
  f.seq = m.seq++;
  f.utime = runtime::now_utime();
  f.intrinsics = in;
  f.depth.create(in.height, in.width, CV_16UC1);
  std::int64_t bad = 0;
  for (int r = 0; r < in.height; ++r) {
    std::uint16_t* dst = f.depth.ptr<std::uint16_t>(r);
    const std::uint8_t* row = raw + size_t(r) * size_t(in.width) * bytes_per_pixel();
    for (int c = 0; c < in.width; ++c) {
      bool oor = false;
      if (options_.format == GenicamFormat::c16) {
        // GigE Vision pixel data is little-endian.
        const std::uint16_t v = static_cast<std::uint16_t>(row[2 * c] | (row[2 * c + 1] << 8));
        dst[c] = c16_to_count(v, m.offset_counts, m.invalid_raw, oor);
      } else {
        float z;  // C of (A, B, C), little-endian IEEE floats like the host's
        std::memcpy(&z, row + 12 * size_t(c) + 8, 4);
        dst[c] = abc32f_to_count(z, m.scale_mm, m.offset_mm, m.invalid_value, oor);
      }
      bad += oor;
    }
  }
  counters_.out_of_range += bad;
  ++counters_.frames;
  return f;
}

std::uint16_t abc32f_to_count(float c, double scale_mm, double offset_mm, double invalid, bool& out_of_range) {
  out_of_range = false;
  if (!std::isfinite(c) || double(c) == invalid) return 0;
  const double counts = std::round((double(c) * scale_mm + offset_mm) * 1e-3 / kAbc32fDepthUnit);
  if (!(counts >= 1 && counts <= 65535)) {
    out_of_range = true;
    return 0;
  }
  return static_cast<std::uint16_t>(counts);
}

}  // namespace hg::camera_bridge
