// Where a part lies: area centroid, principal axis and extents of a polygon with holes (paper §4.3:
// the carrying robot picks the part at its centre of mass).
#pragma once

#include <vector>

#include "outline_core/outline.hpp"

namespace hg::outline_service {

struct PartPose {
  outline::Vec2 centroid;
  double area = 0;                  // holes subtracted
  double principal_axis_angle = 0;  // major axis from the x axis, radians, in (-pi/2, pi/2]
  outline::Vec2 bbox_min, bbox_max;
  double major_extent = 0, minor_extent = 0;
  std::size_t outer_loop = 0;      // index of the outer loop in the input
  std::vector<std::size_t> holes;  // indices of its holes
};

// One pose per part (outer loop with the holes inside it), largest area first.
std::vector<PartPose> part_poses(const std::vector<outline::Loop>& loops);

}  // namespace hg::outline_service
