// Calibration geometry (no LCM, no images): circle fit of a hole loop, rigid least-squares fit of point
// sets (Eigen's Umeyama, no scaling), hand-eye solve (OpenCV calibrateHandEye, Tsai and Park), with the
// residuals and the refusal of degenerate data. Library hg_calibration.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace hg::calibration {

// Degenerate or unusable data; what() gives the reason a person can act on.
struct CalibrationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Circle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0;
  double rms = 0;  // RMS of the points' distances from the circle
};

// Algebraic (Kasa) fit for the start, then geometric least squares (Gauss-Newton on the distances to the
// circle). Throws CalibrationError with fewer than 3 points or points on a line.
Circle fit_circle(const std::vector<Eigen::Vector2d>& points);

struct RigidFit {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  // to = transform * from
  std::vector<double> residuals;                                // metres, |transform * from_i - to_i| per feature
  double rms = 0, worst = 0;                                    // metres
  int worst_index = -1;
};

// Least-squares rigid fit (rotation + translation, no scale). Refuses fewer than 3 features, different
// counts, non-finite coordinates and features (on either side) within min_spread metres of a line.
RigidFit fit_rigid(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to,
                   double min_spread = 0.01);

// Distance of the points from their best-fitting line (second singular value of the centred points / sqrt(n)).
double spread_off_line(const std::vector<Eigen::Vector3d>& points);

struct HandEyeMethod {
  std::string name;  // "tsai", "park"
  Eigen::Isometry3d camera_to_flange = Eigen::Isometry3d::Identity();
  // Per view: where the target lands in the base frame through this view (flange * X * target_in_camera),
  // against the mean over the views: translation (m) and rotation (rad) distance.
  std::vector<double> view_translation, view_rotation;
  double rms_translation = 0, worst_translation = 0, worst_rotation = 0;
};

struct HandEyeResult {
  std::vector<HandEyeMethod> methods;   // tsai, park
  double disagreement_translation = 0;  // m between the methods' camera_to_flange
  double disagreement_rotation = 0;     // rad
};

// Eye-in-hand: camera on the flange, target fixed in the base frame. flange_to_base[i] is the robot pose of
// view i, target_to_camera[i] the target's pose seen in view i. Refuses fewer than 3 views, and views whose
// relative rotations are all below min_rotation (rad) or all about (nearly) one axis.
HandEyeResult solve_eye_in_hand(const std::vector<Eigen::Isometry3d>& flange_to_base,
                                const std::vector<Eigen::Isometry3d>& target_to_camera,
                                double min_rotation = 5.0 * M_PI / 180);

// Eye-in-hand with the target on the table: the hole centres' height in the base frame is known (the cell's
// table-z + the plate's thickness). The hand-eye solve leaves the camera's distance along its optical axis
// weakly determined (every view sees the plate from about the same side: the pm806 demo's views were 0.55-0.74
// mm off along it); this moves camera_to_flange along the camera's optical axis by the least-squares amount
// that puts every predicted centre (flange_to_base[i] x camera_to_flange x centres_camera[i][k]) at
// centre_height. Returns the shift (m, along the axis). Throws CalibrationError when no view looks down.
double fit_camera_height(Eigen::Isometry3d& camera_to_flange, const std::vector<Eigen::Isometry3d>& flange_to_base,
                         const std::vector<std::vector<Eigen::Vector3d>>& centres_camera, double centre_height);

// Rotation angle of a.inverse() * b, radians.
double rotation_distance(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

}  // namespace hg::calibration
