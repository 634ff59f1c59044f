// hg-bench-outline-service: time from a plate cloud to the outline + part poses the service publishes
// (outline_service::compute, i.e. the outline core plus message filling), one thread, median over N
// clouds, for each camera profile and insertion order. Clouds come from the camera bridge's renderer and
// segmentation (not timed). A benchmark that prints figures, not a test.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <ctime>
#include <string>
#include <vector>

#include "camera_bridge/camera_bridge.hpp"
#include "outline_io/cloud.hpp"
#include "runtime/params.hpp"
#include "sim/scene/scene.hpp"
#include "camera_bridge/segment.hpp"
#include "outline_service/outline_service.hpp"

namespace cb = hg::camera_bridge;
namespace sim = hg::sim;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// --pcd FILE: the service end to end on a file's cloud (read and projected as hg-outline does, not timed)
// against the outline core alone on the same points with the same options (the service's defaults: all
// cores), interleaved, medians of N. End to end = decoding the plate_cloud_t message bytes, compute()
// (the core plus filling outline_t and part_pose_t) and encoding every published message.
int bench_file(const std::string& path, int runs) {
  const hg::outline_io::PlanarPoints planar = hg::outline_io::to_plane(hg::outline_io::read_cloud_file(path), path);
  hullgrind::plate_cloud_t cloud{};
  cloud.header.frame_id = "camera";
  cloud.status = hullgrind::plate_cloud_t::STATUS_OK;
  cloud.n = static_cast<int32_t>(planar.points.size());
  for (const hg::outline::Vec2& p : planar.points) {
    cloud.u.push_back(static_cast<float>(p.x));
    cloud.v.push_back(static_cast<float>(p.y));
    cloud.part.push_back(0);
  }
  cloud.num_parts = 1;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(cloud.getEncodedSize()));
  cloud.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  const hg::outline_service::ServiceOptions options;         // the service's defaults (threads 0: all cores)
  std::vector<hg::outline::Vec2> pts(planar.points.size());  // the points the service hands the core
  for (std::size_t i = 0; i < pts.size(); ++i) pts[i] = {cloud.u[i], cloud.v[i]};
  std::vector<double> e2e, decode, core_in_service, core, ratio;
  int threads = 0;
  std::size_t out_bytes = 0;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    hullgrind::plate_cloud_t in;
    in.decode(bytes.data(), 0, static_cast<int>(bytes.size()));
    const auto t1 = std::chrono::steady_clock::now();
    hg::outline_service::Computed c = hg::outline_service::compute(in, options);
    std::vector<std::uint8_t> out(static_cast<std::size_t>(c.outline.getEncodedSize()));
    c.outline.encode(out.data(), 0, static_cast<int>(out.size()));
    out_bytes = out.size();
    for (auto& pose : c.poses) {
      std::vector<std::uint8_t> pb(static_cast<std::size_t>(pose.getEncodedSize()));
      pose.encode(pb.data(), 0, static_cast<int>(pb.size()));
    }
    const auto t2 = std::chrono::steady_clock::now();
    const hg::outline::Result res = hg::outline::compute_outline(pts, options);
    const auto t3 = std::chrono::steady_clock::now();
    auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    e2e.push_back(ms(t0, t2));
    decode.push_back(ms(t0, t1));
    core_in_service.push_back(c.outline.compute_time * 1e3);
    core.push_back(ms(t2, t3));
    ratio.push_back(ms(t0, t2) / ms(t2, t3));
    threads = res.threads_used;
  }
  std::printf("cloud %s: %d points, %d runs, core on %d threads (the service's default options)\n", path.c_str(),
              cloud.n, runs, threads);
  std::printf(
      "end to end (decode + compute + encode, %zu-byte outline_t) median %.1f ms; of it decode %.1f ms, the "
      "core inside compute() %.1f ms\n",
      out_bytes, median(e2e), median(decode), median(core_in_service));
  std::printf("the core alone (compute_outline, same points and options) median %.1f ms\n", median(core));
  std::printf("end to end / core: median of the per-run ratios %.3f, ratio of the medians %.3f\n", median(ratio),
              median(e2e) / median(core));
  return 0;
}

constexpr const char* kUsageHead =
    "usage: hg-bench-outline-service [options]\n"
    "Times plate cloud -> outline_t + part_pose_t (the outline service's work) per camera profile\n"
    "and insertion order: one thread, median of N, clouds from the renderer + segmentation.\n"
    "--pcd FILE: instead, the service end to end on that cloud (message bytes in, encoded messages out,\n"
    "the service's default options) against the outline core alone on the same points, interleaved.\n";

std::vector<hg::runtime::Param> bench_params() {
  using namespace hg::runtime;
  std::vector<Param> params = {integer_param("runs", "20", "runs per row (median)", 1, 1e6),
                               text_param("scene", "plate-hole-slot", "scene preset of the renderer"),
                               text_param("pcd", "", "time the service end to end on this cloud file instead")};
  set_value_names(params, {{"runs", "N"}, {"scene", "NAME"}, {"pcd", "FILE"}});
  return params;
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params p(bench_params());
  if (const int rc =
          hg::runtime::parse_tool(p, argc, argv, "hg-bench-outline-service", hg::runtime::usage_with(kUsageHead));
      rc >= 0)
    return rc;
  if (!p.positional().empty()) {
    std::fprintf(stderr, "hg-bench-outline-service: command line: unexpected argument '%s' (see --help)\n",
                 p.positional()[0].c_str());
    return hg::runtime::kExitBadInput;
  }
  const int runs = int(p.integer("runs"));
  const std::string scene = p.text("scene"), pcd = p.text("pcd");
  if (!pcd.empty()) {
    try {
      return bench_file(pcd, runs);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hg-bench-outline-service: %s\n", e.what());
      return hg::runtime::kExitBadInput;  // the file could not be read as a cloud
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
