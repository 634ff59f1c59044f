// Property: `make run`'s part through many noisy frames of the virtual pm806 camera plans with every edge
// reached. The scene and camera are make run's (hg-virtual://plate-hole-slot?profile=pm806: the scene preset's
// own seed, the noise differing per frame index), cut out by the camera bridge's segmentation (largest part),
// outlined by the outline service's computation at its defaults and planned with config/path_planner.yaml and
// the shipped simulated cell (config/cell-sim.yaml: 10 mm tool, `small-hole: fail`), as the pipeline does.
// Two expectations per frame: the planner's own coverage check passes on every loop (a job of that frame would
// not FAIL "edge out of the tool's reach"), and, independently of the planner's smoothed edge, every point of
// the scene's true part outline lies within the tool radius + 2 mm of the grind path (a collapsed or cut
// slot end is 10 mm and more; the slot's estimated edge is off the true one by up to 1.7 mm on a few of these
// frames, more than issue 5's 1.0 mm that the replay test checks on 20 frames: a known gap). Before the smoothing kept
// its pieces at two residual windows, chose the better of line and circle, merged arcs one circle explains and dropped
// corner pairs a window apart, 2 of these 240 frames FAILED at the slot (a 6-vertex chord of its end arc, a noise-made
// concave kink up to 0.7 mm beyond reach). Before a corner between a straight and an arc needed a tangent circle to
// misfit and a run's pieces met within half the shorter piece tangent or not, frames 630 and 635 FAILED there (a
// false corner, a chord between a short straight and its free arc: a notch 0.8-1.2 mm beyond reach).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <vector>

#include "camera_bridge/camera_bridge.hpp"
#include "camera_bridge/segment.hpp"
#include "hullgrind/plate_cloud_t.hpp"
#include "outline_service/outline_service.hpp"
#include "path_planner/io.hpp"
#include "runtime/config.hpp"
#include "sim/scene/scene.hpp"
#include "tests/common/cell_file.hpp"
#include "tests/path_planner/service_defaults.hpp"
#include "tests/path_planner/truth.hpp"

using namespace hg::path_planner;

namespace {

// Frames 0..239 and 600..759 in full, and every 10th frame of 240..599 and 760..999: each frame's noise is
// independent, so more frames find rarer shapes of it (frames 630 and 635 failed while 0..239 passed).
std::vector<int> frames() {
  std::vector<int> out;
  for (int k = 0; k < 1000; ++k)
    if (k < 240 || (k >= 600 && k < 760) || k % 10 == 0) out.push_back(k);
  return out;
}

// config/path_planner.yaml with the simulated cell, as config/pipeline.toml starts the planner.
PlannerConfig make_run_config() {
  std::map<std::string, std::string> overrides{{"cell", hg::test::sim_cell()}};
  return config_from(
      lookup_from(overrides, hg::runtime::Config::load(std::string(HG_SOURCE_DIR) + "/config/path_planner.yaml")));
}

using hg::path_planner::test::service_options;

// The grind path's segments in the table frame (x, y), from the base-frame waypoints.
std::vector<Segment2> grind_in_table(const std::vector<Waypoint>& path, const Eigen::Isometry3d& base_to_table) {
  std::vector<Segment2> out;
  for (std::size_t i = 1; i < path.size(); ++i)
    if (path[i].kind == kGrind && path[i - 1].kind == kGrind) {
      const Vec3 a = base_to_table * path[i - 1].position, b = base_to_table * path[i].position;
      out.push_back({a.head<2>(), b.head<2>()});
    }
  return out;
}

// Farthest point of the true ring (every 0.5 mm) from the grind path.
double farthest_from_path(const Ring& truth, const std::vector<Segment2>& grind) {
  double worst = 0;
  for (const Vec2& p : hg::path_planner::test::densify(truth, 5e-4)) {
    double d = INFINITY;
    for (const Segment2& s : grind) d = std::min(d, hg::path_planner::test::segment_distance(p, s.a, s.b));
    worst = std::max(worst, d);
  }
  return worst;
}

}  // namespace

TEST(PathPlannerNoisyFrames, MakeRunPartPlansWithEveryEdgeReachedOnEveryFrame) {
  namespace cb = hg::camera_bridge;
  namespace sim = hg::sim;
  const PlannerConfig cfg = make_run_config();
  ASSERT_EQ(cfg.small_hole, SmallHolePolicy::Fail) << "make run's planner fails a job with any unreached edge";
  const sim::SceneSpec spec = sim::scene_preset("plate-hole-slot");
  const sim::CameraProfile profile = sim::camera_profile("pm806");
  int failed = 0;
  double worst_truth = 0;
  const std::vector<int> ks = frames();
  for (const int k : ks) {
    const sim::RenderedFrame f = sim::render(spec, profile, std::uint64_t(k));
    const cb::Segmentation seg = cb::segment(f.depth, f.intrinsics, cb::SegmentParams{});
    ASSERT_EQ(seg.status, cb::SegmentStatus::Ok) << "frame " << k << ": " << seg.text;
    hullgrind::plate_cloud_t cloud;
    cb::fill_plate_cloud(seg, cloud);
    const hullgrind::outline_t outline = hg::outline_service::compute(cloud, service_options()).outline;
    ASSERT_EQ(outline.status, +hullgrind::outline_t::STATUS_OK) << "frame " << k << ": " << outline.error_text;
    const PlanResult r = plan(from_lcm(outline), JobParams{}, cfg, std::nullopt);
    failed += !r.ok;
    EXPECT_TRUE(r.ok) << "frame " << k << ": " << r.reason;
    if (!r.ok) continue;
    for (const LoopCoverage& c : r.coverage)
      EXPECT_TRUE(c.unreached.empty()) << "frame " << k << " loop " << c.loop << ": " << c.unreached_length * 1e3
                                       << " mm unreached";
    // The true outline against the path, in the table frame.
    ASSERT_EQ(f.part_polygons.size(), 1u);
    const auto& poly = f.part_polygons[0];
    std::vector<Ring> rings{poly.outer};
    rings.insert(rings.end(), poly.holes.begin(), poly.holes.end());
    const std::vector<Segment2> grind = grind_in_table(r.path, (cfg.camera_to_base * f.camera_from_table).inverse());
    for (std::size_t j = 0; j < rings.size(); ++j) {
      const double beyond = farthest_from_path(rings[j], grind) - r.params.tool_radius;
      worst_truth = std::max(worst_truth, beyond);
      EXPECT_LE(beyond, 2e-3) << "frame " << k << " ring " << j << ": the true edge is " << beyond * 1e3
                              << " mm beyond the tool";
    }
  }
  std::printf("  %d of %d frames failed; the true edge at most %.2f mm beyond the tool\n", failed, int(ks.size()),
              worst_truth * 1e3);
}
