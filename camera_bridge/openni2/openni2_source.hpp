// The `openni2` depth source: a live OpenNI2 device (the first found, or one named by URI — including our
// virtual device, hg-virtual://...) or an .oni recording, which OpenNI2 opens as a device with playback
// control. Intrinsics come from the stream's fields of view and pixel format; the intensity image from the
// device's IR stream when it has one (docs/openni2.md).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "camera_types/depth_source.hpp"

namespace hg::camera_bridge {

struct OpenNI2Options {
  // Empty: the first device OpenNI2 enumerates. A path ending in ".oni": that recording. Otherwise a
  // device URI as OpenNI2 lists it (e.g. "hg-virtual://plate-hole-slot?profile=pm806").
  std::string uri;
  // .oni only. 1 = recorded rate, 2 = twice as fast, ... <= 0 = frame by frame at the reader's pace (each
  // grab() gets the next recorded frame, none dropped: OpenNI2's manual playback mode).
  double playback_speed = 1.0;
  bool loop = false;  // .oni only: start again after the last frame (else grab() returns nullopt at the end)
  // Open the device's IR stream, when it has one, and deliver its frame paired with each depth frame as
  // DepthFrame::intensity (GRAY8 as CV_8UC1; GRAY16 as CV_16UC1 scaled so the stream's MAX_VALUE is 65535).
  bool ir = true;
  // Depth video mode preference; 0 / any = no preference. The first supported mode matching every given
  // field is used; none matching is a SourceError listing the device's modes.
  int width = 0, height = 0, fps = 0;
  enum class DepthUnit { any, mm, tenth_mm } depth_unit = DepthUnit::any;  // DEPTH_1_MM / DEPTH_100_UM
};

class OpenNI2Source : public camera::DepthSource {
 public:
  explicit OpenNI2Source(OpenNI2Options options);
  ~OpenNI2Source() override;
  std::string describe() const override;
  void open() override;
  bool is_open() const override;
  std::optional<camera::DepthFrame> grab(std::chrono::milliseconds timeout) override;
  void close() override;

  bool is_recording() const;             // opened an .oni file
  bool end_of_recording() const;         // .oni without loop: the last frame has been delivered
  std::int64_t recorded_frames() const;  // .oni: frames in the recording; else 0
  // Frames dropped: their size did not match their header, or (reading IR) their IR frame was lost.
  std::int64_t skipped_frames() const;
  bool reads_ir() const;  // open, with the IR stream started

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

std::unique_ptr<camera::DepthSource> make_openni2_source(const OpenNI2Options& options);

}  // namespace hg::camera_bridge
