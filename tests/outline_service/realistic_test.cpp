// Issue 23 §2 and §4 on the renderer's realistic presets (every sensor effect on, realistic_scan.hpp): for
// every catalogue part at the pm806 and lsr-l profiles, and four at the 0.4 mm m130 profile (a subset: its
// 5 MP frames take the longest; the three with straights and arcs whose flat staircase runs split the
// smoothing before, and knee-scallop), six poses (three face up, three flipped, place and angle at random
// from a seed of the case), through the camera bridge's segmentation (with the frame's intensity image) and
// the outline service's computation, planned as `make run` plans. Expectations from the renderer's polygons
// only: one outer loop, every true cut-out found and no other hole, every cut-out's area from every pose
// within 3 % of its mean, the part's area as the service reports it (its part pose) within 1 % of the true
// area on every scan and within 0.5 % over the poses ((max - min) / mean), the grind edge (the planner's smoothed edge)
// within 0.3 mm RMS and 1.0 mm of the true edge, every loop planned by `make run`'s planner (the shipped simulated
// cell, 10 mm tool, small-hole fail) and no scan POOR with the shipped limits. outline_service_realistic_table prints
// the same figures (docs/BENCHMARKS-outline.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
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
    for (const auto& p : {"pm806", "lsr-l"}) out.push_back({s, p});
  for (const char* s : {"plate-hole-slot", "knee-scallop", "ring-flange", "trapezoid-holes"})
    out.push_back({s, "m130"});
  return out;
}

std::uint64_t seed_of(const std::string& text) {  // FNV-1a: a fixed seed per case, the same on every run
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char ch : text) h = (h ^ ch) * 1099511628211ull;
  return h % 100000 + 1;
}

class Realistic : public testing::TestWithParam<Case> {};

std::string what(const Case& c, const std::vector<Pose>& poses, std::size_t i) {
  return c.shape + "@" + c.profile + " pose " + std::to_string(i) + (poses[i].flipped ? " flipped" : "");
}

// The case's six poses scanned; with `planner`, each outline planned and checked too.
std::vector<Accuracy> scans_of(const Case& c, const hg::path_planner::PlannerConfig* planner) {
  const std::vector<Pose> poses = six_poses(seed_of(c.shape + "/realistic"));
  const Eigen::Isometry3d table_to_base = planner ? base_from_table(*planner) : Eigen::Isometry3d::Identity();
  std::vector<Accuracy> got;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const hg::sim::RenderedFrame f = realistic_frame(c.shape, c.profile, poses[i], seed_of(c.shape + c.profile) + i);
    const Scan s = scan(f, hg::camera_bridge::SegmentParams{}, shipped_rules(), f.intensity);
    got.push_back(measure(s, f));
    EXPECT_TRUE(got.back().ok) << what(c, poses, i) << ": " << s.outline.error_text;
    if (!planner || !got.back().ok) continue;
    const GrindAccuracy g = grind_edge(s.outline, f, *planner, table_to_base);
    EXPECT_TRUE(g.planned) << what(c, poses, i) << ": " << g.reason;
    EXPECT_EQ(g.loops_planned, got.back().outer + got.back().holes) << what(c, poses, i) << ": every loop ground";
    std::printf("%s: grind edge RMS %.2f mm, max %.2f mm at table (%.1f, %.1f) mm\n", what(c, poses, i).c_str(),
                1e3 * g.rms, 1e3 * g.max, 1e3 * g.worst.x(), 1e3 * g.worst.y());
    EXPECT_LE(g.rms, 0.3e-3) << what(c, poses, i) << ": grind edge RMS to the true edge";
    EXPECT_LE(g.max, 1.0e-3) << what(c, poses, i) << ": grind edge's Hausdorff distance to the true edge";
    EXPECT_NE(got.back().quality, +hullgrind::outline_t::QUALITY_POOR)
        << what(c, poses, i) << ": POOR, edge in dropout " << got.back().edge_dropout << ", largest gap "
        << got.back().largest_gap;
  }
  return got;
}

TEST_P(Realistic, OneOuterLoopTheTrueCutOutsTheAreaAlikeFromEveryPoseTheGrindEdgeOnTheTrueEdge) {
  const Case c = GetParam();
  const hg::path_planner::PlannerConfig planner = make_run_planner();
  const std::vector<Pose> poses = six_poses(seed_of(c.shape + "/realistic"));
  const std::vector<Accuracy> got = scans_of(c, &planner);
  auto spread = [&got](double Accuracy::*area) {  // (max - min) / mean over the poses
    double lo = 1e300, hi = 0, mean = 0;
    for (const Accuracy& a : got) lo = std::min(lo, a.*area), hi = std::max(hi, a.*area), mean += a.*area / got.size();
    return (hi - lo) / mean;
  };
  // The outline runs through the centres of the last steel pixels, an inset that depends on the edge's angle
  // to the pixel grid (up to 0.8 % of these parts' area over the poses, and 0.3-3 % below the true area); the
  // part's area counts the pixels the loops enclose, at any angle. Issue 23 §2: within 0.5 % over the poses.
  std::printf("%s@%s: area spread over the poses: the part's %.2f %%, the outline's %.2f %%\n", c.shape.c_str(),
              c.profile.c_str(), 100 * spread(&Accuracy::part_area), 100 * spread(&Accuracy::area));
  EXPECT_LE(spread(&Accuracy::part_area), 0.005) << c.shape << "@" << c.profile << ": the part's area over the poses";
  for (std::size_t i = 0; i < got.size(); ++i)
    EXPECT_NEAR(got[i].part_area, got[i].truth_area, 0.01 * got[i].truth_area)
        << what(c, poses, i) << ": the part's area";
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].outer, 1) << what(c, poses, i) << ": outer loops";
    EXPECT_EQ(got[i].holes_found, got[i].truth_holes) << what(c, poses, i) << ": true cut-outs found";
    EXPECT_EQ(got[i].holes_extra, 0) << what(c, poses, i) << ": holes where the steel is not cut";
    for (std::size_t k = 0; k < got[i].hole_areas.size(); ++k) {  // each cut-out's area within 3 % of its mean
      double mean = 0;
      for (const Accuracy& a : got) mean += a.hole_areas[k] / double(got.size());
      EXPECT_NEAR(got[i].hole_areas[k], mean, 0.03 * mean) << what(c, poses, i) << " cut-out " << k;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Catalogue, Realistic, testing::ValuesIn(all_cases()));

}  // namespace
