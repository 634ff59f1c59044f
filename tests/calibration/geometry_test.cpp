// Circle fit, rigid fit and hand-eye solve against transforms and circles the test generates itself,
// over many seeds, with noise; degenerate data refused with the reason.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "calibration/geometry.hpp"

using namespace hg::calibration;

namespace {

Eigen::Isometry3d random_pose(std::mt19937_64& rng, double reach) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
  T.translation() = reach * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return T;
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const CalibrationError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CircleFit, RecoversRandomCirclesFromNoisyArcs) {
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    SCOPED_TRACE(seed);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    const Eigen::Vector2d c(10 * u(rng), 10 * u(rng));  // far from the origin: conditioning
    const double r = 0.015 + 0.03 * std::abs(u(rng)), sigma = 0.0005 * std::abs(u(rng));
    const int n = 40 + static_cast<int>(200 * std::abs(u(rng)));
    std::normal_distribution<double> noise(0, sigma);
    std::vector<Eigen::Vector2d> pts;
    for (int i = 0; i < n; ++i) {
      const double t = 2 * M_PI * i / n + 0.01 * u(rng);
      const double rr = r + noise(rng);
      pts.push_back(c + rr * Eigen::Vector2d(std::cos(t), std::sin(t)));
    }
    const Circle fit = fit_circle(pts);
    // A full ring of n points with radial noise sigma: centre error ~ sigma sqrt(2 / n); 6 of those.
    const double bound = 6 * sigma * std::sqrt(2.0 / n) + 1e-9;
    EXPECT_LT((fit.centre - c).norm(), bound);
    EXPECT_LT(std::abs(fit.radius - r), 6 * sigma / std::sqrt(n) + 1e-9);
    EXPECT_LT(fit.rms, 2 * sigma + 1e-9);
  }
}

TEST(CircleFit, RefusesTooFewOrCollinearPoints) {
  EXPECT_NE(error_of([] { fit_circle({{0, 0}, {1, 1}}); }).find("need at least 3"), std::string::npos);
  EXPECT_NE(error_of([] { fit_circle({{0, 0}, {1, 1}, {2, 2}, {3, 3}}); }).find("on a line"), std::string::npos);
}

TEST(RigidFit, RecoversTheGeneratedTransformOverManySeeds) {
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    SCOPED_TRACE(seed);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    const Eigen::Isometry3d truth = random_pose(rng, 2.0);
    const double sigma = seed % 3 == 0 ? 0 : 0.0005 * std::abs(u(rng));
    std::normal_distribution<double> noise(0, sigma > 0 ? sigma : 1);
    const int n = 3 + static_cast<int>(seed % 20);
    std::vector<Eigen::Vector3d> from, to;
    for (int i = 0; i < n; ++i) {
      // Coplanar like the plate's holes on odd seeds, spread in 3-D on even ones.
      const Eigen::Vector3d p(0.2 * u(rng), 0.15 * u(rng), seed % 2 ? 0.0 : 0.1 * u(rng));
      from.push_back(p);
      to.push_back(truth * p +
                   (sigma > 0 ? Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) : Eigen::Vector3d::Zero()));
    }
    const double spread = spread_off_line(from);
    if (spread < 0.01) continue;  // refused; covered below
    const RigidFit fit = fit_rigid(from, to);
    // Error bounds of a least-squares fit: translation of the centroid ~ sigma / sqrt(n), rotation ~ sigma /
    // (spread sqrt(n)); 8 of those, evaluated at the farthest feature.
    double reach = 0;
    for (const auto& p : from) reach = std::max(reach, p.norm());
    const double bound = 8 * sigma * (1 + reach / spread) / std::sqrt(static_cast<double>(n)) * 2 + 1e-9;
    for (const auto& p : from) EXPECT_LT((fit.transform * p - truth * p).norm(), bound);
    if (sigma == 0) {
      EXPECT_LT(fit.worst, 1e-9);
    }
    EXPECT_LE(fit.rms, fit.worst);
  }
}

TEST(RigidFit, RefusesDegenerateFeatures) {
  const std::vector<Eigen::Vector3d> line{{0, 0, 0}, {0.1, 0, 0}, {0.2, 0.0001, 0}, {0.3, 0, 0}};
  const std::vector<Eigen::Vector3d> ok{{0, 0, 0}, {0.1, 0, 0}, {0, 0.1, 0}, {0.1, 0.1, 0}};
  EXPECT_NE(error_of([&] { fit_rigid(line, ok); }).find("camera features are collinear"), std::string::npos);
  EXPECT_NE(error_of([&] { fit_rigid(ok, line); }).find("robot features are collinear"), std::string::npos);
  EXPECT_NE(error_of([&] { fit_rigid({ok[0], ok[1]}, {ok[0], ok[1]}); }).find("need at least 3"), std::string::npos);
  EXPECT_NE(error_of([&] { fit_rigid(ok, {ok[0], ok[1], ok[2]}); }).find("4 camera features but 3"), std::string::npos);
  auto nan = ok;
  nan[2].y() = std::nan("");
  EXPECT_NE(error_of([&] { fit_rigid(nan, ok); }).find("feature 2 has a non-finite"), std::string::npos);
}

namespace {

struct HandEyeData {
  Eigen::Isometry3d X, target_in_base;
  std::vector<Eigen::Isometry3d> flange, target_in_camera;
};

// Views of a fixed target from random robot poses: flange * X * target_in_camera = target_in_base.
HandEyeData hand_eye_data(std::uint64_t seed, int views, double max_angle, double t_noise, double r_noise,
                          const Eigen::Vector3d* only_axis = nullptr) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> n(0, 1);
  HandEyeData d;
  d.X = random_pose(rng, 0.15);
  d.target_in_base = random_pose(rng, 1.0);
  for (int k = 0; k < views; ++k) {
    Eigen::Vector3d axis = only_axis ? *only_axis : Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const Eigen::Matrix3d R = Eigen::AngleAxisd(max_angle * u(rng), axis).toRotationMatrix();
    Eigen::Isometry3d cam_in_base = Eigen::Isometry3d::Identity();
    cam_in_base.linear() = R;
    cam_in_base.translation() = d.target_in_base.translation() + Eigen::Vector3d(0.2 * u(rng), 0.2 * u(rng), 0.8);
    d.flange.push_back(cam_in_base * d.X.inverse());
    Eigen::Isometry3d seen = cam_in_base.inverse() * d.target_in_base;
    const Eigen::Vector3d w(n(rng), n(rng), n(rng));
    seen.linear() = seen.linear() * Eigen::AngleAxisd(r_noise * w.norm(), w.normalized()).toRotationMatrix();
    seen.translation() += t_noise * Eigen::Vector3d(n(rng), n(rng), n(rng));
    d.target_in_camera.push_back(seen);
  }
  return d;
}

}  // namespace

TEST(HandEye, BothMethodsRecoverTheGeneratedCameraMount) {
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    SCOPED_TRACE(seed);
    const bool noisy = seed % 2 == 0;
    const HandEyeData d = hand_eye_data(seed, 8, 0.5, noisy ? 0.0002 : 0, noisy ? 0.0002 : 0);
    const HandEyeResult r = solve_eye_in_hand(d.flange, d.target_in_camera);
    ASSERT_EQ(r.methods.size(), 2u);
    for (const auto& m : r.methods) {
      SCOPED_TRACE(m.name);
      // 0.2 mm / 0.2 mrad of noise per view over 8 views, 0.8 m lever arm: a few mm at most.
      const double t_tol = noisy ? 0.004 : 1e-6, r_tol = noisy ? 0.004 : 1e-7;
      EXPECT_LT((m.camera_to_flange.translation() - d.X.translation()).norm(), t_tol);
      EXPECT_LT(rotation_distance(m.camera_to_flange.linear(), d.X.linear()), r_tol);
      ASSERT_EQ(m.view_translation.size(), 8u);
      if (!noisy) {
        EXPECT_LT(m.worst_translation, 1e-6);
      }
    }
    EXPECT_LT(r.disagreement_translation, noisy ? 0.008 : 1e-6);
  }
}

TEST(HandEye, RefusesViewsWithoutEnoughRotation) {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const HandEyeData one_axis = hand_eye_data(3, 8, 0.5, 0, 0, &z);
  EXPECT_NE(error_of([&] { solve_eye_in_hand(one_axis.flange, one_axis.target_in_camera); }).find("about one axis"),
            std::string::npos);
  const HandEyeData small = hand_eye_data(4, 8, 0.02, 0, 0);
  EXPECT_NE(error_of([&] { solve_eye_in_hand(small.flange, small.target_in_camera); }).find("without enough rotation"),
            std::string::npos);
  const HandEyeData two = hand_eye_data(5, 2, 0.5, 0, 0);
  EXPECT_NE(error_of([&] { solve_eye_in_hand(two.flange, two.target_in_camera); }).find("need at least 3"),
            std::string::npos);
}

// The table's height fixes the mount along the optical axis: a mount moved along its axis by a known amount is
// moved back (the centres are exact, from the true mount), 40 seeds of random mounts, views looking down
// within 25 deg and hole centres on a plate at a known height; a mount moved across the axis is left there.
TEST(HandEye, TheTablesHeightFixesTheMountAlongTheOpticalAxis) {
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE(seed);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = Eigen::AngleAxisd(M_PI * u(rng), Eigen::Vector3d(u(rng), u(rng), 1).normalized()).toRotationMatrix();
    X.translation() = Eigen::Vector3d(0.1 * u(rng), 0.1 * u(rng), 0.15 + 0.05 * u(rng));
    const double height = 0.3 * u(rng);
    std::vector<Eigen::Isometry3d> flange;
    std::vector<std::vector<Eigen::Vector3d>> centres;
    for (int v = 0; v < 6; ++v) {
      Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();  // camera -> base, looking down
      camera.linear() = (Eigen::AngleAxisd(0.4 * u(rng), Eigen::Vector3d::UnitX()) *
                         Eigen::AngleAxisd(0.4 * u(rng), Eigen::Vector3d::UnitY()) *
                         Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()))
                            .toRotationMatrix();
      camera.translation() = Eigen::Vector3d(0.6 + 0.1 * u(rng), 0.1 * u(rng), height + 0.9 + 0.1 * u(rng));
      flange.push_back(camera * X.inverse());
      centres.emplace_back();
      for (int h = 0; h < 6; ++h)
        centres.back().push_back(camera.inverse() * Eigen::Vector3d(0.6 + 0.2 * u(rng), 0.15 * u(rng), height));
    }
    const Eigen::Vector3d axis = X.linear() * Eigen::Vector3d::UnitZ();
    const double off = 0.002 * u(rng);
    Eigen::Isometry3d along = X;
    along.translation() += off * axis;
    EXPECT_NEAR(fit_camera_height(along, flange, centres, height), -off, 1e-9);
    EXPECT_LT((along.translation() - X.translation()).norm(), 1e-9);
    // Across the axis: the heights change little; the fit moves only along the axis.
    Eigen::Isometry3d across = X;
    const Eigen::Vector3d side = axis.unitOrthogonal();
    across.translation() += 0.001 * side;
    fit_camera_height(across, flange, centres, height);
    EXPECT_NEAR((across.translation() - X.translation()).dot(side), 0.001, 1e-9);
  }
  // Views that all look sideways cannot tell the height.
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();  // optical axis horizontal
  EXPECT_THROW(fit_camera_height(X, {Eigen::Isometry3d::Identity()}, {{Eigen::Vector3d(0, 0, 1)}}, 0),
               CalibrationError);
}
