// The camera bridge's `synthetic` depth source: the scene renderer behind the DepthSource interface. A
// source plug-in at the simulation layer: the bridge links it (dependencies point down), the renderer and
// the generator's shapes stay out of the bridge's own folder.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "camera_types/depth_source.hpp"
#include "sim/scene/scene.hpp"

namespace hg::sim {

// Renders spec with profile; frames come at `rate` Hz (<= 0: as fast as they are asked for), frame index
// 0, 1, 2, ... so a run is reproducible.
class SyntheticSource : public camera::DepthSource {
 public:
  SyntheticSource(SceneSpec spec, CameraProfile profile, double rate);
  std::string describe() const override;
  void open() override { open_ = true; }
  bool is_open() const override { return open_; }
  std::optional<camera::DepthFrame> grab(std::chrono::milliseconds timeout) override;
  void close() override { open_ = false; }
  const SceneSpec& spec() const { return spec_; }
  const CameraProfile& profile() const { return profile_; }

 private:
  SceneSpec spec_;
  CameraProfile profile_;
  std::chrono::steady_clock::duration period_{};
  std::chrono::steady_clock::time_point next_{};
  std::int64_t index_ = 0;
  bool open_ = false;
};

}  // namespace hg::sim
