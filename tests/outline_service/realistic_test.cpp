// Issue 23 §2 and §4 on the renderer's realistic presets (every sensor effect on, realistic_scan.hpp): for
// every catalogue part and both camera profiles, six poses (three face up, three flipped, place and angle
// at random from a seed of the case), through the camera bridge's segmentation (with the frame's intensity
// image) and the outline service's computation, planned as `make run` plans. Expectations from the
// renderer's polygons only: one outer loop, every true cut-out found and no other hole, the same outline
// from every pose (plate area within 0.5 % and every cut-out's area within 3 % of their means), and the
// smoothed edge the tool grinds within 0.3 mm RMS and 1.0 mm of the true edge with every loop planned.
#include <gtest/gtest.h>

#include <numeric>

#include "realistic_grind.hpp"

using namespace hg::test;

namespace {

struct Case {
  std::string shape, profile;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.shape << "@" << c.profile; }

std::vector<Case> all_cases() {
  std::vector<Case> out;
  for (const auto& s : hg::partgen::shape_names())
    for (const auto& p : hg::sim::camera_profile_names()) out.push_back({s, p});
  return out;
}

std::uint64_t seed_of(const std::string& text) {  // FNV-1a: a fixed seed per case, the same on every run
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char ch : text) h = (h ^ ch) * 1099511628211ull;
  return h % 100000 + 1;
}

class Realistic : public testing::TestWithParam<Case> {};

TEST_P(Realistic, OneOutlinePerPartTheTrueCutOutsTheSameFromEveryPoseAndAGrindEdgeOnTheTrueEdge) {
  const Case c = GetParam();
  const hg::path_planner::PlannerConfig planner = make_run_planner();
  const Eigen::Isometry3d table_to_base = base_from_table(planner);
  const std::vector<Pose> poses = six_poses(seed_of(c.shape + "/realistic"));
  std::vector<Accuracy> got;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::string what =
        c.shape + "@" + c.profile + " pose " + std::to_string(i) + (poses[i].flipped ? " flipped" : "");
    const hg::sim::RenderedFrame f = realistic_frame(c.shape, c.profile, poses[i], seed_of(c.shape + c.profile) + i);
    const Scan s = scan(f, hg::camera_bridge::SegmentParams{}, shipped_rules(), f.intensity);
    const Accuracy a = measure(s, f);
    ASSERT_TRUE(a.ok) << what << ": " << s.outline.error_text;
    EXPECT_EQ(a.outer, 1) << what << ": outer loops";
    EXPECT_EQ(a.holes_found, a.truth_holes) << what << ": true cut-outs found";
    EXPECT_EQ(a.holes_extra, 0) << what << ": holes where the steel is not cut";
    const GrindAccuracy g = grind_edge(s.outline, f, planner, table_to_base);
    EXPECT_TRUE(g.planned) << what << ": " << g.reason;
    EXPECT_EQ(g.loops_planned, a.outer + a.holes) << what << ": every loop ground";
    EXPECT_LE(g.rms, 0.3e-3) << what << ": grind edge RMS " << g.rms * 1e3 << " mm";
    EXPECT_LE(g.max, 1.0e-3) << what << ": grind edge max " << g.max * 1e3 << " mm";
    got.push_back(a);
  }
  // Repeatable: each pose's plate area and true cut-outs' areas against their means over the poses.
  double mean_area = 0;
  for (const Accuracy& a : got) mean_area += a.area / double(got.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_NEAR(got[i].area, mean_area, 0.005 * mean_area) << c.shape << "@" << c.profile << " pose " << i;
    for (std::size_t k = 0; k < got[i].hole_areas.size(); ++k) {
      double mean = 0;
      for (const Accuracy& a : got) mean += a.hole_areas[k] / double(got.size());
      EXPECT_NEAR(got[i].hole_areas[k], mean, 0.03 * mean)
          << c.shape << "@" << c.profile << " pose " << i << " cut-out " << k;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Catalogue, Realistic, testing::ValuesIn(all_cases()));

}  // namespace
