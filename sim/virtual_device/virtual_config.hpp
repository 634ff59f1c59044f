// Configuration of the virtual OpenNI2 device (libhg-virtual.so.0): which synthetic scene it renders, with
// which camera profile, at what rate, and which faults it injects. Chosen by the device URI
//   hg-virtual://<scene>?profile=<name>&fps=<hz>&seed=<n>&disconnect_after=<frames>&reconnect_after=<s>
//                      &cropping=<0|1>
// or, for the device the driver announces on its own, by environment variables (see docs/openni2.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "camera_types/depth_source.hpp"

namespace hg::sim::virtual_device {

inline constexpr const char* kUriScheme = "hg-virtual://";

struct VirtualDeviceConfig {
  std::string scene = "plate-hole-slot";  // scene preset name
  std::string profile = "pm806";          // camera profile name
  double fps = 5.0;                       // frames per second, 0 < fps <= 120
  std::optional<std::uint64_t> seed;      // overrides the preset's noise seed
  // Fault injection: after this many frames of one session (device open) the device disconnects...
  std::optional<std::uint64_t> disconnect_after;
  // ...and comes back this many seconds later (absent: stays away until the driver is reloaded).
  std::optional<double> reconnect_after;
  // false: the depth stream does not support ONI_STREAM_PROPERTY_CROPPING, like Debian's DummyDevice;
  // an .oni recorded from such a stream plays back no frames (docs/openni2.md says why).
  bool cropping_property = true;
};

// Parses a hg-virtual:// URI. Throws std::invalid_argument naming the offending part and its byte offset.
VirtualDeviceConfig parse_virtual_uri(const std::string& uri);
// The canonical URI of a configuration (parse_virtual_uri(to_uri(c)) == c).
std::string to_uri(const VirtualDeviceConfig& config);

// The device the driver announces at start-up: HG_VIRTUAL_URI if set, else HG_VIRTUAL_SCENE,
// HG_VIRTUAL_PROFILE, HG_VIRTUAL_FPS, HG_VIRTUAL_SEED, HG_VIRTUAL_DISCONNECT_AFTER,
// HG_VIRTUAL_RECONNECT_AFTER over the defaults above. Returns the URI (throws like parse_virtual_uri).
std::string announced_uri_from_environment();

// The frames the device serves: frame n (OpenNI frameIndex n, counted from 1) is the scene renderer's
// render(scene, profile, n): its depth, in counts of intrinsics().depth_unit, and its intensity image.
class FrameRenderer {
 public:
  struct Frame {
    cv::Mat depth;      // CV_16UC1
    cv::Mat intensity;  // CV_8UC1, 255 = saturated; empty when !has_intensity()
  };
  explicit FrameRenderer(const VirtualDeviceConfig& config);  // throws std::invalid_argument (unknown names)
  const camera::Intrinsics& intrinsics() const { return intrinsics_; }
  // The scene renders an intensity image (its effects say so, as the realistic presets do): the device
  // then has an IR sensor.
  bool has_intensity() const;
  Frame render_frame(std::uint64_t frame_index) const;
  cv::Mat render(std::uint64_t frame_index) const { return render_frame(frame_index).depth; }  // CV_16UC1

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
  camera::Intrinsics intrinsics_;
};

}  // namespace hg::sim::virtual_device
