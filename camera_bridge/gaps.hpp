// What the organized frame says about the plate's gaps and its edge (docs/cameras.md, "Dropout, cut-outs and
// the edge"), after segment() has found the parts and their top planes. Part of hg_camera_segment; called
// by segment() only (exposed for it, not an interface of the bridge).
//
// A gap is a connected set of pixels without a cloud point that the points of one part enclose. It is a
// cut-out when the frame shows the laser went through the steel: returns at table height or below on a
// tenth of it (the table, or the webs of a perforated table, seen through the hole); or, with nothing
// there at all, when it is wider than SegmentParams::dropout_width and, where the source has an intensity
// image, dark (no light came back from it). Every other gap is dropout: no return from steel that is
// there. It is filled with points on the part's top plane, so no consumer takes it for a hole.
//
// Saturation: a pixel without depth whose intensity is at full scale (255 in an 8-bit image, 65535 in a
// 16-bit one) received more light than the sensor can decode: a specular glint from a surface that is
// there. Inside a part's mask (segment() adds such pixels to it, so a glint across a plate does not cut
// it in two, nor one across its edge bite into it) it is steel and filled like dropout, wherever it lies,
// edge included; the table beside it, which returned, then shows where the plate ends.
//
// The edge: along each part's outer contour (without the kept mixed pixels, Segmentation::mixed, each of which
// saw the table), a pixel is seen when a pixel just outside it returned (the table, a mixed pixel, a side
// wall: the drop from plate to table is in the frame), or when the no-return band beside it ends, across the
// edge, in a return from the table within thickness x SegmentParams::shadow_tan (the baseline's shadow beside
// a lit top face, which cannot hide steel at top height: counted in Segmentation::edge_shadow_length); in
// dropout or shadow when neither (off the image counts as none): there the scan does not show where the
// plate ends.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "camera_bridge/segment.hpp"

namespace hg::camera_bridge {

struct PlatePlanes {
  Eigen::Vector3d table_normal;  // camera frame, n . p = offset, towards the camera
  double table_offset = 0;
  Eigen::Vector3d top_normal;  // the parts' top planes: top_normal . p = top_offset[k]
  std::vector<double> top_offset;
};

// CV_8UC1, 255 where `depth` has no return and `intensity` (CV_8UC1 or CV_16UC1 of the depth's size) is
// saturated; all zero without such an image.
cv::Mat saturated_no_return(const cv::Mat& depth, const cv::Mat& intensity);

// Fills the dropout gaps of `out` (points merged in scan order, Segmentation::filled set for them) and
// measures the outer edge; sets the evidence fields of `out`. `intensity`: empty, or CV_8UC1 / CV_16UC1 of
// the depth image's size (any other is ignored).
void fill_gaps_and_assess_edge(const cv::Mat& depth, const cv::Mat& intensity, const camera::Intrinsics& in,
                               const PlatePlanes& planes, const SegmentParams& params, Segmentation& out);

}  // namespace hg::camera_bridge
