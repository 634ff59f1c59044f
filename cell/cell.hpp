// The cell file (config/cell.yaml): the robot cell's geometry and limits in one place, with the
// camera-to-base calibration that produced its transform. Library hg_cell (yaml-cpp + Eigen, no LCM), below
// every process and tool. Units: metres, radians, seconds; frames: the robot base frame unless named.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace hg::cell {

// Every error names the file and the key ("config/cell.yaml: calibration.rms_mm: ...").
struct CellError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Where the camera is: fixed over the table (eye-to-hand: camera-to-base places every cloud) or on the
// robot's flange (eye-in-hand: camera-to-base = base<-flange at capture x camera-to-flange).
enum class Mounting { EyeToHand, EyeInHand };
const char* to_string(Mounting m);  // "eye-to-hand" | "eye-in-hand", the cell file's words

struct Calibration {
  Mounting mounting = Mounting::EyeToHand;  // key mounting; absent: eye-to-hand
  // p_base = T * p_camera; eye-in-hand: not used for planning (the pose changes with the robot)
  Eigen::Isometry3d camera_to_base = Eigen::Isometry3d::Identity();
  std::string date;     // ISO 8601 UTC, when it was measured
  std::string method;   // "eye-to-hand umeyama", "eye-in-hand tsai", "manual", ...
  double rms_mm = 0;    // RMS residual of the fit, mm
  double worst_mm = 0;  // largest residual, mm
  int features = 0;     // holes (eye-to-hand) or views (eye-in-hand) the fit used
  // Eye-in-hand: camera -> flange (p_flange = T * p_camera); key camera-to-flange, required by mounting
  // eye-in-hand, kept but unused by eye-to-hand.
  std::optional<Eigen::Isometry3d> camera_to_flange;
};

struct Tool {
  double radius = 0.01;  // m, quantity::kToolRadius (runtime/quantities.hpp)
  double tilt = 0;       // rad, toward the edge normal, quantity::kTilt
};

// The names of the cell's frames (key `frames`), in one place: every path, the workspace, the table and home
// are in the base frame, and a path in another frame is refused by the robot bridge.
struct Frames {
  std::string base = "robot_base";  // key frames.base; absent: robot_base
};

// Who approves a plan before the robot moves (key `approval`): an operator always, or the cell's policy for a
// plan that reaches every edge of the part (a plan with an unreached edge always waits for an operator).
enum class Approval { Operator, Auto };

// What the outline service takes from the cell (section `outline`, optional; docs/cell.md): the smallest
// part, and how much of the edge a scan may leave unseen before its outline is POOR (the job NEEDS_RESCAN).
struct OutlineRules {
  double min_part_area = 0.002;   // m^2: a smaller outer loop is a fragment, dropped and counted
  double max_edge_dropout = 0.3;  // fraction of the outer edge's length in dropout or shadow; above: POOR
  double max_edge_gap = 0.1;      // m, the longest such stretch; above: POOR
};

struct Cell {
  Calibration calibration;
  double table_z = 0;  // table top in the base frame; every path point must be strictly above
  Eigen::Vector3d workspace_min = Eigen::Vector3d::Zero(), workspace_max = Eigen::Vector3d::Zero();
  double max_speed = 0;  // m/s
  double max_accel = 0;  // m/s^2
  Tool tool;
  Eigen::Vector3d home = Eigen::Vector3d::Zero();
  Approval approval = Approval::Operator;  // optional key, default operator
  OutlineRules outline;                    // optional section, defaults above
  Frames frames;                           // optional section
};

// Reads and validates a cell file. Throws CellError naming the file and the key: missing or unknown keys,
// wrong types, non-finite numbers, a rotation that is not orthonormal, an empty or inverted workspace, home
// outside it, non-positive limits.
Cell read_cell(const std::string& path);

// Validates, then writes the cell atomically. An existing file is first kept as PATH.YYYYMMDDTHHMMSSZ.bak
// (returned; empty when there was none). Throws CellError naming the file.
std::string write_cell(const std::string& path, const Cell& cell);

// The checks read_cell applies, for a cell built in code; `where` prefixes the messages.
void validate(const Cell& cell, const std::string& where);

// True when R is a proper rotation: orthonormal (every entry of R R^T - I within 1e-6) and det R > 0. The one
// check of a calibration's rotation, for the cell file and everything that takes a transform.
bool is_rotation(const Eigen::Matrix3d& R);

// Current UTC time as ISO 8601 ("2026-12-01T20:30:00Z").
std::string utc_now_iso();

}  // namespace hg::cell
