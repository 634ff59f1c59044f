// Unit tests of frames: plate to robot base, turning the normal up, the flip mirror, against independent (analytic)
// expectations.
#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include "path_planner/io.hpp"
#include "tests/common/cell_file.hpp"
#include "tests/path_planner/step_shapes.hpp"

TEST(PathPlannerFrame, KnownPointsIntoTheBaseFrame) {
  // Camera 1.2 m above the base at x = 0.5, looking down (roll = pi): camera x = base x, camera y = -base y.
  const Eigen::Isometry3d cam = pose_from_xyz_rpy(Vec3(0.5, 0, 1.2), Vec3(kPi, 0, 0));
  // Plate 1 m in front of the camera, u = camera x, v = camera -y, normal toward the camera.
  const Plane plane{Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1)};
  const Eigen::Isometry3d T = plate_to_base(plane, cam);
  // plate (0.1, 0.2, 0) -> camera (0.1, -0.2, 1) -> base (0.6, 0.2, 0.2)
  EXPECT_LT((T * Vec3(0.1, 0.2, 0) - Vec3(0.6, 0.2, 0.2)).norm(), 1e-12);
  EXPECT_LT((T * Vec3(0, 0, 0.05) - Vec3(0.5, 0, 0.25)).norm(), 1e-12);  // plate up = base up
  const std::vector<PlateWaypoint> p = {
      {Vec3(0.1, 0.2, 0), tool_orientation(Vec2(1, 0), Vec2(0, -1), 0), 0.1, kGrind, 0}};
  const auto b = to_base(p, T);
  EXPECT_LT((b[0].orientation.toRotationMatrix().col(2) - Vec3(0, 0, -1)).norm(), 1e-12);  // tool points down
  EXPECT_LT((b[0].orientation.toRotationMatrix().col(0) - Vec3(1, 0, 0)).norm(), 1e-12);
}

// The planner's camera-to-base is the cell file's calibration, exactly (17 digits); a cell whose rotation is
// not orthonormal, or a bad planner value, is a ConfigError.
TEST(PathPlannerFrame, CameraToBaseIsTheCellsCalibration) {
  const Eigen::Isometry3d ref = pose_from_xyz_rpy(Vec3(0.3, -0.2, 1.1), Vec3(3.0, 0.1, -0.4));
  const std::string cell =
      hg::test::write_test_cell(testing::TempDir() + "/pp_frame_cell.yaml", [&](hg::cell::Cell& c) {
        c.calibration.camera_to_base = ref;
        c.home = Vec3(0.4, 0.1, 0.3);
      });
  auto lookup = [&](std::map<std::string, std::string> over) {
    over.emplace("cell", cell);
    return lookup_from(over, hg::runtime::Config());
  };
  const PlannerConfig a = config_from(lookup({}));
  EXPECT_EQ(a.camera_to_base.matrix(), ref.matrix());
  EXPECT_EQ(a.home, Vec3(0.4, 0.1, 0.3));
  std::ifstream in(cell);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::size_t row = text.find("camera-to-base:") + std::string("camera-to-base:").size();
  const std::size_t first = text.find('[', row) + 1;
  text.replace(first, text.find(',', first) - first, "2");  // r00 = 2: not a rotation
  std::ofstream(testing::TempDir() + "/pp_frame_bad.yaml") << text;
  try {
    config_from(lookup({{"cell", testing::TempDir() + "/pp_frame_bad.yaml"}}));
    ADD_FAILURE() << "a cell with a non-rigid camera-to-base was taken";
  } catch (const hg::runtime::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("pp_frame_bad.yaml: calibration.camera-to-base: rotation part"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(config_from(lookup({{"step", "-1"}})), hg::runtime::ConfigError);
}

TEST(PathPlannerFrame, NormalPointingDownIsTurnedUpWithoutMovingThePlate) {
  const Eigen::Isometry3d cam = pose_from_xyz_rpy(Vec3(0.5, 0, 1.2), Vec3(kPi, 0, 0));
  OutlineInput in;
  in.plane = {Vec3(0.01, 0.02, 1), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};  // normal away from the camera
  in.loops = {{false, rect(0, 0, 0.2, 0.1)}};
  auto to3 = [](const Plane& pl, const Vec2& p) { return Vec3(pl.origin + p.x() * pl.u + p.y() * pl.v); };
  std::vector<Vec3> before;
  for (const Vec2& p : in.loops[0].points) before.push_back(to3(in.plane, p));
  normalize_up(in, cam);
  EXPECT_GT((cam.linear() * in.plane.normal).z(), 0);
  EXPECT_GT(in.plane.u.cross(in.plane.v).dot(in.plane.normal), 0);
  EXPECT_GT(signed_area(in.loops[0].points), 0);  // still canonical
  for (const Vec2& p : in.loops[0].points) {
    double best = 1e9;
    for (const Vec3& q : before) best = std::min(best, (to3(in.plane, p) - q).norm());
    EXPECT_LT(best, 1e-15);
  }
}

TEST(PathPlannerFrame, FlipMirrorsAcrossThePrincipalAxisThroughTheCentroid) {
  // 0.4 x 0.2 plate with a 0.04 x 0.04 hole centred at (0.2, 0.05): symmetric about x = 0.2, so the
  // principal axis is exactly x.
  Ring hole = rect(0.18, 0.03, 0.22, 0.07);
  std::reverse(hole.begin(), hole.end());
  const std::vector<Loop> loops = {{false, rect(0, 0, 0.4, 0.2)}, {true, hole}};
  const double A = 0.08 - 0.0016;
  const double cx = 0.2, cy = (0.08 * 0.1 - 0.0016 * 0.05) / A;
  const AreaMoments m = area_moments(loops);
  EXPECT_NEAR(m.area, A, 1e-15);
  EXPECT_NEAR(m.centroid.x(), cx, 1e-12);
  EXPECT_NEAR(m.centroid.y(), cy, 1e-12);
  EXPECT_NEAR(std::abs(m.major_axis.x()), 1, 1e-12);
  const auto f = mirror_for_flip(loops);
  EXPECT_LT(signed_area(f[1].points), 0);  // holes stay clockwise
  EXPECT_GT(signed_area(f[0].points), 0);
  Vec2 hc = Vec2::Zero();
  for (const Vec2& p : f[1].points) hc += p / 4;
  // Mirror of (0.1, 0.05) across the axis through the centroid.
  const Eigen::Matrix2d Rf = 2 * m.major_axis * m.major_axis.transpose() - Eigen::Matrix2d::Identity();
  EXPECT_LT((hc - (m.centroid + Rf * (Vec2(0.2, 0.05) - m.centroid))).norm(), 1e-12);
  EXPECT_NEAR(hc.x(), 0.2, 1e-12);
  EXPECT_NEAR(hc.y(), 2 * cy - 0.05, 1e-12);
  EXPECT_NEAR(area_moments(f).area, A, 1e-12);
}
