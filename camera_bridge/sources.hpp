// The depth sources the bridge knows besides OpenNI2 and GenICam: `synthetic` (the scene renderer, a plug-in
// from the simulation layer: sim/scene/synthetic_source.hpp) and `files` (16-bit depth PNGs + an intrinsics
// YAML, or one .pcd/.ply cloud projected through those intrinsics).
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "camera_types/depth_source.hpp"
#include "sim/scene/synthetic_source.hpp"

namespace hg::camera_bridge {

// Intrinsics from an OpenCV FileStorage file (YAML/JSON/XML): width, height, fx, fy, cx, cy and
// depth_unit (metres per count, default 0.001). Throws SourceError naming the file and the key.
camera::Intrinsics read_intrinsics(const std::string& path);
void write_intrinsics(const camera::Intrinsics& in, const std::string& path);

// A directory of 16-bit single-channel PNGs (sorted by name), or a single .png, or a single .pcd/.ply
// cloud in the camera frame (metres) rendered into a depth image through the intrinsics (nearest point
// per pixel). Frames at `rate` Hz (<= 0: as fast as asked); after the last file start again when `loop`,
// else grab() returns nullopt. A file that does not decode as a 16-bit PNG is delivered as an empty frame
// (the bridge counts it as corrupt and logs the file name); open() fails when there is no input at all.
class FilesSource : public camera::DepthSource {
 public:
  FilesSource(std::string path, std::string intrinsics_path, double rate, bool loop);
  std::string describe() const override;
  void open() override;
  bool is_open() const override { return open_; }
  std::optional<camera::DepthFrame> grab(std::chrono::milliseconds timeout) override;
  void close() override { open_ = false; }
  const std::vector<std::string>& files() const { return files_; }
  bool finished() const { return !loop_ && next_file_ >= files_.size(); }

 private:
  std::string path_, intrinsics_path_;
  bool loop_;
  camera::Intrinsics intrinsics_;
  std::vector<std::string> files_;
  std::size_t next_file_ = 0;
  std::int64_t seq_ = 0;
  std::chrono::steady_clock::duration period_{};
  std::chrono::steady_clock::time_point next_{};
  bool open_ = false;
};

// A cloud (x, y, z triples, camera frame, metres) rendered into a depth image: per pixel the nearest point.
cv::Mat cloud_to_depth(const std::vector<double>& xyz, const camera::Intrinsics& in);
// True when this build reads .pcd/.ply (the outline I/O library was there at configure time).
bool can_read_clouds();

}  // namespace hg::camera_bridge
