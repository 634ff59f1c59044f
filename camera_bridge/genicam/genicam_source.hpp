// The `genicam` depth source: an industrial 3-D camera over GigE Vision / USB3 Vision through Aravis
// (Debian's libaravis), reading range images (Coord3D_C16) and the SFNC Scan3d features for the depth
// scale and offset, the focal length and the principal point (docs/cameras.md).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "camera_types/depth_source.hpp"

namespace hg::camera_bridge {

// The pixel format read: range images (one 16-bit Z per pixel) or organized point clouds (X, Y, Z floats per
// pixel, of which the bridge keeps Z on the camera's pixel grid).
enum class GenicamFormat { c16, abc32f };
const char* genicam_format_name(GenicamFormat f);  // "Coord3D_C16", "Coord3D_ABC32f"
// Counts of an ABC32f frame: 0.1 mm (16 bits reach 6.5 m).
constexpr double kAbc32fDepthUnit = 1e-4;

struct GenicamOptions {
  // Aravis device id (as `arv-tool-0.8` lists it: "Vendor-Model-Serial", its serial, or its IP address). Empty:
  // the first device found that offers the pixel format (below) and the Scan3d features.
  std::string device_id;
  // true: TriggerMode On, TriggerSource Software, one TriggerSoftware per grab(); false: free-running.
  bool software_trigger = false;
  GenicamFormat format = GenicamFormat::c16;
};

// Counters of what was received and skipped since construction.
struct GenicamCounters {
  std::atomic<std::int64_t> frames{0};        // good frames delivered
  std::atomic<std::int64_t> timeouts{0};      // grab() calls that got no buffer in time
  std::atomic<std::int64_t> incomplete{0};    // buffers with a status other than success, skipped
  std::atomic<std::int64_t> unusable{0};      // complete buffers of a wrong format or size, skipped
  std::atomic<std::int64_t> out_of_range{0};  // pixels whose distance does not fit 16-bit counts (set to 0)
};

class GenicamSource : public camera::DepthSource {
 public:
  explicit GenicamSource(GenicamOptions options);
  ~GenicamSource() override;
  std::string describe() const override;
  void open() override;  // SourceError: no device, no 3-D camera, missing Scan3d feature, ...
  bool is_open() const override;
  // nullopt on a timeout or a skipped buffer; SourceError when the camera's control channel was lost.
  std::optional<camera::DepthFrame> grab(std::chrono::milliseconds timeout) override;
  void close() override;
  std::int64_t frames_skipped() const override { return counters_.incomplete + counters_.unusable; }

  const GenicamCounters& counters() const { return counters_; }
  const camera::Intrinsics& intrinsics() const;  // as read from the camera at open()
  std::string opened_device() const;             // the id of the device open now ("" when closed)

 private:
  void configure();                                             // pixel format, Scan3d -> intrinsics, trigger
  void start_stream();                                          // buffers, lost-camera signal, AcquisitionStart
  std::optional<camera::DepthFrame> convert(void* arv_buffer);  // nullopt (and counted) for a buffer to skip
  std::size_t bytes_per_pixel() const;
  struct Impl;
  GenicamOptions options_;
  GenicamCounters counters_;
  std::unique_ptr<Impl> impl_;
};

// Depth in metres of a Coord3D_C16 raw value, by the SFNC rule C = raw * scale + offset (millimetres).
// The bridge keeps depth as 16-bit counts of depth_unit = scale mm, so a raw value becomes
// raw + round(offset / scale) counts; `invalid` raw values and results outside 1..65535 become 0 (no data).
// Returns the count; `out_of_range` is set when a valid raw value did not fit.
std::uint16_t c16_to_count(std::uint16_t raw, std::int64_t offset_counts, std::int64_t invalid, bool& out_of_range);

// Count of kAbc32fDepthUnit of a Coord3D_ABC32f C (Z) value: C * scale + offset millimetres, rounded. NaN,
// infinite and `invalid` values are 0 (no data); a result outside 1..65535 is 0 with out_of_range set.
std::uint16_t abc32f_to_count(float c, double scale_mm, double offset_mm, double invalid, bool& out_of_range);

}  // namespace hg::camera_bridge
