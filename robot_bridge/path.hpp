// A grind path as the robot bridge runs it, the safety checks made before anything moves, and the motion
// profile the simulated robot follows. No LCM and no I/O here, so tests drive it with their own clock.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

#include "motion/motion.hpp"

namespace hullgrind {
class grind_path_t;
}

namespace hg::robot_bridge {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

struct Pose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
};

struct Path {
  std::string job_id;
  std::string frame;
  std::vector<Vec3> position;     // robot base frame, metres
  std::vector<Quat> orientation;  // tool frame in the base frame
  std::vector<double> speed;      // m/s on the segment that ENDS at the waypoint (speed[0]: from the start pose)
  std::vector<std::int8_t> kind;  // grind_path_t::KIND_*
  std::size_t size() const { return position.size(); }
};

Path from_lcm(const hullgrind::grind_path_t& msg);
// Reads a path file (path_file/path_file.hpp, docs/path_file.md) with the one path-file reader. Throws
// std::runtime_error naming the file, the key and the waypoint index.
Path read_path_json(const std::string& file);
const char* kind_name(std::int8_t kind);

// The cell's limits (motion/motion.hpp, shared with the planner's validation); every path is checked
// against them before the robot moves.
using Limits = motion::Limits;

// Empty when the path may run from `start` (the robot's current TCP); else the first reason, naming the
// waypoint. Checks: non-empty, finite numbers, unit quaternions, every waypoint (and the start) inside the
// workspace box and above the table (segments are straight, the box convex: the whole path stays inside),
// 0 < speed <= max_speed, and the corner rule of motion/motion.hpp (the lateral acceleration v^2 / r of
// every corner at its commanded speed within max_accel; a reversal is refused).
std::string check_path(const Path& path, const Pose& start, const Limits& limits);
// Empty when the path is in the cell's base frame (frames.base); else why not: its positions would be read in
// the wrong frame. Checked before check_path by everything that runs or exports a path.
std::string check_frame(const Path& path, const std::string& base_frame);

// Time-parametrised motion along the polyline start -> waypoint 0 -> ... -> waypoint n-1, at rest at both
// ends. Each segment runs at its commanded speed; speed changes are trapezoidal with tangential
// acceleration `accel`: the speed at a waypoint is the lower of the two segment speeds, lowered further
// where a segment is too short to brake or accelerate in (forward and backward passes). Orientation is
// slerped along each segment by distance. Corners are taken without slowing (check_path bounds their
// lateral acceleration).
class Profile {
 public:
  Profile() = default;
  Profile(const Pose& start, const Path& path, double accel);

  struct Sample {
    Pose pose;
    int waypoint = -1;    // index of the waypoint being approached (n when finished)
    double distance = 0;  // along the path from the start pose, metres
    double speed = 0;
  };
  Sample at(double t) const;  // t in seconds since the start; clamped to [0, duration]
  double duration() const { return t0_.empty() ? 0 : t0_.back(); }
  double length() const { return s0_.empty() ? 0 : s0_.back(); }
  std::size_t segments() const { return len_.size(); }

 private:
  std::vector<Vec3> p_;
  std::vector<Quat> q_;
  std::vector<double> len_, s0_, t0_;          // per segment length; cumulative distance and time at pts
  std::vector<double> v_in_, v_out_, v_peak_;  // per segment
  double accel_ = 1;
};

}  // namespace hg::robot_bridge
