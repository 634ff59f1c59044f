// hg-plan-bench: time plan() (smooth, offset, resample, orient, leads, base frame, validate) on a pixel
// staircase of a 0.6 x 0.4 m plate rotated 0.3 rad with a D100 hole (partgen::pixel_staircase) at a
// pitch that gives about the requested vertex count; and on the same staircase with Gaussian jitter of
// 0.6 pitch on every vertex (a noisy boundary, pixel_pitch configured). Prints median, min, max in ms.
//   hg-plan-bench [VERTICES=10000] [RUNS=21]
#include "sim/partgen/synth.hpp"
#include "path_planner/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "runtime/params.hpp"

using namespace hg::path_planner;

namespace {

std::vector<Loop> plate(double pitch) {
  const Eigen::Rotation2Dd R(0.3);
  Ring outer;
  for (const Vec2& p : {Vec2(-0.3, -0.2), Vec2(0.3, -0.2), Vec2(0.3, 0.2), Vec2(-0.3, 0.2)}) outer.push_back(R * p);
  Ring hole;
  for (int k = 0; k < 400; ++k) {
    const double t = -2 * M_PI * k / 400;
    hole.push_back(Vec2(0.1, 0.02) + 0.05 * Vec2(std::cos(t), std::sin(t)));
  }
  std::vector<Loop> loops{{false, hg::partgen::pixel_staircase(outer, pitch)},
                          {true, hg::partgen::pixel_staircase(hole, pitch)}};
  return loops;
}

std::size_t vertices(const std::vector<Loop>& loops) {
  std::size_t n = 0;
  for (const Loop& l : loops) n += l.points.size();
  return n;
}

void run(const char* label, const std::vector<Loop>& loops, const PlannerConfig& cfg, int runs) {
  OutlineInput in;
  in.plane = {Vec3(0, 0, 1.19), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1)};
  in.loops = loops;
  std::vector<double> ms;
  PlanResult r;
  for (int i = 0; i < runs; ++i) {
    r = plan(in, JobParams{}, cfg, std::nullopt);
    ms.push_back(r.seconds * 1e3);
  }
  std::sort(ms.begin(), ms.end());
  std::printf("%-22s %6zu vertices  median %7.2f ms  min %7.2f  max %7.2f  (%s, %zu waypoints)\n", label,
              vertices(loops), ms[ms.size() / 2], ms.front(), ms.back(), r.ok ? "planned" : r.reason.c_str(),
              r.path.size());
}

constexpr const char* kUsageHead =
    "usage: hg-plan-bench [VERTICES] [RUNS]\n"
    "Times the planner on a generated plate outline of about this many vertices (docs/BENCHMARKS-planner.md).\n";

std::vector<hg::runtime::Param> bench_params() {
  using namespace hg::runtime;
  return {positional(integer_param("vertices", "10000", "about this many outline vertices", 100, 1e8)),
          positional(integer_param("runs", "21", "runs (median, min, max)", 1, 1e6))};
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params p(bench_params());
  if (const int rc = hg::runtime::parse_tool(p, argc, argv, "hg-plan-bench", hg::runtime::usage_with(kUsageHead));
      rc >= 0)
    return rc;
  const long want = long(p.integer("vertices"));
  const int runs = int(p.integer("runs"));
  // vertices ~ perimeter / pitch: find the pitch by a few secant-like steps
  double pitch = 0.0005;
  for (int it = 0; it < 4; ++it) pitch *= double(vertices(plate(pitch))) / double(want);
  const std::vector<Loop> loops = plate(pitch);
  PlannerConfig cfg;
  cfg.camera_to_base = pose_from_xyz_rpy(Vec3(0.5, 0, 1.2), Vec3(M_PI, 0, 0));
  cfg.limits.workspace_min = Vec3(-2, -2, 0);
  cfg.limits.workspace_max = Vec3(2, 2, 2);
  cfg.limits.table_z = 0;
  std::printf("pitch %.4f mm, %d runs\n", pitch * 1e3, runs);
  run("staircase", loops, cfg, runs);
  std::vector<Loop> noisy = loops;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0, 0.6 * pitch);
  for (Loop& l : noisy)
    for (Vec2& p : l.points) p += Vec2(g(rng), g(rng));
  cfg.smooth.pitch = pitch;
  run("staircase + noise", noisy, cfg, runs);
  return 0;
}
