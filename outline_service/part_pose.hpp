// Where a part lies: area centroid, principal axis and extents of a polygon with holes (paper §4.3:
// the carrying robot picks the part at its centre of mass).
#pragma once

#include <vector>

#include "outline_core/outline.hpp"

namespace hg::outline_service {

struct PartPose {
  outline::Vec2 centroid;
  double area = 0;                  // the steel's: holes subtracted, the edge's inset restored (part_poses)
  double principal_axis_angle = 0;  // major axis from the x axis, radians, in (-pi/2, pi/2]
  outline::Vec2 bbox_min, bbox_max;
  double major_extent = 0, minor_extent = 0;
  std::size_t outer_loop = 0;      // index of the outer loop in the input
  std::vector<std::size_t> holes;  // indices of its holes
};

// One pose per part (outer loop with the holes inside it), largest area first. The loops run through the
// outermost points of the steel: on a lattice of spacing h along the plane's u, v axes (a camera looking
// down; the planner assumes the same, path_planner/smooth.cpp), the centres of the last steel pixels, on
// average h/2 x max(|t_u|, |t_v|) inside an edge of direction t, so that the loops' own area depends on
// the part's angle to the lattice. The area adds that inset along every loop of the part, h/2 x the loops'
// length in the max norm (along a staircase the same as along the straight edge it steps round), and is
// the same for every angle; the centroid, axis and extents are the loops'. spacing 0: the loops' area.
std::vector<PartPose> part_poses(const std::vector<outline::Loop>& loops, double spacing);

}  // namespace hg::outline_service
