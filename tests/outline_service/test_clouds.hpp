// Plate clouds for the outline service tests: a scan-order grid over a rectangle with a rectangular hole.
#pragma once

#include <cmath>

#include "hullgrind/plate_cloud_t.hpp"

namespace hg::test {

// Points at pitch `p` (metres) covering [0, w] x [0, h] minus the open hole (hx0, hx1) x (hy0, hy1),
// in row-major scan order, on the plane z = 1 of the camera frame.
inline hullgrind::plate_cloud_t plate_with_hole(double w, double h, double hx0, double hx1, double hy0, double hy1,
                                                double p) {
  hullgrind::plate_cloud_t c{};
  c.header.frame_id = "camera";
  c.status = hullgrind::plate_cloud_t::STATUS_OK;
  c.plane_origin[2] = 1;
  c.plane_normal[2] = -1;
  c.plane_u_axis[0] = 1;
  c.plane_v_axis[1] = -1;
  c.thickness = 0.01;
  int nx = int(std::lround(w / p)), ny = int(std::lround(h / p));
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      double x = i * p, y = j * p;
      if (x > hx0 && x < hx1 && y > hy0 && y < hy1) continue;
      c.u.push_back(float(x));
      c.v.push_back(float(y));
      c.part.push_back(0);
    }
  c.n = int32_t(c.u.size());
  c.num_parts = 1;
  return c;
}

}  // namespace hg::test
