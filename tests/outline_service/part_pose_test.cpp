// Part poses from outline loops (outline_service/part_pose): area, centroid and principal axis against
// closed forms for rectangles, holes assigned to their part, parts ordered largest first; on a pixel
// lattice, the area of the pixels whatever the part's angle to the lattice.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "outline_service/part_pose.hpp"

namespace os = hg::outline_service;
using hg::outline::Loop;
using hg::outline::Vec2;

namespace {

Loop polygon(std::vector<Vec2> pts, bool hole) {
  Loop l;
  l.hole = hole;
  l.points = std::move(pts);
  return l;
}

std::vector<Vec2> rect(double x0, double y0, double x1, double y1, bool clockwise, double angle = 0) {
  std::vector<Vec2> p = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  if (clockwise) std::reverse(p.begin(), p.end());
  double c = std::cos(angle), s = std::sin(angle);
  for (auto& q : p) q = {c * q.x - s * q.y, s * q.x + c * q.y};
  return p;
}

TEST(OutlineServicePose, RotatedRectangleWithHole) {
  const double a = 0.5;  // rotation of the whole part
  // 0.4 x 0.2 plate, 0.1 x 0.1 hole centred at (0.3, 0.1) in the plate's own frame.
  std::vector<Loop> loops = {polygon(rect(0, 0, 0.4, 0.2, false, a), false),
                             polygon(rect(0.25, 0.05, 0.35, 0.15, true, a), true)};
  loops[0].area = 0.08;
  auto poses = os::part_poses(loops, 0);
  ASSERT_EQ(poses.size(), 1u);
  const auto& p = poses[0];
  EXPECT_NEAR(p.area, 0.08 - 0.01, 1e-12);
  // Centroid in the plate frame: (0.08*(0.2,0.1) - 0.01*(0.3,0.1)) / 0.07, then rotated by a.
  double lx = (0.08 * 0.2 - 0.01 * 0.3) / 0.07, ly = 0.1;
  EXPECT_NEAR(p.centroid.x, std::cos(a) * lx - std::sin(a) * ly, 1e-12);
  EXPECT_NEAR(p.centroid.y, std::sin(a) * lx + std::cos(a) * ly, 1e-12);
  EXPECT_NEAR(p.principal_axis_angle, a, 1e-9);  // the long side
  ASSERT_EQ(p.holes.size(), 1u);
  EXPECT_EQ(p.holes[0], 1u);
}

TEST(OutlineServicePose, TwoPartsLargestFirstHoleAssignedToItsPart) {
  std::vector<Loop> loops = {polygon(rect(0, 0, 0.1, 0.1, false), false), polygon(rect(1, 0, 1.3, 0.2, false), false),
                             polygon(rect(1.1, 0.05, 1.2, 0.15, true), true)};
  loops[0].area = 0.01;
  loops[1].area = 0.06;
  auto poses = os::part_poses(loops, 0);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].outer_loop, 1u);
  EXPECT_NEAR(poses[0].area, 0.05, 1e-12);
  EXPECT_EQ(poses[0].holes, std::vector<std::size_t>{2});
  EXPECT_NEAR(poses[1].area, 0.01, 1e-12);
  EXPECT_TRUE(poses[1].holes.empty());
  EXPECT_NEAR(poses[0].major_extent, 0.3, 1e-12);
  EXPECT_NEAR(poses[0].minor_extent, 0.2, 1e-12);
}

// Loops through the outermost pixel centres of a lattice of pitch h (the outline core's loops): the part's
// area is its pixels' area, counted, whether its edges run along the lattice or at 45 deg to it (there the
// loop's own area is 0.35 pixel short per pixel of edge, along it 0.5).
TEST(OutlineServicePose, OnAPixelLatticeTheAreaIsThePixelsAtAnyAngle) {
  const double h = 0.002;
  const int n = 41, k = 20;  // a square of n x n pixels; a diamond of the pixels with |i| + |j| <= k
  const double side = (n - 1) * h;
  const auto square = os::part_poses({polygon(rect(0, 0, side, side, false), false)}, h);
  const std::vector<Vec2> diamond = {{k * h, 0}, {0, k * h}, {-k * h, 0}, {0, -k * h}};
  const auto turned = os::part_poses({polygon(diamond, false)}, h);
  ASSERT_EQ(square.size(), 1u);
  ASSERT_EQ(turned.size(), 1u);
  EXPECT_NEAR(square[0].area, n * n * h * h, h * h);
  EXPECT_NEAR(turned[0].area, (2 * k * k + 2 * k + 1) * h * h, h * h);  // 1 + 4 (1 + 2 + ... + k) pixels
  // Without the spacing, the loops' own areas: short by half a pixel along the square's edge, by 0.35 of one
  // along the diamond's.
  EXPECT_NEAR(os::part_poses({polygon(rect(0, 0, side, side, false), false)}, 0)[0].area, side * side, 1e-15);
  EXPECT_NEAR(os::part_poses({polygon(diamond, false)}, 0)[0].area, 2 * k * k * h * h, 1e-15);
}

}  // namespace
