// The sensor and scene effects of SensorEffects (docs/scene.md), between the renderer's noise-free
// geometry and the frame it returns. Internal to hg_camera_scene (scene.cpp calls it).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "sim/scene/scene.hpp"

namespace hg::sim::detail {

// A part's bow (SensorEffects::warp): a paraboloid about its bounding-box centre c, w(p) =
// 4 s (|p - c|^2 - r0^2) / (1 m)^2, s the sagitta over a 1 m chord; r0 = 0 when the edges rise (s > 0, the
// plate rests on its middle), r0 = the farthest vertex when the middle rises (s < 0, it rests on its rim).
struct Warp {
  double s = 0;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  double r0sq = 0;
  double max_height = 0;  // largest w over the part
  double height(double x, double y) const {
    const double dx = x - c.x(), dy = y - c.y();
    return 4 * s * (dx * dx + dy * dy - r0sq);
  }
  Eigen::Vector2d gradient(double x, double y) const { return 8 * s * Eigen::Vector2d(x - c.x(), y - c.y()); }
};
std::vector<Warp> warps_of(const std::vector<partgen::PolygonWithHoles>& polys, double sagitta);

// Depth along the optical axis where the ray (a, b, 1) meets the top face of a part of thickness t bowed by
// `warp` (fixed-point iteration: the bow's slope is small).
double top_depth(const RenderedFrame& out, const Warp& warp, double t, double a, double b);

// Whether table point (x, y) falls in an opening of the table's top (a perforation hole or a slat gap).
bool table_opening(const TableSpec& table, double x, double y);
// Probability that a pixel with mean return S detects it: Q(N, N threshold / S), N speckle cells.
double detection_probability(double mean_return, double threshold, int cells);

// From the noise-free depth `z_true` (metres, CV_64F) and labels of `out`: the table's pattern and debris,
// the rounded edges, incidence, speckle, specular lobes, the baseline's shadow, mixed pixels, then the
// profile's noise and dropout; sets out.depth (and out.intensity when asked). Deterministic per
// (spec.seed, frame_index).
void apply_effects(const SceneSpec& spec, const CameraProfile& prof, std::uint64_t frame_index,
                   const std::vector<Warp>& warps, cv::Mat& z_true, RenderedFrame& out);

}  // namespace hg::sim::detail
