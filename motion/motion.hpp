// The cell's motion rule, in one place: the limits every path is checked against and the corner rule. The
// planner's validation (path_planner/validate.cpp) and its corner-speed step use it to publish only paths
// the robot bridge will run; the bridge (robot_bridge/path.cpp) checks every path with it before it moves.
// No LCM, no I/O.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <vector>

namespace hg::motion {

using Vec3 = Eigen::Vector3d;

// The cell's limits (robot base frame). The defaults are the robot bridge's (config/robot_bridge.yaml):
// the bridge is the last check before the robot moves, so the planner validates against the same numbers.
struct Limits {
  Vec3 workspace_min = Vec3(-1.5, -1.5, -0.5), workspace_max = Vec3(1.5, 1.5, 1.5);  // base frame box
  double table_z = -0.5;    // table top in the base frame: every point of the path must be strictly above
  double max_speed = 0.25;  // m/s, TCP
  double max_accel = 2.0;   // m/s^2, TCP; also the lateral acceleration a corner may demand
};

// Inside the workspace box, bounds included (false for a NaN coordinate).
bool inside_workspace(const Vec3& p, const Limits& limits);
// Strictly above the table top (false for a NaN height).
bool above_table(const Vec3& p, const Limits& limits);

// The corner rule: at every waypoint i but the last, with a = waypoint i-1 (the robot's start position for
// i = 0), b = waypoint i, c = waypoint i+1, and v = min(speed[i], speed[i+1]) (speed[i]: the segment ending
// at i), v^2 / r <= max_accel, r the radius of the circle through a, b, c. A waypoint with a zero-length
// segment on either side is no corner; a reversal (r = 0) breaks the rule at any speed.

// Radius of the circle through a, b, c: infinite when collinear with b between, 0 for a reversal.
double corner_radius(const Vec3& a, const Vec3& b, const Vec3& c);
// Largest v with v * v / radius <= max_accel in floating point (with a 1e-9 relative margin, so another
// build's last-bit rounding of r or v^2 / r still passes); infinite for an infinite radius, 0 for radius 0.
double corner_speed_limit(double radius, double max_accel);

struct CornerFault {
  std::size_t waypoint = 0;
  double radius = 0;   // m, 0 for a reversal
  double speed = 0;    // m/s, the lower of the two segment speeds
  double lateral = 0;  // m/s^2, v^2 / r (infinite for a reversal)
};
// The first waypoint where the path start -> position[0] -> ... breaks the corner rule, if any.
// position and speed have one entry per waypoint.
std::optional<CornerFault> first_corner_fault(const std::vector<Vec3>& position, const std::vector<double>& speed,
                                              const Vec3& start, double max_accel);

}  // namespace hg::motion
