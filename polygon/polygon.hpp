// 2-D polygon geometry, in one place: signed area, length, area moments and the principal axis of rings
// (open: the closing edge is implicit). Used by the outline service's part pose, the planner (orientation,
// the flip's mirror axis) and the part generator. Eigen only.
#pragma once

#include <Eigen/Core>

#include <span>

namespace hg::polygon {

using Vec2 = Eigen::Vector2d;

// Shoelace about the first vertex (keeps precision for rings far from the origin): > 0 counter-clockwise.
double signed_area(std::span<const Vec2> ring);
// Perimeter, closing edge included.
double ring_length(std::span<const Vec2> ring);

// Area, centroid and central second moments of a region bounded by rings (Green's theorem: counter-clockwise
// rings add, clockwise rings subtract, so an outer loop plus its clockwise holes is the part minus its holes).
struct AreaMoments {
  double area = 0;
  Vec2 centroid = Vec2::Zero();
  double ixx = 0, iyy = 0, ixy = 0;  // about the centroid
  // Direction of the largest spread (the part's long axis), from the x axis, in (-pi/2, pi/2]; 0 when the
  // second moments do not prefer a direction.
  double principal_axis_angle() const;
  Vec2 principal_axis() const;  // unit vector at principal_axis_angle()
};

// Sums the moments of rings about a reference point near them (keeps the sums well conditioned).
class MomentSum {
 public:
  explicit MomentSum(const Vec2& reference) : ref_(reference) {}
  void add(std::span<const Vec2> ring);
  // The region's moments; area 0 (and the centroid at the reference) when the rings enclose nothing.
  AreaMoments moments() const;

 private:
  Vec2 ref_;
  double a_ = 0, sx_ = 0, sy_ = 0, sxx_ = 0, syy_ = 0, sxy_ = 0;  // raw sums: 2 A, 6 A x̄, ..., 24 Sxy
};

}  // namespace hg::polygon
