// The plate plane the planner's process tests share: seen from a camera looking straight down at it
// (normal toward the camera), 1.19 m away, u along the camera's x and v against its y.
#pragma once

#include <cstdint>

#include "hullgrind/outline_t.hpp"

namespace hg::path_planner::test {

// An outline of sequence number `seq` in that plane, STATUS_OK, with no loops yet.
inline hullgrind::outline_t outline_in_camera_plane(std::int64_t seq) {
  hullgrind::outline_t o{};
  o.header.seq = seq;
  o.header.frame_id = "camera";
  const double origin[3] = {0, 0, 1.19}, n[3] = {0, 0, -1}, u[3] = {1, 0, 0}, v[3] = {0, -1, 0};
  for (int k = 0; k < 3; ++k)
    o.plane_origin[k] = origin[k], o.plane_normal[k] = n[k], o.plane_u_axis[k] = u[k], o.plane_v_axis[k] = v[k];
  o.status = hullgrind::outline_t::STATUS_OK;
  return o;
}

}  // namespace hg::path_planner::test
