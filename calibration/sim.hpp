// Simulated calibration sessions on the virtual camera (sim/scene/scene.*): the calibration plate in
// the cell, the robot poses a procedure commands, and the depth frames the camera sees there. The truth
// returned comes from the renderer's ground truth (camera_from_table and the part's placement), never from
// an estimator. Library hg_calibration_sim (tools and tests only).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sim/scene/scene.hpp"

namespace hg::calibration::sim {

struct View {
  hg::sim::RenderedFrame frame;
  Eigen::Isometry3d plate_to_camera = Eigen::Isometry3d::Identity();  // renderer's truth
};

// Renders the calibration plate at the wanted pose in the camera frame. The renderer places parts on a
// (tilted) table under a camera at its mount height, so the wanted pose is decomposed into table tilt,
// mount height and the part's placement on the table. Throws std::invalid_argument when the pose cannot be
// shown (plate facing away, outside the view).
View render_plate(const hg::sim::CameraProfile& profile, const Eigen::Isometry3d& plate_to_camera, std::uint64_t seed,
                  std::uint64_t frame_index);

struct EyeToHandSession {
  std::vector<View> views;  // fixed camera; one per plate placement (several frames averaged per placement)
  std::vector<std::vector<Eigen::Vector3d>> tcp_at_hole;  // [placement][drawing hole]: TCP touched, base frame
  Eigen::Isometry3d camera_to_base_true = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Isometry3d> plate_to_base_true;
};

// Camera fixed over the table at the profile's mount height; `placements` plate positions; TCP readings with
// `tcp_noise` metres of Gaussian error per axis (pointer tip on the hole centre).
EyeToHandSession eye_to_hand(const std::string& profile, int placements, double tcp_noise, std::uint64_t seed);

struct EyeInHandSession {
  std::vector<View> views;
  std::vector<Eigen::Isometry3d> flange_to_base;  // robot poses as reported (with repeatability noise)
  Eigen::Isometry3d camera_to_flange_true = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d plate_to_base_true = Eigen::Isometry3d::Identity();
};

// The eye-in-hand procedure's plan: the flange poses to command (true poses that put the camera over the
// plate), the camera's true mount and the plate's true place.
struct EyeInHandPlan {
  std::vector<Eigen::Isometry3d> flange_to_base;
  Eigen::Isometry3d camera_to_flange_true = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d plate_to_base_true = Eigen::Isometry3d::Identity();
};
EyeInHandPlan eye_in_hand_plan(const std::string& profile, int views, std::uint64_t seed);

// What the flange camera sees with the flange at `flange_to_base` (the robot's true pose). The returned view's
// plate_to_camera is the renderer's truth; `rendered_flange` (if given) receives the flange pose that truth
// implies (equal to flange_to_base up to the renderer's placement rounding).
View render_from_flange(const std::string& profile, const EyeInHandPlan& plan, const Eigen::Isometry3d& flange_to_base,
                        std::uint64_t seed, std::uint64_t frame_index, Eigen::Isometry3d* rendered_flange = nullptr);

// Camera on the flange; `views` robot poses around the plate (tilts up to ~15 deg about two axes, turns
// about the optical axis); reported poses with `pose_noise` metres / `pose_noise` x 0.1 rad of error.
EyeInHandSession eye_in_hand(const std::string& profile, int views, double pose_noise, std::uint64_t seed);

// The cell's fixed truths used by both sessions (the table in the base frame, the camera on the flange).
Eigen::Isometry3d table_to_base();
Eigen::Isometry3d camera_to_flange();

}  // namespace hg::calibration::sim
