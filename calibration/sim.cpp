#include "calibration/sim.hpp"

#include <cmath>
#include <random>
#include <stdexcept>

#include "calibration/target.hpp"
#include "sim/partgen/shapes.hpp"

namespace hg::calibration::sim {

namespace scene = hg::sim;

Eigen::Isometry3d table_to_base() {
  // Table top at base z = 0 (config/cell.yaml), its origin 0.6 m in front of the robot, turned 2 deg.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.035, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.6, 0.05, 0.0);
  return T;
}

Eigen::Isometry3d camera_to_flange() {
  // Camera 80 mm beside the tool axis and 120 mm up it, looking along the flange's z, turned 90 deg.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      (Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.08, 0.0, 0.12);
  return T;
}

View render_plate(const scene::CameraProfile& profile, const Eigen::Isometry3d& plate_to_camera, std::uint64_t seed,
                  std::uint64_t frame_index) {
  // Renderer: camera_from_table = [F Rx(a) Ry(b) | (0, 0, h)], table_from_part = [Rz(c) | (tx, ty, 0)],
  // F = diag(1, -1, -1). Decompose F R = Rx(a) Ry(b) Rz(c) and solve the translation for tx, ty, h.
  const Eigen::Matrix3d F = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const Eigen::Matrix3d M = F * plate_to_camera.linear();
  const double b = std::asin(std::clamp(M(0, 2), -1.0, 1.0));
  const double a = std::atan2(-M(1, 2), M(2, 2)), c = std::atan2(-M(0, 1), M(0, 0));
  const Eigen::Matrix3d tilt =
      (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
  Eigen::Matrix3d A;
  A << tilt.col(0), tilt.col(1), -Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d sol = A.fullPivLu().solve(F * plate_to_camera.translation());
  if (!(sol.z() > 0.2) || std::abs(a) > 0.6 || std::abs(b) > 0.6)
    throw std::invalid_argument("calibration sim: plate pose cannot be rendered (tilt or distance)");
  const partgen::Shape shape = partgen::make_shape("calibration-plate");
  const auto box_centre = [&] {
    Eigen::Vector2d lo = shape.polygon.outer[0], hi = lo;
    for (const auto& p : shape.polygon.outer) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    return Eigen::Vector2d((lo + hi) / 2);
  }();
  scene::CameraProfile prof = profile;
  prof.mount_height = sol.z();
  scene::SceneSpec spec;
  spec.name = "calibration-plate";
  spec.table_tilt_x = a;
  spec.table_tilt_y = b;
  spec.seed = seed;
  scene::ScenePart part;
  part.shape = "calibration-plate";
  part.theta = c;
  part.thickness = shape.thickness;
  const Eigen::Vector2d centre = Eigen::Vector2d(sol.x(), sol.y()) + Eigen::Rotation2Dd(c) * box_centre;
  part.x = centre.x();
  part.y = centre.y();
  spec.parts.push_back(part);
  View v;
  v.frame = scene::render(spec, prof, frame_index);
  // Truth from the renderer: its camera pose and the part's placement as it placed it.
  const partgen::Pose placed = partgen::pose_about_centre(shape, part.theta, {part.x, part.y});
  Eigen::Isometry3d part_to_table = Eigen::Isometry3d::Identity();
  part_to_table.linear() = Eigen::AngleAxisd(placed.theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  part_to_table.translation() << placed.translation, 0;
  v.plate_to_camera = v.frame.camera_from_table * part_to_table;
  return v;
}

namespace {

Eigen::Isometry3d pose(double x, double y, double z, const Eigen::Matrix3d& R) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

Eigen::Matrix3d small_rotation(std::mt19937_64& rng, double sigma) {
  std::normal_distribution<double> n(0, sigma);
  const Eigen::Vector3d w(n(rng), n(rng), n(rng));
  return w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

}  // namespace

EyeToHandSession eye_to_hand(const std::string& profile_name, int placements, double tcp_noise, std::uint64_t seed) {
  const scene::CameraProfile prof = scene::camera_profile(profile_name);
  const Drawing drawing = calibration_plate_drawing();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> n(0, tcp_noise);
  EyeToHandSession s;
  const Eigen::Matrix3d flip = Eigen::Vector3d(1, -1, -1).asDiagonal();
  for (int k = 0; k < placements; ++k) {
    // Plate centre within 0.2 m x 0.12 m of the point under the camera, turned up to 45 deg.
    const Eigen::Isometry3d plate_to_table =
        pose(0.2 * u(rng), 0.12 * u(rng), 0,
             Eigen::AngleAxisd(0.8 * u(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix()) *
        pose(-0.21, -0.15, 0, Eigen::Matrix3d::Identity());
    const Eigen::Isometry3d table_to_camera = pose(0, 0, prof.mount_height, flip);
    View v = render_plate(prof, table_to_camera * plate_to_table, seed, k);
    s.camera_to_base_true = table_to_base() * v.frame.camera_from_table.inverse();
    s.plate_to_base_true.push_back(s.camera_to_base_true * v.plate_to_camera);
    std::vector<Eigen::Vector3d> tcp;
    for (const auto& h : drawing.holes)
      tcp.push_back(s.plate_to_base_true.back() * h.centre + Eigen::Vector3d(n(rng), n(rng), n(rng)));
    s.tcp_at_hole.push_back(tcp);
    s.views.push_back(std::move(v));
  }
  return s;
}

EyeInHandPlan eye_in_hand_plan(const std::string& profile_name, int views, std::uint64_t seed) {
  const scene::CameraProfile prof = scene::camera_profile(profile_name);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  EyeInHandPlan plan;
  plan.camera_to_flange_true = camera_to_flange();
  plan.plate_to_base_true = table_to_base() * pose(-0.21, -0.15, 0, Eigen::Matrix3d::Identity());
  const Eigen::Matrix3d flip = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const double h = 0.6 * prof.mount_height;  // the carrying robot holds the camera closer than a fixed mount
  for (int k = 0; k < views; ++k) {
    // Camera over the plate centre, tilted about the table's x and y, turned about its optical axis.
    const Eigen::Matrix3d R = flip * (Eigen::AngleAxisd(0.4 * u(rng), Eigen::Vector3d::UnitX()) *
                                      Eigen::AngleAxisd(0.4 * u(rng), Eigen::Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(0.6 * u(rng), Eigen::Vector3d::UnitZ()))
                                         .toRotationMatrix();
    const Eigen::Isometry3d plate_to_camera =
        pose(0.03 * u(rng), 0.03 * u(rng), h + 0.1 * u(rng), R) * pose(-0.21, -0.15, 0, Eigen::Matrix3d::Identity());
    plan.flange_to_base.push_back(plan.plate_to_base_true * plate_to_camera.inverse() *
                                  plan.camera_to_flange_true.inverse());
  }
  return plan;
}

View render_from_flange(const std::string& profile, const EyeInHandPlan& plan, const Eigen::Isometry3d& flange,
                        std::uint64_t seed, std::uint64_t frame_index, Eigen::Isometry3d* rendered_flange) {
  const Eigen::Isometry3d plate_to_camera = (flange * plan.camera_to_flange_true).inverse() * plan.plate_to_base_true;
  View v = render_plate(scene::camera_profile(profile), plate_to_camera, seed, frame_index);
  if (rendered_flange)
    *rendered_flange = plan.plate_to_base_true * v.plate_to_camera.inverse() * plan.camera_to_flange_true.inverse();
  return v;
}

EyeInHandSession eye_in_hand(const std::string& profile_name, int views, double pose_noise, std::uint64_t seed) {
  const EyeInHandPlan plan = eye_in_hand_plan(profile_name, views, seed);
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ull);
  EyeInHandSession s;
  s.camera_to_flange_true = plan.camera_to_flange_true;
  s.plate_to_base_true = plan.plate_to_base_true;
  std::normal_distribution<double> n(0, pose_noise);
  for (int k = 0; k < views; ++k) {
    // The robot pose that put the camera there (the renderer's truth), then what the robot reports.
    Eigen::Isometry3d flange;
    View v = render_from_flange(profile_name, plan, plan.flange_to_base[k], seed, k, &flange);
    Eigen::Isometry3d reported = flange;
    reported.linear() = flange.linear() * small_rotation(rng, 0.1 * pose_noise);
    reported.translation() += Eigen::Vector3d(n(rng), n(rng), n(rng));
    s.flange_to_base.push_back(reported);
    s.views.push_back(std::move(v));
  }
  return s;
}

}  // namespace hg::calibration::sim
