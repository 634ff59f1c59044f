#include "calibration/target.hpp"

#include <cmath>

#include "outline_core/outline.hpp"
#include "sim/partgen/shapes.hpp"

namespace hg::calibration {

Drawing calibration_plate_drawing() {
  const partgen::Shape shape = partgen::make_shape("calibration-plate");
  Drawing d;
  d.thickness = shape.thickness;
  for (const auto& h : partgen::calibration_plate_holes())
    d.holes.push_back({h.id, Eigen::Vector3d(h.centre.x(), h.centre.y(), shape.thickness), h.diameter});
  return d;
}

namespace {

// Each hole loop circle-fitted, its centre in the camera frame.
std::vector<SeenHole> hole_circles(const PlatePlane& plane, const std::vector<HoleLoop>& loops) {
  std::vector<SeenHole> out;
  for (const HoleLoop& ring : loops) {
    if (ring.size() < 8) continue;
    const Circle c = fit_circle(ring);
    SeenHole h;
    h.centre_camera = plane.origin + c.centre.x() * plane.u_axis + c.centre.y() * plane.v_axis;
    h.diameter = 2 * c.radius;
    h.fit_rms = c.rms;
    h.points = static_cast<int>(ring.size());
    out.push_back(h);
  }
  return out;
}

// Nearest drawing diameter within tolerance, each drawing hole used once (the drawing's diameters differ by
// more than twice the tolerance, so the nearest one is unambiguous).
std::vector<SeenHole> match_by_diameter(std::vector<SeenHole> seen, const Drawing& d, double tol) {
  std::vector<SeenHole> matched(d.holes.size());
  for (SeenHole& h : seen) {
    int best = -1;
    for (std::size_t k = 0; k < d.holes.size(); ++k)
      if (std::abs(h.diameter - d.holes[k].diameter) <= tol &&
          (best < 0 || std::abs(h.diameter - d.holes[k].diameter) < std::abs(h.diameter - d.holes[best].diameter)))
        best = static_cast<int>(k);
    if (best < 0 || matched[best].drawing_index >= 0) continue;
    h.drawing_index = best;
    matched[best] = h;
  }
  std::vector<SeenHole> out;
  for (const auto& h : matched)
    if (h.drawing_index >= 0) out.push_back(h);
  return out;
}

}  // namespace

std::vector<HoleLoop> hole_loops(const std::vector<float>& u, const std::vector<float>& v) {
  std::vector<outline::Vec2> pts(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) pts[i] = {u[i], v[i]};
  const outline::Result res = outline::compute_outline(std::move(pts));
  std::vector<HoleLoop> out;
  for (const outline::Loop& loop : res.loops) {
    if (!loop.hole) continue;
    HoleLoop ring;
    for (const auto& p : loop.points) ring.emplace_back(p.x, p.y);
    out.push_back(std::move(ring));
  }
  return out;
}

PlateView plate_from_loops(const PlatePlane& plane, const std::vector<HoleLoop>& loops, const Drawing& drawing,
                           const DetectOptions& options) {
  const std::vector<SeenHole> all = hole_circles(plane, loops);
  PlateView view;
  view.holes = match_by_diameter(all, drawing, options.diameter_tolerance);
  if (view.holes.size() < 3)
    throw CalibrationError(std::to_string(all.size()) + " hole loops found, " + std::to_string(view.holes.size()) +
                           " match a diameter of the drawing; need at least 3");
  std::vector<Eigen::Vector3d> from, to;
  for (const auto& h : view.holes) {
    from.push_back(drawing.holes[h.drawing_index].centre);
    to.push_back(h.centre_camera);
  }
  view.pattern_fit = fit_rigid(from, to);
  if (view.pattern_fit.worst > options.pattern_tolerance)
    throw CalibrationError("the holes' pattern is not the drawing's: hole " +
                           drawing.holes[view.holes[view.pattern_fit.worst_index].drawing_index].id + " is " +
                           std::to_string(view.pattern_fit.worst * 1e3) + " mm off");
  view.plate_to_camera = view.pattern_fit.transform;
  view.text = std::to_string(view.holes.size()) + " of " + std::to_string(drawing.holes.size()) +
              " holes, pattern rms " + std::to_string(view.pattern_fit.rms * 1e3) + " mm";
  return view;
}

PlateView detect_plate(const cv::Mat& depth, const camera::Intrinsics& in, const Drawing& drawing,
                       const DetectOptions& options) {
  const camera_bridge::Segmentation seg = camera_bridge::segment(depth, in, options.segment);
  if (seg.status != camera_bridge::SegmentStatus::Ok) throw CalibrationError("no plate in the frame: " + seg.text);
  return plate_from_loops({seg.origin, seg.u_axis, seg.v_axis}, hole_loops(seg.u, seg.v), drawing, options);
}

}  // namespace hg::calibration
