// Paths and message helpers shared by the robot bridge tests.
#pragma once

#include <cmath>
#include <utility>
#include <string>
#include <vector>

#include "hullgrind/grind_path_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/loop_coverage_t.hpp"

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

// One loop of loops_path: a 20 mm square ground at z = 0.1 from its corner (x, y), entered by an air move at
// height travel_z and left by a retract to 0.15.
struct LoopSpec {
  double x, y;
  double travel_z = 0.15;
};

// A plan of several loops as the planner sequences them (air move -1, then the loop's approach, grind and
// retract with its loop index), with full coverage of every loop (loop 0 the outer loop, the others holes).
inline hullgrind::grind_path_t loops_path(const std::string& job, const std::vector<LoopSpec>& loops) {
  std::vector<Wp> wps;
  std::vector<int> index;
  auto add = [&](double x, double y, double z, double v, int kind, int loop) {
    wps.push_back({x, y, z, v, kind});
    index.push_back(loop);
  };
  for (std::size_t k = 0; k < loops.size(); ++k) {
    const LoopSpec& l = loops[k];
    const int loop = int(k);
    add(l.x, l.y, l.travel_z, 0.1, k == 0 ? 0 : 5, -1);
    add(l.x, l.y, 0.1, 0.05, 0, loop);
    for (auto [dx, dy] : {std::pair{0.02, 0.0}, {0.02, 0.02}, {0.0, 0.02}, {0.0, 0.0}})
      add(l.x + dx, l.y + dy, 0.1, 0.02, 2, loop);
    add(l.x, l.y, 0.15, 0.05, 4, loop);
  }
  hullgrind::grind_path_t p = make_path(job, wps);
  for (std::size_t i = 0; i < index.size(); ++i) p.loop_index[i] = std::int16_t(index[i]);
  p.revision = 1;
  for (std::size_t k = 0; k < loops.size(); ++k) {
    hullgrind::loop_coverage_t c{};
    c.loop_index = std::int16_t(k);
    c.hole = k > 0;
    c.planned = true;
    c.edge_length = c.reached_length = 0.08;
    p.coverage.push_back(c);
  }
  p.num_loops = std::int32_t(p.coverage.size());
  return p;
}

// Marks a stretch of `loop` unreached (cause CAUSE_*): the coverage's reached length shrinks by `length`; a
// TOO_SMALL loop is marked not planned (as the planner reports a skipped hole).
inline void leave_unground(hullgrind::grind_path_t& p, int loop, double length, std::int8_t cause) {
  hullgrind::edge_stretch_t s{};
  s.loop_index = std::int16_t(loop);
  s.hole = loop > 0;
  s.start = 0.01;
  s.length = length;
  s.cause = cause;
  s.reason = "test stretch";
  p.unreached.push_back(s);
  p.num_unreached = std::int32_t(p.unreached.size());
  for (auto& c : p.coverage)
    if (c.loop_index == loop) {
      c.reached_length -= length;
      c.planned = cause != hullgrind::edge_stretch_t::CAUSE_TOO_SMALL;
      c.reason = "test";
    }
}

inline hullgrind::job_request_t request(const std::string& job, std::int8_t action) {
  hullgrind::job_request_t r{};
  r.header.frame_id = "";
  r.job_id = job;
  r.part_id = "part-" + job;
  r.action = action;
  return r;
}

// APPROVE by an operator, of revision `revision` (0: the latest), without the loops `excluded`.
inline hullgrind::job_request_t approval(const std::string& job, const std::string& by,
                                         std::vector<std::int16_t> excluded = {}, int revision = 0) {
  hullgrind::job_request_t r = request(job, hullgrind::job_request_t::ACTION_APPROVE);
  r.actor = by.empty() ? "" : "operator " + by;
  r.plan_revision = revision;
  r.excluded_loops = std::move(excluded);
  r.num_excluded = std::int32_t(r.excluded_loops.size());
  return r;
}

}  // namespace rbtest
