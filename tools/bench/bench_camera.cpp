// hg-bench-camera: time from a depth frame to an encoded plate_cloud_t (segmentation + message fill +
// LCM encoding), one thread, median over N frames, for each camera profile. Frames are rendered first
// (rendering is not timed). A benchmark that prints figures, not a test.
#include <algorithm>
#include <ctime>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "camera_bridge/camera_bridge.hpp"
#include "runtime/params.hpp"
#include "sim/scene/scene.hpp"
#include "camera_bridge/segment.hpp"

using namespace hg::camera_bridge;
using namespace hg::sim;

namespace {

constexpr const char* kUsageHead =
    "usage: hg-bench-camera [options]\n"
    "Times depth frame -> encoded plate_cloud_t per camera profile (one thread, median of N).\n";

std::vector<hg::runtime::Param> bench_params() {
  using namespace hg::runtime;
  std::vector<Param> params = {integer_param("frames", "30", "frames timed per profile (median)", 1, 1e6),
                               text_param("scene", "three-parts", "scene preset of the renderer"),
                               flag_param("all-parts", "segment every part, not only the largest")};
  set_value_names(params, {{"frames", "N"}, {"scene", "NAME"}});
  return params;
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params p(bench_params());
  if (const int rc = hg::runtime::parse_tool(p, argc, argv, "hg-bench-camera", hg::runtime::usage_with(kUsageHead));
      rc >= 0)
    return rc;
  if (!p.positional().empty()) {
    std::fprintf(stderr, "hg-bench-camera: command line: unexpected argument '%s' (see --help)\n",
                 p.positional()[0].c_str());
    return hg::runtime::kExitBadInput;
  }
  const int frames = int(p.integer("frames"));
  const std::string scene = p.text("scene");
  const bool all_parts = p.flag("all-parts");
  cv::setNumThreads(1);  // one thread, as the target says
  SceneSpec spec;
  try {
    spec = scene_preset(scene);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-bench-camera: command line: --scene: %s\n", e.what());
    return hg::runtime::kExitBadInput;
  }
  SegmentParams params;
  params.all_parts = all_parts;
  std::printf("scene %s, %s, %d frames per profile, OpenCV threads %d\n", scene.c_str(),
              all_parts ? "all parts" : "largest part", frames, cv::getNumThreads());
  for (const std::string& name : camera_profile_names()) {
    const CameraProfile prof = camera_profile(name);
    std::vector<RenderedFrame> rendered;
    for (int k = 0; k < std::min(frames, 5); ++k) rendered.push_back(render(spec, prof, k));
    std::vector<double> ms, cpu_ms;
    auto cpu_now = [] {
      timespec ts;
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
      return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
    };
    std::vector<std::uint8_t> buf;
    std::size_t points = 0;
    for (int i = 0; i < frames; ++i) {
      const RenderedFrame& f = rendered[i % rendered.size()];
      const double c0 = cpu_now();
      const auto t0 = std::chrono::steady_clock::now();
      const Segmentation s = segment(f.depth, f.intrinsics, params);
      hullgrind::plate_cloud_t msg{};
      msg.header.frame_id = "camera";
      fill_plate_cloud(s, msg);
      buf.resize(msg.getEncodedSize());
      msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
      const auto t1 = std::chrono::steady_clock::now();
      ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      cpu_ms.push_back(cpu_now() - c0);
      points = s.size();
    }
    std::sort(ms.begin(), ms.end());
    std::sort(cpu_ms.begin(), cpu_ms.end());
    // Wall time suffers when other processes share the cores; thread CPU time shows the work itself.
    std::printf(
        "%-6s %4dx%-4d  wall median %7.2f ms (min %7.2f, max %7.2f)  thread CPU median %7.2f ms"
        "  (%zu points, %zu bytes)\n",
        name.c_str(), prof.width, prof.height, ms[ms.size() / 2], ms.front(), ms.back(), cpu_ms[cpu_ms.size() / 2],
        points, buf.size());
  }
  return 0;
}
