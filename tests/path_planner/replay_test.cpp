// `make run`'s scene (plate-hole-slot through the pm806 profile, the largest part) rendered, segmented and
// outlined by the camera bridge's and the outline service's own code, then planned; and the committed camera log
// (tests/data/camera_bridge_three_parts.lcmlog: pm806 profile, 1.35 mm pixels at 1.5 m, three parts) through the
// outline service's computation and the planner, configured as `make run` configures them (config/path_planner.yaml,
// camera 1.5 m above the base origin's plate spot). Independent expectation: the robot bridge's own path check
// (robot_bridge/path.cpp, linked), with the limits of config/robot_bridge.yaml, on the grind_path_t the bridge would
// decode.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <sstream>

#include <lcm/lcm-cpp.hpp>

#include "camera_bridge/camera_bridge.hpp"
#include "sim/scene/scene.hpp"
#include "camera_bridge/segment.hpp"
#include "hullgrind/plate_cloud_t.hpp"
#include "sim/partgen/shapes.hpp"
#include "outline_service/outline_service.hpp"
#include "path_planner/io.hpp"
#include "robot_bridge/path.hpp"
#include "robot_bridge/robot_bridge.hpp"
#include "runtime/config.hpp"
#include "tests/common/cell_file.hpp"
#include "tests/path_planner/service_defaults.hpp"
#include "tests/path_planner/truth.hpp"

using namespace hg::path_planner;
namespace rb = hg::robot_bridge;

namespace {

// config/path_planner.yaml with command-line style overrides and a cell file (default: the simulated cell of
// `make run`, config/cell-sim.yaml: camera 1.5 m up), the way hg-plan reads them.
PlannerConfig planner_config(std::map<std::string, std::string> overrides,
                             const std::string& cell = hg::test::sim_cell()) {
  overrides.emplace("cell", cell);
  return config_from(
      lookup_from(overrides, hg::runtime::Config::load(std::string(HG_SOURCE_DIR) + "/config/path_planner.yaml")));
}

// The robot bridge's limits as it takes them: config/robot_bridge.yaml and the same cell file.
rb::Limits bridge_limits(const std::string& cell = hg::test::sim_cell()) {
  hg::runtime::Params params(rb::process_info().params);
  params.use_config(hg::runtime::Config::load(std::string(HG_SOURCE_DIR) + "/config/robot_bridge.yaml"));
  params.set("cell", cell);
  return rb::limits_from(params);
}

// The simulated cell with the camera `height` above the table origin, looking down.
std::string cell_with_camera_at(double height) {
  return hg::test::write_test_cell(
      testing::TempDir() + "/pp_replay_cell_" + std::to_string(height) + ".yaml", [&](hg::cell::Cell& c) {
        c.calibration.camera_to_base = pose_from_xyz_rpy(Vec3(0.5, 0, height), Vec3(M_PI, 0, 0));
      });
}

using hg::path_planner::test::service_options;

std::vector<hullgrind::plate_cloud_t> clouds() {
  lcm::LogFile log(std::string(HG_TEST_DATA) + "/camera_bridge_three_parts.lcmlog", "r");
  std::vector<hullgrind::plate_cloud_t> out;
  while (const lcm::LogEvent* ev = log.readNextEvent()) {
    hullgrind::plate_cloud_t m;
    if (ev->channel == "HG_PLATE_CLOUD" && m.decode(ev->data, 0, ev->datalen) == ev->datalen)
      out.push_back(std::move(m));
  }
  return out;
}

}  // namespace

TEST(PathPlannerReplay, EveryPlannedPathPassesTheRobotBridgesCheck) {
  const std::vector<hullgrind::plate_cloud_t> cs = clouds();
  ASSERT_EQ(cs.size(), 2u);
  const rb::Limits limits = bridge_limits();
  const PlannerConfig cfg = planner_config({{"small-hole", "skip"}});  // the scene has tiny holes
  ASSERT_EQ(cfg.limits.max_accel, limits.max_accel) << "the planner's max_accel must equal the bridge's";
  EXPECT_LE(cfg.limits.max_speed, limits.max_speed) << "the planner's max_speed above the bridge's";
  // Without the corner step (max_accel out of reach) for comparison: the failure `make run` showed.
  PlannerConfig unlimited = cfg;
  unlimited.limits.max_accel = 1e12;
  int refused_unlimited = 0, planned = 0;
  for (const auto& cloud : cs) {
    const hullgrind::outline_t outline = hg::outline_service::compute(cloud, service_options()).outline;
    ASSERT_EQ(outline.status, +hullgrind::outline_t::STATUS_OK) << outline.error_text;
    const OutlineInput in = from_lcm(outline);
    // Robot at home (as before its first status) and at a corner of the workspace.
    for (const std::optional<Vec3>& robot : {std::optional<Vec3>(), std::optional<Vec3>(Vec3(0.9, -0.8, 0.4))})
      for (double tool : {0.003, 0.01}) {
        JobParams jp;
        jp.tool_radius = tool;
        const rb::Pose start{robot ? *robot : cfg.home, Eigen::Quaterniond::Identity()};
        const PlanResult before = plan(in, jp, unlimited, robot);
        ASSERT_TRUE(before.ok) << before.reason;
        const std::string why =
            rb::check_path(rb::from_lcm(to_lcm(before, "replay", 0, "robot_base", 0)), start, limits);
        refused_unlimited += !why.empty();

        const PlanResult r = plan(in, jp, cfg, robot);
        ASSERT_TRUE(r.ok) << r.reason;
        ++planned;
        EXPECT_EQ(rb::check_path(rb::from_lcm(to_lcm(r, "replay", 0, "robot_base", 0)), start, limits), "")
            << "cloud " << cloud.header.seq << " tool " << tool;
        double slowest = 1e9, t = 0, t_nominal = 0;
        for (std::size_t i = 1; i < r.path.size(); ++i)
          if (r.path[i].kind == kGrind) {
            const double len = (r.path[i].position - r.path[i - 1].position).norm();
            slowest = std::min(slowest, r.path[i].speed);
            t += len / r.path[i].speed;
            t_nominal += len / r.params.grind_speed;
          }
        std::printf(
            "  cloud %lld, tool %2.0f mm, robot %s: %zu waypoints, %d speeds lowered, slowest %.4f m/s, "
            "grind %.1f s (%.1f s at constant speed); without the step: %s\n",
            (long long)cloud.header.seq, tool * 1e3, robot ? "away" : "home", r.path.size(), r.slowed, slowest, t,
            t_nominal, why.empty() ? "accepted" : why.c_str());
      }
  }
  EXPECT_EQ(planned, 8);
  std::printf("  without the corner step the bridge refused %d of %d paths\n", refused_unlimited, planned);
}

// What `make run` does up to the robot: hg-virtual://plate-hole-slot?profile=pm806 frames (noise differs
// per frame index), the camera bridge's segmentation (largest part), the outline service, the planner with
// the run's config; the robot starts at its sim-home, which is the planner's home.
TEST(PathPlannerReplay, MakeRunSceneFramesPassTheRobotBridgesCheck) {
  namespace cb = hg::camera_bridge;
  namespace sim = hg::sim;
  const rb::Limits limits = bridge_limits();
  // small_hole skip: some frames' noise opens a spurious pin hole in the outline (reported as a warning).
  const PlannerConfig cfg = planner_config({{"small-hole", "skip"}});
  PlannerConfig unlimited = cfg;
  unlimited.limits.max_accel = 1e12;
  const sim::SceneSpec spec = sim::scene_preset("plate-hole-slot");
  const sim::CameraProfile profile = sim::camera_profile("pm806");
  int refused_unlimited = 0, frames = 0, lowered = 0;
  double slowest = 1e9;
  for (std::uint64_t k = 0; k < 20; ++k) {
    const sim::RenderedFrame f = sim::render(spec, profile, k);
    const cb::Segmentation seg = cb::segment(f.depth, f.intrinsics, cb::SegmentParams{});
    ASSERT_EQ(seg.status, cb::SegmentStatus::Ok) << seg.text;
    hullgrind::plate_cloud_t cloud;
    cb::fill_plate_cloud(seg, cloud);
    const hullgrind::outline_t outline = hg::outline_service::compute(cloud, service_options()).outline;
    ASSERT_EQ(outline.status, +hullgrind::outline_t::STATUS_OK) << outline.error_text;
    const OutlineInput in = from_lcm(outline);
    const rb::Pose start{cfg.home, Eigen::Quaterniond::Identity()};
    // Odd frames at a fast feed (0.1 m/s needs corner radii of 5 mm at 2 m/s^2): real corners get slowed.
    JobParams jp;
    jp.grind_speed = k % 2 ? 0.1 : 0;
    const PlanResult before = plan(in, jp, unlimited, std::nullopt);
    ASSERT_TRUE(before.ok) << before.reason;
    const std::string why = rb::check_path(rb::from_lcm(to_lcm(before, "run", 0, "robot_base", 0)), start, limits);
    refused_unlimited += !why.empty();
    const PlanResult r = plan(in, jp, cfg, std::nullopt);
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_EQ(rb::check_path(rb::from_lcm(to_lcm(r, "run", 0, "robot_base", 0)), start, limits), "") << "frame " << k;
    ++frames;
    lowered += r.slowed;
    for (const Waypoint& w : r.path) slowest = std::min(slowest, w.speed);
    std::printf("  frame %2llu, grind %.2f m/s: %zu waypoints, %3d speeds lowered; without the step: %s\n",
                (unsigned long long)k, r.params.grind_speed, r.path.size(), r.slowed,
                why.empty() ? "accepted" : why.c_str());
  }
  std::printf(
      "  without the corner step the bridge refused %d of %d frames' paths; with it none, %d speeds lowered, "
      "slowest %.4f m/s\n",
      refused_unlimited, frames, lowered, slowest);
  // Some fast frames have corners the step must slow, so the check has teeth. (How many varies with the
  // noise kinks the smoothing leaves; 8 of the 10 before line/arc junctions were joined, 4 after.)
  EXPECT_GE(refused_unlimited, 1);
  EXPECT_GT(lowered, 0);
}

namespace {

// Frames of a rendered scene through the camera bridge's segmentation, the outline service's computation
// and the planner, against the scene's ground truth: every grind waypoint away from the true corners
// (vertices turning >= 20 deg, a tool radius + 10 mm around them) lies the tool radius from the true edge of
// the ring it grinds. Returns the worst error per ring over the frames; checks that every ring was ground.
std::vector<double> ground_truth_errors(const std::string& scene, const std::string& camera, int frames) {
  namespace cb = hg::camera_bridge;
  namespace sim = hg::sim;
  const sim::SceneSpec spec = sim::scene_preset(scene);
  const sim::CameraProfile profile = sim::camera_profile(camera);
  std::vector<double> worst_all;
  for (int k = 0; k < frames; ++k) {
    const sim::RenderedFrame f = sim::render(spec, profile, std::uint64_t(k));
    EXPECT_EQ(f.part_polygons.size(), 1u) << scene;
    // The pixel pitch on the plate, as config/pipeline.toml gives it to the planner: plate top distance / fx.
    const double pitch = (std::abs(f.table_offset) - f.part_thickness[0]) / f.intrinsics.fx;
    // The camera above the table origin, looking down (config/pipeline.toml's hand-eye for the pm806).
    const PlannerConfig cfg = planner_config({{"small-hole", "skip"}, {"pixel-pitch", std::to_string(pitch)}},
                                             cell_with_camera_at(profile.mount_height));
    const cb::Segmentation seg = cb::segment(f.depth, f.intrinsics, cb::SegmentParams{});
    EXPECT_EQ(seg.status, cb::SegmentStatus::Ok) << seg.text;
    if (seg.status != cb::SegmentStatus::Ok) return {};
    hullgrind::plate_cloud_t cloud;
    cb::fill_plate_cloud(seg, cloud);
    const hullgrind::outline_t outline = hg::outline_service::compute(cloud, service_options()).outline;
    EXPECT_EQ(outline.status, +hullgrind::outline_t::STATUS_OK) << outline.error_text;
    const PlanResult r = plan(from_lcm(outline), JobParams{}, cfg, std::nullopt);
    EXPECT_TRUE(r.ok) << r.reason;
    if (!r.ok) return {};
    const double tool = r.params.tool_radius;

    const auto& poly = f.part_polygons[0];
    std::vector<Ring> rings{poly.outer};
    rings.insert(rings.end(), poly.holes.begin(), poly.holes.end());
    const std::vector<Vec2> corners = hg::path_planner::test::corners_of(rings, 20 * M_PI / 180);
    const Eigen::Isometry3d base_to_table = (cfg.camera_to_base * f.camera_from_table).inverse();
    std::vector<double> worst(rings.size(), 0);
    std::vector<int> checked(rings.size(), 0);
    for (const Waypoint& w : r.path) {
      if (w.kind != kGrind) continue;
      const Vec3 q3 = base_to_table * w.position;
      const Vec2 q(q3.x(), q3.y());
      bool near_corner = false;
      for (const Vec2& c : corners) near_corner |= (q - c).norm() < tool + 0.010;
      if (near_corner) continue;
      std::size_t ring = 0;
      double d = 1e300;
      for (std::size_t j = 0; j < rings.size(); ++j)
        if (const double dj = hg::path_planner::test::ring_distance(q, rings[j]); dj < d) d = dj, ring = j;
      worst[ring] = std::max(worst[ring], std::abs(d - tool));
      ++checked[ring];
    }
    std::printf("  %s@%s frame %2d: worst offset error outer %.2f mm", scene.c_str(), camera.c_str(), k,
                1e3 * worst[0]);
    for (std::size_t j = 1; j < rings.size(); ++j) std::printf(", hole %zu %.2f mm", j, 1e3 * worst[j]);
    std::printf("\n");
    worst_all.resize(rings.size(), 0);
    for (std::size_t j = 0; j < rings.size(); ++j) {
      // A 30 mm hole ground with the 10 mm tool leaves a short loop; every ring still gets waypoints.
      EXPECT_GE(checked[j], 10) << scene << "@" << camera << " frame " << k << " ring " << j
                                << " has (almost) no grind waypoints";
      worst_all[j] = std::max(worst_all[j], worst[j]);
    }
  }
  return worst_all;
}

}  // namespace

// `make run`'s scene, 20 frames: within issue 5's 1.0 mm for noisy parts on every ring of every frame (the
// whole-pipeline e2e test checks one frame). The slot (straights running tangentially into 20 mm end arcs)
// was the hard ring: line/arc segmentation dented it by up to 2.8 mm, and where the camera bridge's opening
// ate edge pixels beside dropouts and mixed pixels the raw outline ran 1-2 mm into the material for a
// stretch (up to 1.6 mm over 80 frames).
TEST(PathPlannerReplay, MakeRunSceneFramesMatchTheGroundTruth) {
  const std::vector<double> worst = ground_truth_errors("plate-hole-slot", "pm806", 20);
  ASSERT_EQ(worst.size(), 3u) << "outer edge, round hole, slot";
  for (std::size_t j = 0; j < worst.size(); ++j) EXPECT_LE(worst[j], 0.001) << "ring " << j;
}

// Every other catalogue part, alone on the table, through both camera profiles: the same 1.0 mm. The
// l-bracket's R15 inner fillet was cut to a corner on pm806 frames (1.1-1.4 mm here, 0.41 R at the fillet's
// middle) until the planner fitted fillets between straights.
TEST(PathPlannerReplay, CatalogueScenesMatchTheGroundTruthAtBothCameras) {
  for (const std::string& scene : hg::partgen::shape_names()) {
    if (scene == "plate-hole-slot") continue;  // the test above
    for (const std::string camera : {"pm806", "lsr-l"}) {
      const std::vector<double> worst = ground_truth_errors(scene, camera, 3);
      ASSERT_FALSE(worst.empty()) << scene << "@" << camera;
      for (std::size_t j = 0; j < worst.size(); ++j)
        EXPECT_LE(worst[j], 0.001) << scene << "@" << camera << " ring " << j;
    }
  }
}
