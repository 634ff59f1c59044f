// Where a part lies: area centroid, principal axis and extents of a polygon with holes (paper §4.3:
// the carrying robot picks the part at its centre of mass).
#pragma once

#include <vector>

#include "outline_core/outline.hpp"

namespace hg::outline_service {

struct PartPose {
  outline::Vec2 centroid;
  double area = 0;                  // the steel's: holes subtracted, the pixels the loops run through counted
  double principal_axis_angle = 0;  // major axis from the x axis, radians, in (-pi/2, pi/2]
  outline::Vec2 bbox_min, bbox_max;
  double major_extent = 0, minor_extent = 0;
  std::size_t outer_loop = 0;      // index of the outer loop in the input
  std::vector<std::size_t> holes;  // indices of its holes
};

// One pose per part (outer loop with the holes inside it), largest area first. The loops run through the
// outermost points of the steel: on a lattice of spacing h along the plane's u, v axes (a camera looking
// down; the planner assumes the same, path_planner/smooth.cpp), the centres of the last steel pixels, so
// that the loops' own area is short of the pixels' by an inset that depends on the part's angle to the
// lattice. The area is the pixels' the loops enclose, by Pick's theorem: A + h^2 (B / 2 + 1 - holes), B the
// lattice points on the loops (per edge gcd(|du|, |dv|) in steps of h, at least one): a chord the alpha
// shape draws across a staircase's notch holds one lattice point and has the notch's pixel inside it. The
// centroid, axis and extents are the loops'. spacing 0: the loops' area.
std::vector<PartPose> part_poses(const std::vector<outline::Loop>& loops, double spacing);

}  // namespace hg::outline_service
