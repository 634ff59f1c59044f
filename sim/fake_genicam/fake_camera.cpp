#include "sim/fake_genicam/fake_camera.hpp"

#include <arv.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#ifndef HG_GENICAM_XML
#define HG_GENICAM_XML ""
#endif

namespace hg::sim {

namespace {
ArvGvFakeCamera* gv(void* p) { return static_cast<ArvGvFakeCamera*>(p); }
ArvFakeCamera* fake(void* p) { return arv_gv_fake_camera_get_fake_camera(gv(p)); }
}  // namespace

FakeGenicamCamera::FakeGenicamCamera(FakeGenicamOptions options) : options_(std::move(options)) {
  if (options_.xml_path.empty()) options_.xml_path = HG_GENICAM_XML;
  if (!(options_.scale_mm > 0)) throw std::invalid_argument("fake genicam camera: scale_mm must be positive");
  gv_ = arv_gv_fake_camera_new_full(options_.interface.c_str(), options_.serial.c_str(), options_.xml_path.c_str());
  if (!gv_ || !arv_gv_fake_camera_is_running(gv(gv_))) {
    if (gv_) g_object_unref(gv(gv_));
    gv_ = nullptr;
    throw std::runtime_error("fake genicam camera: Aravis could not start a GigE Vision device on '" +
                             options_.interface + "' with '" + options_.xml_path + "'");
  }
  ArvFakeCamera* cam = fake(gv_);
  namespace r = fake_genicam_reg;
  const CameraProfile& p = options_.profile;
  write_register(ARV_FAKE_CAMERA_REGISTER_SENSOR_WIDTH, static_cast<std::uint32_t>(p.width));
  write_register(ARV_FAKE_CAMERA_REGISTER_SENSOR_HEIGHT, static_cast<std::uint32_t>(p.height));
  write_register(r::kWidth, static_cast<std::uint32_t>(p.width));
  write_register(r::kHeight, static_cast<std::uint32_t>(p.height));
  write_register(ARV_FAKE_CAMERA_REGISTER_PIXEL_FORMAT, ARV_PIXEL_FORMAT_COORD3D_C_16);
  write_register(ARV_FAKE_CAMERA_REGISTER_ACQUISITION_FRAME_PERIOD_US,
                 static_cast<std::uint32_t>(1e6 / std::max(0.1, options_.frame_rate)));
  write_double(r::kScale, options_.scale_mm);
  write_double(r::kOffset, options_.offset_mm);
  write_double(r::kInvalid, 0.0);
  write_double(r::kFocal, p.fx);
  write_double(r::kPpu, p.cx);
  write_double(r::kPpv, p.cy);
  // How often the device looks for a software trigger.
  arv_fake_camera_set_trigger_frequency(cam, 50.0);
  arv_fake_camera_set_fill_pattern(
      cam, [](ArvBuffer* b, void* self, guint32 e, guint32 g, ArvPixelFormat f) { fill(b, self, e, g, f); }, this);
}

FakeGenicamCamera::~FakeGenicamCamera() {
  if (gv_) g_object_unref(gv(gv_));
}

void FakeGenicamCamera::write_register(std::uint32_t address, std::uint32_t value) {
  arv_fake_camera_write_register(fake(gv_), address, value);
}

std::uint32_t FakeGenicamCamera::read_register(std::uint32_t address) const {
  guint32 v = 0;
  arv_fake_camera_read_register(fake(gv_), address, &v);
  return v;
}

void FakeGenicamCamera::set_packet_loss(double ratio) { g_object_set(gv(gv_), "gvsp-lost-ratio", ratio, nullptr); }

void FakeGenicamCamera::write_double(std::uint32_t address, double value) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, 8);
  bits = GUINT64_TO_BE(bits);
  arv_fake_camera_write_memory(fake(gv_), address, 8, &bits);
}

std::uint16_t FakeGenicamCamera::raw_of(double metres) const {
  if (!(metres > 0)) return 0;
  const double raw = std::round((metres * 1000.0 - options_.offset_mm) / options_.scale_mm);
  return raw >= 1 && raw <= 65535 ? static_cast<std::uint16_t>(raw) : 0;
}

// Called by Aravis's device thread for each frame it sends (see FakeGenicamOptions::fixed_frame_index).
void FakeGenicamCamera::fill(void* buffer, void* self_ptr, std::uint32_t, std::uint32_t, std::uint32_t format) {
  auto* self = static_cast<FakeGenicamCamera*>(self_ptr);
  auto* b = static_cast<ArvBuffer*>(buffer);
  // arv_buffer_get_data's size is the received size (0 on the sending side); the device allocated the buffer
  // with the payload of its registers when acquisition started, and sends exactly that many bytes.
  auto* data = static_cast<std::uint8_t*>(const_cast<void*>(arv_buffer_get_data(b, nullptr)));
  const size_t size = arv_fake_camera_get_payload(fake(self->gv_));
  const int w = arv_buffer_get_image_width(b), h = arv_buffer_get_image_height(b);
  std::memset(data, 0, size);
  const CameraProfile& p = self->options_.profile;
  const std::int64_t index = self->served_++;
  const bool abc = format == ARV_PIXEL_FORMAT_COORD3D_ABC_32F;
  if ((!abc && format != ARV_PIXEL_FORMAT_COORD3D_C_16) || w != p.width || h != p.height ||
      size < size_t(w) * h * (abc ? 12 : 2))
    return;
  const std::int64_t k = self->options_.fixed_frame_index >= 0 ? self->options_.fixed_frame_index : index;
  const RenderedFrame r = render(self->options_.scene, p, static_cast<std::uint64_t>(k));
  for (int y = 0; y < h; ++y) {
    const std::uint16_t* src = r.depth.ptr<std::uint16_t>(y);
    if (abc) {
      self->fill_abc32f_row(src, y, reinterpret_cast<float*>(data + size_t(y) * w * 12));
      continue;
    }
    std::uint8_t* dst = data + size_t(y) * w * 2;
    for (int x = 0; x < w; ++x) {
      const std::uint16_t raw = src[x] ? self->raw_of(src[x] * p.depth_unit) : 0;
      dst[2 * x] = static_cast<std::uint8_t>(raw & 0xff);  // GigE Vision pixel data: little-endian
      dst[2 * x + 1] = static_cast<std::uint8_t>(raw >> 8);
    }
  }
}

// Coord3D_ABC32f: (X, Y, Z) of each pixel's depth through the profile's pinhole, each coordinate as
// (mm - offset) / scale; NaN where there is no depth.
void FakeGenicamCamera::fill_abc32f_row(const std::uint16_t* depth, int row, float* xyz) const {
  const CameraProfile& p = options_.profile;
  const auto coded = [&](double mm) { return static_cast<float>((mm - options_.offset_mm) / options_.scale_mm); };
  for (int x = 0; x < p.width; ++x, xyz += 3) {
    if (!depth[x]) {
      xyz[0] = xyz[1] = xyz[2] = std::numeric_limits<float>::quiet_NaN();
      continue;
    }
    const double z = depth[x] * p.depth_unit * 1000.0;
    xyz[0] = static_cast<float>((x - p.cx) / p.fx * z);  // A and B unscaled: the bridge reads only C
    xyz[1] = static_cast<float>((row - p.cy) / p.fy * z);
    xyz[2] = coded(z);
  }
}

}  // namespace hg::sim
