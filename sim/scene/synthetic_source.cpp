#include "sim/scene/synthetic_source.hpp"

#include "camera_types/pacing.hpp"
#include "runtime/node.hpp"

namespace hg::sim {

SyntheticSource::SyntheticSource(SceneSpec spec, CameraProfile profile, double rate)
    : spec_(std::move(spec)), profile_(std::move(profile)), period_(camera::period_of(rate)) {}

std::string SyntheticSource::describe() const {
  return "synthetic scene '" + spec_.name + "' with camera profile " + profile_.name;
}

std::optional<camera::DepthFrame> SyntheticSource::grab(std::chrono::milliseconds timeout) {
  if (!open_) throw camera::SourceError("synthetic source is not open");
  if (!camera::wait_slot(next_, period_, timeout)) return std::nullopt;
  camera::DepthFrame f;
  f.seq = index_;
  RenderedFrame r = render(spec_, profile_, static_cast<std::uint64_t>(index_++));
  // Stamped when the frame exists, as a camera stamps its frames: the rendering stands in for the exposure
  // and the transfer, which a real depth camera does without our CPU, and is not the pipeline's latency.
  f.utime = runtime::now_utime();
  f.intrinsics = r.intrinsics;
  f.depth = std::move(r.depth);
  f.intensity = std::move(r.intensity);
  return f;
}

}  // namespace hg::sim
