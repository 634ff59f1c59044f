// URScript for Universal Robots controllers: a grind path becomes one program of linear moves.
#pragma once

#include <cstdint>
#include <string>

#include "robot_bridge/path.hpp"

namespace hg::robot_bridge {

struct ScriptOptions {
  double accel = 0.5;           // tool acceleration a= for every move, m/s^2
  double blend_radius = 0.001;  // r= between moves, metres; capped at 40 % of the shorter adjacent segment
  int progress_register =
      24;  // output integer register the program writes the waypoint index to (RTDE: output_int_register_N)
  std::int32_t done_tag = 1;  // written to the register after the last move: "this job's program finished"
  std::string name = "hg_job";
};

// p[x, y, z, rx, ry, rz]: position in metres, rotation vector (axis * angle, angle in [0, pi]) in radians.
std::string ur_pose(const Vec3& position, const Quat& orientation);
// Air moves (approach, retract, travel) are movel; tool-on-work moves (lead-in, grind, lead-out) are movep
// (constant tool speed through the blends). Before the move to waypoint i the program writes i to the
// progress register; after the last move it writes done_tag. The last move has r=0 (stops exactly).
std::string make_script(const Path& path, const ScriptOptions& options);
// What the bridge sends to halt a running program: a new program replaces it and decelerates the tool.
std::string stop_script(double accel);

}  // namespace hg::robot_bridge
