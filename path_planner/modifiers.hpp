// The passes after sequencing: each a small class with its parameters in its constructor, composed from the
// config's path-modifiers list into one compound modifier, the way ROS-Industrial's noether composes its
// tool-path modifiers. The steps that change the path's type (smooth, offset, resample, sequence, to_base)
// are plain functions (pipeline.hpp); a modifier takes the sequenced passes and returns them changed.
// A pass (pipeline.hpp) is one grind loop as the tool travels it, from its entry.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "path_planner/pipeline.hpp"

namespace hg::path_planner {

struct ToolPath {
  std::vector<Pass> passes;  // in the order they run
  // The base frame, where the robot bridge judges the corners: corner-speeds judges them there too, on the
  // very numbers the path is published with.
  Eigen::Isometry3d plate_to_base = Eigen::Isometry3d::Identity();
  Vec3 start = Vec3::Zero();  // the robot's position before the first waypoint (base frame)
  int speeds_lowered = 0;     // waypoint speeds lowered for corners (corner-speeds)
};
// The waypoints of every pass, in order.
std::vector<PlateWaypoint> flatten(const ToolPath& path);

class PathModifier {
 public:
  virtual ~PathModifier() = default;
  virtual void apply(ToolPath& path) const = 0;
};

// leads: a lead-in arc onto each pass's entry and a lead-out arc off its end (lead_in_arc, lead_out_arc),
// tangent to the loop on its away side, at the entry's orientation; in a hole the radius is at most 0.3 times
// the radius of a circle of the hole's area. The arc's start becomes the entry (its kind and speed); the old
// entry and the arcs' points are reached at `speed`.
class LeadArcs final : public PathModifier {
 public:
  LeadArcs(double radius, double sweep, double step, double speed);
  void apply(ToolPath& path) const override;

 private:
  double radius_, sweep_, step_, speed_;
};

// approach: before each pass a waypoint `safe_height` above its entry, reached at `travel_speed` (kind
// approach for the first pass, travel for the others; loop -1: an air move).
class Approach final : public PathModifier {
 public:
  Approach(double safe_height, double travel_speed);
  void apply(ToolPath& path) const override;

 private:
  double safe_height_, travel_speed_;
};

// retract: after each pass a waypoint `safe_height` above its last one, reached at `speed` (kind retract).
class Retract final : public PathModifier {
 public:
  Retract(double safe_height, double speed);
  void apply(ToolPath& path) const override;

 private:
  double safe_height_, speed_;
};

// corner-speeds: the cell's corner rule (limit_corner_speeds) over the whole path in the base frame from its
// start; the geometry stays, the speeds at corners are lowered (counted in ToolPath::speeds_lowered).
class CornerSpeeds final : public PathModifier {
 public:
  explicit CornerSpeeds(double max_accel);
  void apply(ToolPath& path) const override;

 private:
  double max_accel_;
};

// Its modifiers, one after the other.
class CompoundModifier final : public PathModifier {
 public:
  explicit CompoundModifier(std::vector<std::unique_ptr<PathModifier>> modifiers);
  void apply(ToolPath& path) const override;
  std::size_t size() const { return modifiers_.size(); }

 private:
  std::vector<std::unique_ptr<PathModifier>> modifiers_;
};

// The names of the path-modifiers list, in the one order they compose in (each works on what the ones before
// it made: the approach goes to the lead-in's start, the corner speeds see every move).
const std::vector<std::string>& modifier_names();
// Empty when `names` is a usable list: known names, each at most once, in the order of modifier_names();
// otherwise why not (names the modifier).
std::string check_modifier_list(const std::vector<std::string>& names);
// The compound modifier of a checked list, each modifier's parameters from the job and the configuration:
// leads (lead-radius, lead-angle, step, grind_speed), approach (safe_height, travel_speed), retract
// (safe_height, the approach speed), corner-speeds (the cell's max-accel).
CompoundModifier compose_modifiers(const std::vector<std::string>& names, const JobParams& job,
                                   const PlannerConfig& config);
// The speed of the vertical moves onto the work and off it: approach-speed, at most the travel speed.
double approach_speed(const JobParams& job, const PlannerConfig& config);

}  // namespace hg::path_planner
