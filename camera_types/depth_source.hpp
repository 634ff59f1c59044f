// Where depth frames come from. The bridge only sees this interface, so a vendor SDK backend
// (Percipio, Mech-Eye) can be added later without touching segmentation or publishing.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>

namespace hg::camera {

// Pinhole intrinsics of the depth image as delivered (pixels), and the depth scale.
struct Intrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double depth_unit = 0.001;  // metres per depth count; count 0 = no data
};

struct DepthFrame {
  std::int64_t seq = 0;    // frame counter of the source
  std::int64_t utime = 0;  // capture time, microseconds since the epoch
  Intrinsics intrinsics;
  cv::Mat depth;  // CV_16UC1, height x width
  // The sensor's intensity (reflected light) image of the same pixels, registered to depth: CV_8UC1 (255 =
  // saturated) or CV_16UC1; empty when the source has none. The bridge uses it to tell dropout on steel
  // (light came back, no depth) from a hole.
  cv::Mat intensity;
};

// The device is missing, lost or unreadable; what() says which and why.
struct SourceError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class DepthSource {
 public:
  virtual ~DepthSource() = default;
  virtual std::string describe() const = 0;  // for logs and the heartbeat: "openni2 (first device)", ...
  virtual void open() = 0;                   // throws SourceError when the device cannot be opened
  virtual bool is_open() const = 0;
  // Next frame, waiting at most `timeout`: nullopt when none came in time. Throws SourceError when the
  // device is lost (the caller closes, backs off and re-opens).
  virtual std::optional<DepthFrame> grab(std::chrono::milliseconds timeout) = 0;
  virtual void close() = 0;
  // Frames the device sent that the source dropped since construction (incomplete or malformed buffers);
  // the bridge counts them as dropped in its heartbeat. 0 for sources that drop none.
  virtual std::int64_t frames_skipped() const { return 0; }
};

}  // namespace hg::camera
