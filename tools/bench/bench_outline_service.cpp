// hg-bench-outline-service: time from a plate cloud to the outline + part poses the service publishes
// (outline_service::compute, i.e. the outline core plus message filling), one thread, median over N
// clouds, for each camera profile and insertion order. Clouds come from the camera bridge's renderer and
// segmentation (not timed). A benchmark that prints figures, not a test.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "camera_bridge/camera_bridge.hpp"
#include "runtime/params.hpp"
#include "sim/scene/scene.hpp"
#include "camera_bridge/segment.hpp"
#include "outline_service/outline_service.hpp"
#include "runtime/version.hpp"

namespace cb = hg::camera_bridge;
namespace sim = hg::sim;

int main(int argc, char** argv) {
  if (hg::runtime::answer_version(argc, argv, "hg-bench-outline-service")) return 0;
  int runs = 20;
  std::string scene = "plate-hole-slot";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--scene" && i + 1 < argc)
      scene = argv[++i];
    else if (a == "--help" || a == "-h") {
      std::printf(
          "usage: hg-bench-outline-service [--runs N] [--scene NAME]\n"
          "Times plate cloud -> outline_t + part_pose_t (the outline service's work) per camera profile\n"
          "and insertion order: one thread, median of N, clouds from the renderer + segmentation.\n");
      return 0;
    } else {
      std::fprintf(stderr, "hg-bench-outline-service: command line: unknown option %s (see --help)\n", a.c_str());
      return hg::runtime::kExitBadInput;
    }
  }
  auto cpu_now = [] {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
  };
  sim::SceneSpec spec;
  try {
    spec = sim::scene_preset(scene);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-bench-outline-service: command line: --scene: %s\n", e.what());
    return hg::runtime::kExitBadInput;
  }
  std::printf("scene %s, %d runs per row\n", scene.c_str(), runs);
  std::printf("%-6s %-9s %-8s %9s %9s %9s %8s\n", "camera", "image", "order", "points", "wall ms", "cpu ms", "loops");
  for (const std::string& name : sim::camera_profile_names()) {
    const sim::CameraProfile prof = sim::camera_profile(name);
    const sim::RenderedFrame f = sim::render(spec, prof, 0);
    const cb::Segmentation s = cb::segment(f.depth, f.intrinsics, cb::SegmentParams{});
    hullgrind::plate_cloud_t cloud{};
    cloud.header.frame_id = "camera";
    cb::fill_plate_cloud(s, cloud);
    for (const char* order : {"as-is", "hilbert", "brio"}) {
      hg::outline_service::ServiceOptions opt;
      opt.order = hg::outline::parse_order(order);
      std::vector<double> wall, cpu;
      int loops = 0;
      for (int r = 0; r < runs; ++r) {
        const double c0 = cpu_now();
        const auto t0 = std::chrono::steady_clock::now();
        auto c = hg::outline_service::compute(cloud, opt);
        wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        cpu.push_back(cpu_now() - c0);
        loops = c.outline.num_loops;
      }
      std::sort(wall.begin(), wall.end());
      std::sort(cpu.begin(), cpu.end());
      std::printf("%-6s %4dx%-4d %-8s %9d %9.2f %9.2f %8d\n", name.c_str(), prof.width, prof.height, order, cloud.n,
                  wall[wall.size() / 2], cpu[cpu.size() / 2], loops);
    }
  }
  return 0;
}
