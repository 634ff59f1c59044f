// The grind-path planning pipeline: small pure steps over plain structs (Eigen), composed the way
// ROS-Industrial's noether composes tool paths: the steps that change the path's type are functions,
//   (mirror if flipped) -> smooth -> offset -> resample -> sequence (order, start, orientation),
// then the path modifiers of the config's list (modifiers.hpp: leads, approach, retract, corner speeds),
//   -> robot base frame -> validate -> coverage.
// No LCM here: the process (path_planner.cpp) and the CLI (hg_plan.cpp) both call plan().
//
// Conventions (see docs/path_planner.md):
//  - 2-D work happens in the PLATE frame: x, y in the plate plane, z up (away from the table, toward the
//    camera). normalize_up() makes the outline's plane satisfy this before anything else.
//  - Rings are open (closing edge implicit). Canonical orientation: material on the LEFT of travel, i.e.
//    outer loops counter-clockwise and holes clockwise seen from above (what the outline core produces).
//  - SI units: metres, radians, m/s.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "motion/motion.hpp"
#include "polygon/polygon.hpp"
#include "runtime/quantities.hpp"

namespace hg::path_planner {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Ring = std::vector<Vec2>;

struct Loop {
  bool hole = false;
  Ring points;  // canonical orientation: material on the left
};

// The plate plane in the camera frame: p = origin + x u + y v (+ z normal).
struct Plane {
  Vec3 origin = Vec3::Zero();
  Vec3 u = Vec3::UnitX(), v = Vec3::UnitY(), normal = Vec3::UnitZ();
};

struct OutlineInput {
  Plane plane;               // camera frame (plan() applies camera_to_base to it)
  std::string frame;         // the frame an outline file says its plane is in ("" when it does not say)
  bool plane_given = false;  // an outline file had a plane (else: the configured default plane)
  std::vector<Loop> loops;
  std::int64_t seq = -1;  // outline header.seq, copied into the path
  // The point spacing h the outline was computed from (outline_t.point_spacing, the "spacing" of hg-outline's
  // JSON): the pixel pitch on the plate for a camera's grid. 0: not given (estimated from the loops).
  double point_spacing = 0;
};

// ---- geometry helpers (polygon/polygon.hpp) ----
using polygon::ring_length;
using polygon::signed_area;
// Makes every ring canonical (outer CCW, holes CW) by reversing those that are not.
void make_canonical(std::vector<Loop>& loops);
// Area centroid and principal (major) axis direction of the outer loops minus the holes.
struct AreaMoments {
  double area = 0;
  Vec2 centroid = Vec2::Zero();
  Vec2 major_axis = Vec2::UnitX();
};
AreaMoments area_moments(const std::vector<Loop>& loops);

// ---- input checks and frame normalisation ----
// Empty string when usable; otherwise why not (names the loop and point index).
std::string check_outline(const OutlineInput& in);
// If the plane normal points down in the robot base frame (base z up), flips normal and v and mirrors the
// loops (y -> -y, rings reversed) so that the plate frame has z up and loops stay canonical.
void normalize_up(OutlineInput& in, const Eigen::Isometry3d& camera_to_base);
// Double-sided grinding: the part is turned over about its principal axis through its area centroid (the
// axis part_pose_t reports and the handling robot flips it about), so the second side's edges are the
// mirror image of the first side's across that line. Rings are reversed to stay canonical.
std::vector<Loop> mirror_for_flip(const std::vector<Loop>& loops);

// ---- 1. de-noise the pixel staircase, keeping corners ----
struct SmoothOptions {
  double pitch = 0;                          // pixel pitch on the plate; <= 0: estimate from the outline
  double window_pitches = 4;                 // residual windows are 2x this many vertices (misfit test, noise level)
  double corner_scale_pitches = 8;           // length of the one-sided line fits of the corner detector, in units
                                             // (the pitch, or the vertex spacing when noise spreads it)
  double corner_angle = 0.5235987755982988;  // 30 deg: smaller turns are treated as curves
  bool edge_compensation = true;             // move the loop from the outermost pixel centres to the edge
  double noise = 0;                          // noise of a window mean, m (estimate_noise); 0: from the ring itself
};
struct SmoothedRing {
  Ring points;
  std::vector<std::uint8_t> corner;  // 1 where points[i] is a detected corner
};
// Pixel pitch estimate: median length of the loop edges within 10 deg of the x or y axis (the staircase
// steps), when most edges are such steps and most of those are within 2 % of the median (lattice steps);
// 0 otherwise: a drawn polygon, or a noisy boundary (noise of a fraction of a pitch destroys the lattice).
double estimate_pitch(const std::vector<Loop>& loops);
// The spacing of a dense outline from its own vertices when the staircase is lost (noise): the lower
// quartile of the edge lengths of the loops of 200 vertices and more (a pixel boundary's edges are one pitch
// along an axis and longer on the diagonals); 0 for a drawn polygon (no such loop).
double estimate_vertex_spacing(const std::vector<Loop>& loops);
// The spacing the smoothing and the coverage use, and where it came from: the configured pixel-pitch, else
// the outline's point spacing, else estimate_pitch, else estimate_vertex_spacing (0: none, a drawn polygon).
// The last is no pixel lattice: the smoothing gets pitch 0 then (its unit from the vertices, no edge
// compensation) and only the coverage tolerance uses it.
struct Spacing {
  double value = 0;
  std::string source;  // "pixel-pitch", "outline", "staircase", "vertices" or "none"
};
Spacing choose_spacing(const OutlineInput& outline, const SmoothOptions& configured);
// Corner-preserving de-noising (smooth.cpp): corners from a two-scale turning angle, the runs between them
// as TLS line and circle pieces, corners at the intersections of the pieces beside them, edge compensation
// by pitch/2 * max(|t_x|, |t_y|). pitch 0 (unknown): dense rings are fitted without edge compensation,
// sparse ones (drawn polygons) returned unchanged. Straight pieces come out as their two end points.
SmoothedRing smooth_ring(const Ring& ring, double pitch, const SmoothOptions& options);
// Noise of the outline's window means (the misfit threshold of the fits), pooled over all loops: it is the
// camera's and the segmentation's, the same along every edge of a frame, and a short loop of tight arcs
// (a slot) would overestimate it alone, since arc-to-line junctions are not cancelled by the estimator.
double estimate_noise(const std::vector<Loop>& loops, const SmoothOptions& options);

// ---- 2. offset by the tool radius (Clipper) ----
// Outer loops grow by `distance`, holes shrink. Returns zero rings for a hole too small for the tool, and
// possibly several rings when the offset splits a loop. Output canonical (material on the left).
std::vector<Ring> offset_ring(const Ring& ring, bool hole, double distance, double arc_tolerance);

// The diameter of the widest circle inside a hole's edge, within 0.04 mm (bisection on the offset, which
// vanishes a little early): a tool of
// that diameter or less fits. Infinite for an outer loop.
double inscribed_width(const Ring& edge, bool hole, double arc_tolerance);

// ---- 3. resample at a fixed step, keeping corners ----
// Vertices whose turning angle exceeds corner_angle are kept exactly; every piece between them is divided
// into equal sub-steps no longer than `step`, and (chord_error > 0) a sub-step whose chord strays farther
// than chord_error from the piece's vertices is halved, there only, until it does not: a tight arc (a slot
// end offset to 1 mm radius) is not cut across by a 2 mm step, which would leave its edge out of reach.
struct SampledRing {
  Ring points;
  std::vector<std::uint8_t> corner;
};
SampledRing resample_ring(const Ring& ring, double step, double corner_angle, double chord_error = 0);

// ---- 4. orientation ----
using job::Direction;  // runtime/quantities.hpp: one declaration with the job request's
// True when the loop is travelled against its canonical direction (material on the right). Climb with a
// spindle turning clockwise seen from above puts the material on the right of travel (G41): outer loops
// clockwise, holes counter-clockwise; conventional is the reverse.
bool travel_reversed(Direction direction, bool spindle_clockwise);
// Tool frame in the plate frame for a waypoint with travel tangent t and away-from-material normal m
// (both in-plane unit vectors): x along travel, z (the tool axis, pointing from the flange to the work)
// = cos(tilt) * (-up) - sin(tilt) * m, i.e. tilted by `tilt` away from the vertical, the tool leaning out
// over the air side with its tip toward the edge; y = z x x.
Eigen::Quaterniond tool_orientation(const Vec2& tangent, const Vec2& away_normal, double tilt);

// ---- 5. sequencing: ordering, start points, leads, approach/retract ----
// The waypoint kinds: runtime/quantities.hpp (grind_path_t.kind).
using waypoint::kApproach;
using waypoint::kGrind;
using waypoint::Kind;
using waypoint::kLeadIn;
using waypoint::kLeadOut;
using waypoint::kRetract;
using waypoint::kTravel;
struct PlateWaypoint {
  Vec3 position;  // plate frame
  Eigen::Quaterniond orientation;
  double speed;
  std::int8_t kind;
  std::int16_t loop;  // index into the outline's loops; -1 for air moves
};
struct GrindLoop {
  SampledRing ring;  // canonical orientation
  bool hole = false;
  int loop_index = 0;  // outline loop it came from
};
struct SequenceOptions {
  double tilt = 0;
  double grind_speed = 0.02;
  double approach_speed = 0.05;  // of the move onto each pass's entry (modifiers.hpp)
  double z = 0;                  // height of the grind points above the plate top surface
  Direction direction = Direction::Climb;
  bool spindle_clockwise = true;
};
// Greedy nearest-neighbour order: from `start` (plate frame, x, y), the loop with the nearest eligible
// start vertex (not a corner) next, and so on. Returns the loop order and each loop's start vertex.
struct Ordering {
  std::vector<int> order;
  std::vector<int> start_vertex;  // per entry of order
};
Ordering order_loops(const std::vector<GrindLoop>& loops, const Vec2& start);
// Lead-in arc: ends at p0 tangent to `tangent`, lies on the `away` side; returns points from its start to
// p0 inclusive. Lead-out is the mirror image: starts at p0, leaves tangentially.
std::vector<Vec2> lead_in_arc(const Vec2& p0, const Vec2& tangent, const Vec2& away, double radius, double sweep,
                              double step);
std::vector<Vec2> lead_out_arc(const Vec2& p0, const Vec2& tangent, const Vec2& away, double radius, double sweep,
                               double step);
// One grind loop as the tool travels it. Every waypoint's speed and kind say how the tool moves INTO it: the
// first, the entry (the loop's start vertex), is reached at the approach speed (kind approach), the others
// (round the loop to the start vertex again) are grind moves.
struct Pass {
  std::int16_t loop = 0;  // index into the outline's loops
  bool hole = false;
  double area = 0;  // of the ring ground, m^2 (a lead arc in a hole stays well inside it)
  // Travel direction and away-from-material normal at the entry (plate frame, unit, in-plane).
  Vec2 tangent = Vec2::UnitX(), away = Vec2::UnitY();
  std::vector<PlateWaypoint> waypoints;  // plate frame; waypoints.front() is the entry
};
// One pass per loop, in order_loops' order, in the travel direction, each waypoint at its tool_orientation.
// The leads, approach, retract and corner speeds are path modifiers after it (modifiers.hpp).
std::vector<Pass> sequence(const std::vector<GrindLoop>& loops, const Vec2& start, const SequenceOptions& options);

// ---- 6. into the robot base frame ----
struct Waypoint {
  Vec3 position;  // robot base frame
  Eigen::Quaterniond orientation;
  double speed;
  std::int8_t kind;
  std::int16_t loop;
};
// Plate frame -> camera frame (plane) -> base frame (hand-eye calibration).
Eigen::Isometry3d plate_to_base(const Plane& plane, const Eigen::Isometry3d& camera_to_base);
std::vector<Waypoint> to_base(const std::vector<PlateWaypoint>& path, const Eigen::Isometry3d& plate_to_base);
// Camera -> base from x, y, z (m) and roll, pitch, yaw (rad, R = Rz(yaw) Ry(pitch) Rx(roll)).
Eigen::Isometry3d pose_from_xyz_rpy(const Vec3& xyz, const Vec3& rpy);

// ---- 6b. corner speeds (the cell's corner rule, motion/motion.hpp, which the robot bridge checks) ----
using motion::corner_radius;
using motion::corner_speed_limit;
// Lowers the speed of both segments at every corner to the corner's limit (geometry unchanged); reversals
// are left for validate to refuse. Returns how many waypoint speeds were lowered.
int limit_corner_speeds(std::vector<Waypoint>& path, const Vec3& start, double max_accel);

// ---- 7. validation ----
// The cell's limits (motion/motion.hpp): one struct and one set of defaults with the robot bridge;
// max_accel MUST equal the bridge's max-accel.
using Limits = motion::Limits;
// Empty string when the path is fit to run; otherwise the first reason found (names the waypoint).
// Self-intersection is checked per grind loop (lead-in end + grind waypoints of one loop) in the plane
// perpendicular to `up` (base frame). Corners: the rule above from `start` (the robot's position).
std::string validate(const std::vector<Waypoint>& path, const Limits& limits, const Vec3& up, const Vec3& start);
// True when the closed polyline has two non-adjacent segments that touch or cross (grid-bucketed).
bool self_intersects(const std::vector<Vec2>& closed_polyline);

// ---- 7b. coverage: the tool reaches every point of the edge ----
// The disc's reach in the plate plane: every point within the effective tool radius (tool_radius, the
// radius at the contact; the tilt turns the disc about the TCP and does not move the contact in this
// model) of the TCP's grind path, the published waypoints taken back into the plate frame and projected
// along the plate normal. The edge checked is the smoothed ring (the planner's estimate of the true,
// edge-compensated edge that the offset is taken from): the raw outline runs through the outermost pixel
// centres, half a pitch inside the edge, with noise of the order of the tolerance (docs/path_planner.md).
struct Segment2 {
  Vec2 a, b;
};
// The TCP path of every grind loop in the plate frame: the segments that end at a grind waypoint (the first
// starts at the lead-in's end), projected onto the plate plane.
std::vector<Segment2> grind_segments(const std::vector<Waypoint>& path, const Eigen::Isometry3d& plate_to_base);
struct UnreachedStretch {
  double start = 0;   // arc length from the edge ring's first vertex to the stretch's start, m
  double length = 0;  // m
  Vec2 from = Vec2::Zero(), to = Vec2::Zero();  // end points (plate frame)
  bool concave = false;                         // at a concave corner, or a concave bend tighter than the tool
  double depth = 0;  // the farthest sample's distance beyond the reach, m (infinite: more than one reach beyond)
  std::vector<Vec2> points;  // the edge samples in the stretch, in order (plate frame)
};
struct LoopCoverage {
  int loop = 0;
  bool hole = false;
  bool planned = true;  // false: the loop is not ground at all (a hole too small for the tool; skipped says why)
  std::string skipped;  // why not planned
  double length = 0;    // edge length, m
  double unreached_length = 0;  // m
  std::vector<UnreachedStretch> unreached;
  double reached_fraction() const { return length > 0 ? 1 - unreached_length / length : 1; }
};
// Samples the closed edge ring at spacing tolerance / 2 (every vertex included) and counts a sample reached
// when it lies within reach + tolerance - spacing / 2 of a segment: every point of the edge is then within
// half a spacing of a sample, so a loop reported fully reached has every point within reach + tolerance.
// Each sample stands for half the edge to each neighbour; consecutive unreached samples make a stretch.
LoopCoverage edge_coverage(const Ring& edge, const std::vector<Segment2>& tool_path, double reach, double tolerance);

// One line for a loop with unreached edge: the loop, the unreached and total length, the longest stretch's end
// points in the base frame (mm), and whether a concave corner or bend tighter than the tool is the cause.
std::string describe_unreached(const LoopCoverage& coverage, const Eigen::Isometry3d& plate_to_base, double reach,
                               double tolerance, const std::string& frame);

// ---- composition ----
struct JobParams {
  double tool_radius = 0.01;         // quantity::kToolRadius
  double tilt = 0.7853981633974483;  // quantity::kTilt (45 deg)
  double grind_speed = 0.02;
  double travel_speed = 0.2;
  double step = 0.002;
  double safe_height = 0.05;
  Direction direction = Direction::Climb;
  bool flipped = false;
};
enum class SmallHolePolicy { Fail, Skip };
struct PlannerConfig {
  JobParams defaults;
  SmoothOptions smooth;
  double arc_tolerance = 1e-5;                         // Clipper round-join tolerance, metres
  double resample_corner_angle = 0.17453292519943295;  // 10 deg
  double approach_speed = 0.05;
  double lead_radius = 0.01;
  double lead_angle = 1.5707963267948966;
  // The path modifiers after sequencing, in order (modifiers.hpp; the parameter path-modifiers).
  std::vector<std::string> modifiers = {"leads", "approach", "retract", "corner-speeds"};
  double z_offset = 0;
  bool spindle_clockwise = true;
  SmallHolePolicy small_hole = SmallHolePolicy::Fail;  // also what an edge the tool cannot reach does
  double coverage_tolerance = 2e-4;                    // edge points may be this much farther than the tool radius, m
  double resample_chord_error =
      1e-5;  // largest distance of a resampled chord from the offset ring, m (as arc_tolerance)
  Eigen::Isometry3d camera_to_base = Eigen::Isometry3d::Identity();
  // Eye-in-hand cells: camera -> flange; each outline is placed with its flange pose (place_outline).
  std::optional<Eigen::Isometry3d> camera_to_flange;
  Plane default_plane;            // used when an outline file has no plane
  Vec3 home = Vec3(0.5, 0, 0.3);  // base frame; start reference when the robot's position is unknown
  std::string base_frame = "robot_base";
  Limits limits;
  // From the cell file (config_from): its name for messages. With a cell, defaults.tool_radius is the mounted
  // tool's, which a job may not exceed; a config built in code (no cell file) has no such check.
  std::string cell_file;
};
struct PlanResult {
  bool ok = false;
  std::string reason;  // why not, when !ok
  std::vector<std::string> warnings;
  std::vector<Waypoint> path;
  JobParams params;          // as used
  double pitch = 0;          // pixel pitch used by the smoothing
  std::string pitch_source;  // Spacing::source
  int loops_planned = 0;
  int slowed = 0;                      // waypoint speeds lowered for corners (limit_corner_speeds)
  std::vector<LoopCoverage> coverage;  // per outline loop (edge_coverage), when the path was made
  std::vector<Ring> edges;             // the smoothed edge of every outline loop (plate frame): what the tool grinds
  double unreached_length = 0;         // sum over the loops, m
  double coverage_tolerance = 0;       // as used
  Eigen::Isometry3d plate_to_base = Eigen::Isometry3d::Identity();  // plate frame of the coverage -> base
  double seconds = 0;                                               // planning time
};
// Fills zero-valued job parameters from the defaults; returns a reason when a parameter is outside its range
// (runtime/quantities.hpp, the one every reader checks) or the direction is none.
std::string resolve_params(const JobParams& requested, const JobParams& defaults, JobParams& out);
// Empty when the job's parameters are within the cell (speeds <= limits.max_speed, tool radius <= the
// mounted tool's, defaults.tool_radius, when the config came from a cell file); else the reason, naming the
// cell file and key.
std::string check_job_within_cell(const JobParams& params, const PlannerConfig& config);
PlanResult plan(OutlineInput outline, const JobParams& params, const PlannerConfig& config,
                const std::optional<Vec3>& robot_position_base);
// The first steps of plan(): normalize_up, make_canonical, the flip's mirror (in place on `outline`), the
// pitch (set) and the smoothed ring of every loop: the edges the tool must grind, plate frame.
std::vector<Ring> edges_to_grind(OutlineInput& outline, bool flipped, const PlannerConfig& config, double& pitch);
// The coverage check's tolerance: the configured one plus half the spacing, since the edge is only known to
// within half a pixel (a stretch of the estimated edge less than that beyond the tool is within its error).
double coverage_tolerance(const PlannerConfig& config, double pitch);
// edge_coverage of every loop's edge by the tool path (loop and hole filled in).
std::vector<LoopCoverage> loops_coverage(const std::vector<Loop>& loops, const std::vector<Ring>& edges,
                                         const std::vector<Segment2>& tool_path, double reach, double tolerance);
// The coverage plan() computed, recomputed from an outline and a published path (the overview draws it):
// the same edges and the same check, with the plate frame's transform to the base frame.
struct PathCoverage {
  std::vector<LoopCoverage> loops;
  Eigen::Isometry3d plate_to_base = Eigen::Isometry3d::Identity();
};
PathCoverage path_coverage(OutlineInput outline, const std::vector<Waypoint>& path, double tool_radius, bool flipped,
                           const PlannerConfig& config);

}  // namespace hg::path_planner
