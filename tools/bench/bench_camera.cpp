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
#include "runtime/version.hpp"

using namespace hg::camera_bridge;
using namespace hg::sim;

int main(int argc, char** argv) {
  if (hg::runtime::answer_version(argc, argv, "hg-bench-camera")) return 0;
  int frames = 30;
  std::string scene = "three-parts";
  bool all_parts = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--frames" && i + 1 < argc) frames = std::atoi(argv[++i]);
    else if (a == "--scene" && i + 1 < argc)
      scene = argv[++i];
    else if (a == "--all-parts")
      all_parts = true;
    else if (a == "--help" || a == "-h") {
      std::printf(
          "usage: hg-bench-camera [--frames N] [--scene NAME] [--all-parts]\n"
          "Times depth frame -> encoded plate_cloud_t per camera profile (one thread, median of N).\n");
      return 0;
    } else {
      std::fprintf(stderr, "hg-bench-camera: command line: unknown option %s (see --help)\n", a.c_str());
      return hg::runtime::kExitBadInput;
    }
  }
  if (frames < 1) frames = 1;
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
