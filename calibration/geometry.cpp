#include "calibration/geometry.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/SVD>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace hg::calibration {

Circle fit_circle(const std::vector<Eigen::Vector2d>& pts) {
  const int n = static_cast<int>(pts.size());
  if (n < 3) throw CalibrationError("circle fit: " + std::to_string(n) + " points, need at least 3");
  // Centre the points first: the algebraic system is badly conditioned far from the origin.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= n;
  // Kasa: x^2 + y^2 + D x + E y + F = 0 in least squares.
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d q = pts[i] - mean;
    A.row(i) << q.x(), q.y(), 1.0;
    b[i] = -q.squaredNorm();
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::Vector3d s = svd.singularValues();
  if (!(s[2] > 1e-9 * s[0])) throw CalibrationError("circle fit: the points lie on a line");
  const Eigen::Vector3d def = svd.solve(b);
  Eigen::Vector2d c(-def[0] / 2, -def[1] / 2);
  double r = std::sqrt(std::max(0.0, c.squaredNorm() - def[2]));
  // Geometric refinement: minimise sum (|p - c| - r)^2 by Gauss-Newton; a few steps converge from Kasa's start.
  for (int it = 0; it < 20; ++it) {
    Eigen::MatrixXd J(n, 3);
    Eigen::VectorXd res(n);
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d d = (pts[i] - mean) - c;
      const double len = std::max(d.norm(), 1e-15);
      res[i] = len - r;
      J.row(i) << -d.x() / len, -d.y() / len, -1.0;
    }
    const Eigen::Vector3d step = J.colPivHouseholderQr().solve(-res);
    c += step.head<2>();
    r += step[2];
    if (step.norm() < 1e-12 * std::max(1.0, r)) break;
  }
  double ss = 0;
  for (const auto& p : pts) ss += std::pow(((p - mean) - c).norm() - r, 2);
  return {c + mean, r, std::sqrt(ss / n)};
}

double spread_off_line(const std::vector<Eigen::Vector3d>& pts) {
  if (pts.size() < 2) return 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  Eigen::MatrixXd M(pts.size(), 3);
  for (std::size_t i = 0; i < pts.size(); ++i) M.row(i) = (pts[i] - mean).transpose();
  const Eigen::Vector3d s = Eigen::JacobiSVD<Eigen::MatrixXd>(M).singularValues();
  return s[1] / std::sqrt(static_cast<double>(pts.size()));
}

RigidFit fit_rigid(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to,
                   double min_spread) {
  if (from.size() != to.size())
    throw CalibrationError("rigid fit: " + std::to_string(from.size()) + " camera features but " +
                           std::to_string(to.size()) + " robot positions");
  if (from.size() < 3)
    throw CalibrationError("rigid fit: " + std::to_string(from.size()) + " features, need at least 3 non-collinear");
  for (std::size_t i = 0; i < from.size(); ++i)
    if (!from[i].allFinite() || !to[i].allFinite())
      throw CalibrationError("rigid fit: feature " + std::to_string(i) + " has a non-finite coordinate");
  for (const auto* side : {&from, &to})
    if (spread_off_line(*side) < min_spread)
      throw CalibrationError("rigid fit: the " + std::string(side == &from ? "camera" : "robot") +
                             " features are collinear (spread off their line " +
                             std::to_string(spread_off_line(*side) * 1e3) + " mm < " +
                             std::to_string(min_spread * 1e3) + " mm); need 3 non-collinear");
  Eigen::Matrix3Xd src(3, from.size()), dst(3, to.size());
  for (std::size_t i = 0; i < from.size(); ++i) {
    src.col(i) = from[i];
    dst.col(i) = to[i];
  }
  RigidFit fit;
  fit.transform.matrix() = Eigen::umeyama(src, dst, false);
  double ss = 0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    const double r = (fit.transform * from[i] - to[i]).norm();
    fit.residuals.push_back(r);
    ss += r * r;
    if (r > fit.worst) {
      fit.worst = r;
      fit.worst_index = static_cast<int>(i);
    }
  }
  fit.rms = std::sqrt(ss / from.size());
  return fit;
}

double rotation_distance(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

namespace {

// Hand-eye needs relative motions with rotations about at least two different axes.
void check_rotation_diversity(const std::vector<Eigen::Isometry3d>& flange_to_base, double min_rotation) {
  std::vector<Eigen::Vector3d> axes;
  double largest = 0;
  for (std::size_t i = 0; i < flange_to_base.size(); ++i)
    for (std::size_t j = i + 1; j < flange_to_base.size(); ++j) {
      const Eigen::AngleAxisd aa(flange_to_base[i].linear().transpose() * flange_to_base[j].linear());
      largest = std::max(largest, aa.angle());
      if (aa.angle() >= min_rotation) axes.push_back(aa.axis());
    }
  if (axes.empty())
    throw CalibrationError("hand-eye: views without enough rotation: the largest rotation between two views is " +
                           std::to_string(largest * 180 / M_PI) + " deg, need " +
                           std::to_string(min_rotation * 180 / M_PI) + " deg");
  double widest = 0;
  for (const auto& a : axes)
    for (const auto& b : axes) widest = std::max(widest, std::acos(std::min(1.0, std::abs(a.dot(b)))));
  if (widest < min_rotation)
    throw CalibrationError(
        "hand-eye: views without enough rotation: every rotation between views is about one "
        "axis (axes within " +
        std::to_string(widest * 180 / M_PI) + " deg); tilt the camera about a second axis");
}

HandEyeMethod solve_one(const std::vector<Eigen::Isometry3d>& f2b, const std::vector<Eigen::Isometry3d>& t2c,
                        int cv_method, const std::string& name) {
  std::vector<cv::Mat> Rg, tg, Rt, tt;
  for (std::size_t i = 0; i < f2b.size(); ++i) {
    cv::Mat m;
    cv::eigen2cv(Eigen::Matrix3d(f2b[i].linear()), m);
    Rg.push_back(m.clone());
    cv::eigen2cv(Eigen::Vector3d(f2b[i].translation()), m);
    tg.push_back(m.clone());
    cv::eigen2cv(Eigen::Matrix3d(t2c[i].linear()), m);
    Rt.push_back(m.clone());
    cv::eigen2cv(Eigen::Vector3d(t2c[i].translation()), m);
    tt.push_back(m.clone());
  }
  cv::Mat R, t;
  cv::calibrateHandEye(Rg, tg, Rt, tt, R, t, static_cast<cv::HandEyeCalibrationMethod>(cv_method));
  HandEyeMethod out;
  out.name = name;
  Eigen::Matrix3d Re;
  Eigen::Vector3d te;
  cv::cv2eigen(R, Re);
  cv::cv2eigen(t, te);
  out.camera_to_flange.linear() = Re;
  out.camera_to_flange.translation() = te;
  // Residuals: the target's base pose through each view against their mean (rotation mean by the chordal
  // average, projected back onto SO(3)).
  std::vector<Eigen::Isometry3d> target_in_base;
  Eigen::Vector3d mean_t = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_R = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < f2b.size(); ++i) {
    target_in_base.push_back(f2b[i] * out.camera_to_flange * t2c[i]);
    mean_t += target_in_base.back().translation();
    sum_R += target_in_base.back().linear();
  }
  mean_t /= static_cast<double>(f2b.size());
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(sum_R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d mean_R = svd.matrixU() * svd.matrixV().transpose();
  if (mean_R.determinant() < 0) mean_R = -mean_R;
  double ss = 0;
  for (const auto& T : target_in_base) {
    out.view_translation.push_back((T.translation() - mean_t).norm());
    out.view_rotation.push_back(rotation_distance(T.linear(), mean_R));
    ss += out.view_translation.back() * out.view_translation.back();
    out.worst_translation = std::max(out.worst_translation, out.view_translation.back());
    out.worst_rotation = std::max(out.worst_rotation, out.view_rotation.back());
  }
  out.rms_translation = std::sqrt(ss / f2b.size());
  return out;
}

}  // namespace

double fit_camera_height(Eigen::Isometry3d& camera_to_flange, const std::vector<Eigen::Isometry3d>& flange_to_base,
                         const std::vector<std::vector<Eigen::Vector3d>>& centres_camera, double centre_height) {
  const Eigen::Vector3d axis = camera_to_flange.linear() * Eigen::Vector3d::UnitZ();  // optical axis, flange frame
  double num = 0, den = 0;  // least squares of the heights e + s a = 0 over every centre
  for (std::size_t i = 0; i < flange_to_base.size() && i < centres_camera.size(); ++i) {
    const double a = (flange_to_base[i].linear() * axis).z();  // height change per metre along the axis
    for (const Eigen::Vector3d& c : centres_camera[i]) {
      num += ((flange_to_base[i] * camera_to_flange * c).z() - centre_height) * a;
      den += a * a;
    }
  }
  if (!(den > 1e-6)) throw CalibrationError("hand-eye: no view looks down at the plate: its height cannot be fitted");
  const double s = -num / den;
  camera_to_flange.translation() += s * axis;
  return s;
}

HandEyeResult solve_eye_in_hand(const std::vector<Eigen::Isometry3d>& flange_to_base,
                                const std::vector<Eigen::Isometry3d>& target_to_camera, double min_rotation) {
  if (flange_to_base.size() != target_to_camera.size())
    throw CalibrationError("hand-eye: " + std::to_string(flange_to_base.size()) + " robot poses but " +
                           std::to_string(target_to_camera.size()) + " target poses");
  if (flange_to_base.size() < 3)
    throw CalibrationError("hand-eye: " + std::to_string(flange_to_base.size()) +
                           " views, need at least 3 (5 advised)");
  check_rotation_diversity(flange_to_base, min_rotation);
  HandEyeResult r;
  r.methods.push_back(solve_one(flange_to_base, target_to_camera, cv::CALIB_HAND_EYE_TSAI, "tsai"));
  r.methods.push_back(solve_one(flange_to_base, target_to_camera, cv::CALIB_HAND_EYE_PARK, "park"));
  const auto& a = r.methods[0].camera_to_flange;
  const auto& b = r.methods[1].camera_to_flange;
  r.disagreement_translation = (a.translation() - b.translation()).norm();
  r.disagreement_rotation = rotation_distance(a.linear(), b.linear());
  return r;
}

}  // namespace hg::calibration
