// From one depth frame to the plate's points: table plane, part mask, plate top plane, points in scan order.
// Library hg_camera_segment: OpenCV + Eigen only (no LCM), so tests call it directly.
//
// Plate-plane axes (what plate_cloud_t carries): normal n points from the plate towards the camera;
// u is the camera's x axis projected into the plane and normalised; v = n x u. Then (u, v, n) is
// right-handed (u x v = n), and for a camera looking straight down u runs along image columns (right)
// and v against image rows (up in the image), so a plate seen from above keeps its handedness: an
// outline that is counter-clockwise on the table is counter-clockwise in (u, v).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "camera_types/depth_source.hpp"

namespace hg::camera_bridge {

struct SegmentParams {
  // Table plane: RANSAC over the frame, or a calibrated plane (camera frame, n . p = offset, n towards the
  // camera) refined by least squares on the points within ransac_threshold of it.
  bool calibrated_plane = false;
  Eigen::Vector3d plane_normal = Eigen::Vector3d(0, 0, -1);
  double plane_offset = -1.5;
  int ransac_iterations = 150;
  double ransac_threshold = 0.004;  // metres: table inlier distance
  int sample_stride = 4;            // RANSAC and refit use every stride-th pixel in both directions
  double min_table_fraction = 0.2;  // of the sampled valid points; fewer table inliers: BAD_FRAME
  // Part mask: height above the table within [min_height, max_height].
  double min_height = 0.003;
  double max_height = 0.040;
  int open_size = 2;        // square kernel of the opening against specks (pixels); 0 or 1: none
  int close_size = 3;       // square kernel of the closing of pin holes (pixels); 0 or 1: none
  double min_area = 0.002;  // m^2 on the table; smaller components are ignored
  bool all_parts = false;   // false: the largest part only
  // A mask pixel becomes a cloud point only when its height is within this of the fitted top plane
  // (drops mixed pixels half way down an edge and side-wall pixels). 0: automatic, 4 sigma of the
  // top-plane residuals but at least 1 mm.
  double top_tolerance = 0;
  // A pixel beside the top face but off its plane is a mixed pixel kept as steel when its depth fraction
  // between table and top ((z_table - z) / (z_table - z_top) along its ray) is at least this (segment.cpp,
  // classify()); above 1: none kept.
  double mixed_fraction = 0.5;
  // Width of a pixel's footprint on the scene, in pixels (optics, spot or matching window): how far beyond
  // the edge a mixed pixel with its centre on the steel sees, which sets the fraction it shows where the
  // camera sees the side wall (segment.cpp, steel_centre_fraction()).
  double footprint_pixels = 2.0;
  std::uint64_t ransac_seed = 12345;
  // Gaps inside a part (gaps.hpp): with nothing in the frame to say the steel is cut there, a gap at most
  // this wide (metres, the widest circle that fits in it) is dropout and filled; a wider one stays a hole.
  double dropout_width = 0.010;
  // The largest tangent of the angle between the emitter's ray and the camera's at the plate (the baseline
  // over the mount height: lsr-l's 0.35 m at 2 m is 0.18): a no-return band beside the edge that ends in a
  // table return within thickness x this is the baseline's shadow beside a lit top face, which shows where
  // the plate ends (gaps.hpp, "The edge"). 0: every band without a return beside it counts as dropout.
  double shadow_tan = 0.25;
  bool fill_dropout = true;  // false: gaps are left as they are (the edge is assessed either way)
};

enum class SegmentStatus { Ok, NoPart, BadFrame };

struct Segmentation {
  SegmentStatus status = SegmentStatus::BadFrame;
  std::string text;  // why, when not Ok
  // Table plane in the camera frame: table_normal . p = table_offset, normal towards the camera.
  Eigen::Vector3d table_normal = Eigen::Vector3d::Zero();
  double table_offset = 0;
  double table_rms = 0;  // metres, RMS distance of the table inliers used in the refit
  // Plate top plane: p = origin + u * u_axis + v * v_axis, normal = u_axis x v_axis (towards the camera).
  Eigen::Vector3d origin = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d u_axis = Eigen::Vector3d::Zero(), v_axis = Eigen::Vector3d::Zero();
  double thickness = 0;  // metres: top plane above the table (at the origin)
  int num_parts = 0;
  cv::Mat labels;  // CV_8UC1: 0 none, k + 1 part k (the cleaned mask, before the top tolerance)
  // Points in scan-line (row-major image) order.
  std::vector<float> u, v;
  std::vector<std::int16_t> part;
  std::vector<std::int32_t> pixel;   // source pixel index row * width + col
  std::vector<std::uint8_t> filled;  // 1: a point on the top plane filling dropout, not a measured one
  cv::Mat mixed;  // CV_8UC1: 255 at the pixels of the points that are mixed pixels kept as steel (their
                  // footprint saw the table too)
  std::size_t size() const { return u.size(); }
  // What the organized frame showed (gaps.hpp): dropout patches filled (single missing pixels, which leave
  // no hole in an outline, are filled but not counted), gaps kept as cut-outs, and the outer edge.
  int dropout_filled = 0;
  double dropout_filled_area = 0;  // m^2 on the top plane
  int cutouts = 0;
  double edge_length = 0;          // m, the parts' outer contours
  double edge_dropout_length = 0;  // m of it in dropout or shadow
  double largest_edge_gap = 0;     // m, the longest such stretch
  double edge_shadow_length = 0;   // m of the edge counted seen as a bounded shadow (SegmentParams::shadow_tan)
  double edge_dropout_fraction() const { return edge_length > 0 ? edge_dropout_length / edge_length : 0; }
};

// Empty when the frame is usable; otherwise why not (wrong size or type, no valid pixel, bad intrinsics).
std::string frame_defect(const cv::Mat& depth, const camera::Intrinsics& in);

// Throws std::invalid_argument on bad parameters; never throws on frame content (a defective frame gives
// status BadFrame with the reason).
// `intensity`: the source's intensity image of the same frame (CV_8UC1 or CV_16UC1, the depth's size), or
// empty when it has none; it lets a wide gap with no depth but with light coming back count as dropout.
Segmentation segment(const cv::Mat& depth, const camera::Intrinsics& in, const SegmentParams& params,
                     const cv::Mat& intensity = cv::Mat());

// Deprojection used by segment(): camera-frame point of pixel (col, row) at depth z (metres).
inline Eigen::Vector3d deproject(const camera::Intrinsics& in, double col, double row, double z) {
  return {(col - in.cx) / in.fx * z, (row - in.cy) / in.fy * z, z};
}

}  // namespace hg::camera_bridge
