// The calibration plate through the product's pipeline (segmentation, outline core, circle fits) against
// the renderer's ground truth, and the whole eye-to-hand / eye-in-hand procedures on simulated sessions.
#include <random>

#include <gtest/gtest.h>

#include "calibration/sim.hpp"
#include "calibration/target.hpp"

using namespace hg::calibration;
namespace scene = hg::sim;

TEST(CalibrationPlate, PoseInTheCameraMatchesTheRenderersTruth) {
  const Drawing drawing = calibration_plate_drawing();
  ASSERT_GE(drawing.holes.size(), 4u);
  for (const std::string profile : {"pm806", "lsr-l"})
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      SCOPED_TRACE(profile + " seed " + std::to_string(seed));
      const sim::EyeInHandSession s = sim::eye_in_hand(profile, 2, 0, seed);
      for (const sim::View& v : s.views) {
        const PlateView seen = detect_plate(v.frame.depth, v.frame.intrinsics, drawing);
        EXPECT_EQ(seen.holes.size(), drawing.holes.size());
        for (const SeenHole& h : seen.holes) {
          const DrawingHole& d = drawing.holes[h.drawing_index];
          EXPECT_LT((h.centre_camera - v.plate_to_camera * d.centre).norm(), 0.001) << d.id;
          EXPECT_NEAR(h.diameter, d.diameter, 0.004) << d.id;
        }
        EXPECT_LT((seen.plate_to_camera.translation() - v.plate_to_camera.translation()).norm(), 0.001);
        EXPECT_LT(rotation_distance(seen.plate_to_camera.linear(), v.plate_to_camera.linear()), 0.2 * M_PI / 180);
      }
    }
}

TEST(CalibrationPlate, AnotherPartIsRefused) {
  scene::SceneSpec spec = scene::scene_preset("plate-hole-slot");  // two cut-outs, neither of the drawing's
  const scene::RenderedFrame f = scene::render(spec, scene::camera_profile("pm806"), 0);
  try {
    detect_plate(f.depth, f.intrinsics, calibration_plate_drawing());
    ADD_FAILURE() << "accepted";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("need at least 3"), std::string::npos) << e.what();
  }
}

namespace {
double angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return rotation_distance(a, b) * 180 / M_PI; }
}  // namespace

TEST(CalibrationProcedure, EyeToHandMeetsItsTargetOnSimulatedSessions) {
  const Drawing drawing = calibration_plate_drawing();
  for (const std::string profile : {"pm806", "lsr-l"})
    for (std::uint64_t seed = 11; seed <= 13; ++seed) {
      SCOPED_TRACE(profile + " seed " + std::to_string(seed));
      const sim::EyeToHandSession s = sim::eye_to_hand(profile, 3, 0.00005, seed);
      std::vector<Eigen::Vector3d> cam, base;
      for (std::size_t k = 0; k < s.views.size(); ++k) {
        const PlateView seen = detect_plate(s.views[k].frame.depth, s.views[k].frame.intrinsics, drawing);
        for (const SeenHole& h : seen.holes) {
          cam.push_back(h.centre_camera);
          base.push_back(s.tcp_at_hole[k][h.drawing_index]);
        }
      }
      const RigidFit fit = fit_rigid(cam, base);
      EXPECT_LT((fit.transform.translation() - s.camera_to_base_true.translation()).norm(), 0.0005);
      EXPECT_LT(angle_deg(fit.transform.linear(), s.camera_to_base_true.linear()), 0.05);
    }
}

TEST(CalibrationProcedure, EyeInHandMeetsItsTargetOnSimulatedSessions) {
  const Drawing drawing = calibration_plate_drawing();
  for (const std::string profile : {"pm806", "lsr-l"})
    for (std::uint64_t seed = 21; seed <= 22; ++seed) {
      SCOPED_TRACE(profile + " seed " + std::to_string(seed));
      const sim::EyeInHandSession s = sim::eye_in_hand(profile, 8, 0.00002, seed);
      std::vector<Eigen::Isometry3d> seen;
      for (const auto& v : s.views)
        seen.push_back(detect_plate(v.frame.depth, v.frame.intrinsics, drawing).plate_to_camera);
      const HandEyeResult r = solve_eye_in_hand(s.flange_to_base, seen);
      for (const auto& m : r.methods) {
        SCOPED_TRACE(m.name);
        EXPECT_LT((m.camera_to_flange.translation() - s.camera_to_flange_true.translation()).norm(), 0.001);
        EXPECT_LT(angle_deg(m.camera_to_flange.linear(), s.camera_to_flange_true.linear()), 0.1);
      }
    }
}
