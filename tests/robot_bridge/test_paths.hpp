// Paths and message helpers shared by the robot bridge tests.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/job_request_t.hpp"

namespace rbtest {

struct Wp {
  double x, y, z, speed;
  int kind;
  double qw = 0, qx = 1, qy = 0, qz = 0;  // tool pointing down
};

inline hullgrind::grind_path_t make_path(const std::string& job, const std::vector<Wp>& wps) {
  hullgrind::grind_path_t p{};
  p.header.frame_id = "robot_base";
  p.job_id = job;
  p.frame = "robot_base";
  p.n = int(wps.size());
  for (const Wp& w : wps) {
    p.position.push_back({w.x, w.y, w.z});
    const double n = std::sqrt(w.qw * w.qw + w.qx * w.qx + w.qy * w.qy + w.qz * w.qz);
    p.orientation.push_back({w.qw / n, w.qx / n, w.qy / n, w.qz / n});
    p.speed.push_back(w.speed);
    p.kind.push_back(std::int8_t(w.kind));
    p.loop_index.push_back(std::int16_t(w.kind == 2 ? 0 : -1));
  }
  return p;
}

// Down from the sim's home (0.5, 0, 0.3), along x while grinding, back up: three long straight segments.
inline hullgrind::grind_path_t three_segment_path(const std::string& job) {
  return make_path(job, {{0.5, 0.0, 0.1, 0.05, 0}, {0.8, 0.0, 0.1, 0.02, 2}, {0.8, 0.0, 0.3, 0.1, 4}});
}

// A small square loop with tilted tool orientations (exercises the rotation vectors of the UR script).
inline hullgrind::grind_path_t square_path(const std::string& job) {
  const double c = std::cos(0.3), s = std::sin(0.3);
  return make_path(job, {{0.40, 0.00, 0.15, 0.10, 0},
                         {0.40, 0.00, 0.10, 0.05, 1, 0, c, s, 0},
                         {0.45, 0.00, 0.10, 0.04, 2, 0, c, 0, s},
                         {0.45, 0.05, 0.10, 0.04, 2, 0.2, 0.9, 0.1, 0.3},
                         {0.40, 0.05, 0.10, 0.04, 2, 0, 1, 0, 0},
                         {0.40, 0.00, 0.10, 0.04, 3},
                         {0.40, 0.00, 0.15, 0.10, 4}});
}

inline hullgrind::job_request_t request(const std::string& job, std::int8_t action) {
  hullgrind::job_request_t r{};
  r.header.frame_id = "";
  r.job_id = job;
  r.part_id = "part-" + job;
  r.action = action;
  return r;
}

}  // namespace rbtest
