// The accuracy of the chain on the renderer's realistic presets (issue 23 §2 and §4), measured against the
// renderer's truth: one catalogue part with realistic_effects() at a pose, rendered with its intensity
// image, taken through the camera bridge's segmentation and the outline service's computation as the
// processes do (scan_frames.hpp), and the outline's loops carried into the table frame and compared with
// the generator's polygons there. Written independently of the bridge and the service: the truth is the
// renderer's polygons only. Used by realistic_test.cpp (the property) and realistic_table.cpp (the table of
// docs/BENCHMARKS-outline.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "scan_frames.hpp"

namespace hg::test {

// What `<shape>-realistic` renders (the same scene, every effect on), at `pose` and noise seed `seed`.
inline sim::RenderedFrame realistic_frame(const std::string& shape, const std::string& profile, const Pose& pose,
                                          std::uint64_t seed) {
  sim::SceneSpec spec = part_scene(shape, pose, seed);
  spec.effects = sim::scene_preset(shape + "-realistic").effects;
  return sim::render(spec, sim::camera_profile(profile), 0);
}

using Ring2 = std::vector<Eigen::Vector2d>;

inline double seg_dist(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

inline double rings_dist(const Eigen::Vector2d& p, const std::vector<Ring2>& rings) {
  double d = 1e300;
  for (const Ring2& r : rings)
    for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) d = std::min(d, seg_dist(p, r[j], r[i]));
  return d;
}

// The ring's points every `step` along it (its vertices included).
inline Ring2 densified(const Ring2& r, double step) {
  Ring2 out;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const Eigen::Vector2d a = r[i], b = r[(i + 1) % r.size()];
    const int n = std::max(1, int(std::ceil((b - a).norm() / step)));
    for (int k = 0; k < n; ++k) out.push_back(a + (b - a) * (double(k) / n));
  }
  return out;
}

inline double ring_area(const Ring2& r) {
  double a = 0;
  for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) a += r[j].x() * r[i].y() - r[i].x() * r[j].y();
  return 0.5 * a;
}

inline bool ring_contains(const Ring2& r, const Eigen::Vector2d& p) {
  bool in = false;
  for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
    if ((r[i].y() > p.y()) != (r[j].y() > p.y()) &&
        p.x() < r[j].x() + (r[i].x() - r[j].x()) * (p.y() - r[j].y()) / (r[i].y() - r[j].y()))
      in = !in;
  return in;
}

inline Eigen::Vector2d ring_centroid(const Ring2& r) {
  Eigen::Vector2d s = Eigen::Vector2d::Zero();
  double a = 0;
  for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) {
    const double w = r[j].x() * r[i].y() - r[i].x() * r[j].y();
    a += w, s += w * (r[j] + r[i]);
  }
  return s / (3 * a);
}

// One scan measured against the truth (lengths in metres, areas in m^2, table frame).
struct Accuracy {
  bool ok = false;  // the outline service gave loops
  int outer = 0, holes = 0;
  int truth_holes = 0, holes_found = 0, holes_extra = 0;  // found: true cut-outs with an outline hole on them
  double area = 0, truth_area = 0;
  double part_area = 0;            // what the service reports for the part (its part pose's area), m^2
  std::vector<double> hole_areas;  // outline hole matched to each true cut-out (0: none), in the truth's order
  std::vector<double> truth_hole_areas;
  double rms = 0, max = 0;  // outline vertices to the true edge; max: the symmetric Hausdorff distance
  int quality = 0;
  double edge_dropout = 0, largest_gap = 0;
  int dropout_filled = 0, fragments_dropped = 0;
  double area_error() const { return truth_area > 0 ? (area - truth_area) / truth_area : 0; }
  double part_area_error() const { return truth_area > 0 ? (part_area - truth_area) / truth_area : 0; }
};

// The outline's loops in the table frame (x, y of the plate-plane points).
inline std::vector<std::pair<bool, Ring2>> table_loops(const hullgrind::outline_t& o, const sim::RenderedFrame& f) {
  const Eigen::Isometry3d table_from_camera = f.camera_from_table.inverse();
  const Eigen::Vector3d origin(o.plane_origin), u(o.plane_u_axis), v(o.plane_v_axis);
  std::vector<std::pair<bool, Ring2>> out;
  for (const auto& l : o.loops) {
    Ring2 r;
    for (int i = 0; i < l.n; ++i) r.push_back((table_from_camera * (origin + l.u[i] * u + l.v[i] * v)).head<2>());
    out.push_back({l.hole, r});
  }
  return out;
}

inline Accuracy measure(const Scan& s, const sim::RenderedFrame& f) {
  Accuracy a;
  const auto& truth = f.part_polygons.at(0);
  std::vector<Ring2> truth_rings{Ring2(truth.outer.begin(), truth.outer.end())};
  for (const auto& h : truth.holes) truth_rings.emplace_back(h.begin(), h.end());
  a.truth_area = std::abs(ring_area(truth_rings[0]));
  for (std::size_t k = 1; k < truth_rings.size(); ++k) {
    a.truth_area -= std::abs(ring_area(truth_rings[k]));
    a.truth_hole_areas.push_back(std::abs(ring_area(truth_rings[k])));
  }
  a.truth_holes = int(truth.holes.size());
  a.hole_areas.assign(truth.holes.size(), 0);
  a.quality = s.outline.quality;
  a.edge_dropout = s.outline.edge_dropout_fraction, a.largest_gap = s.outline.largest_edge_gap;
  a.dropout_filled = s.cloud.dropout_filled, a.fragments_dropped = s.outline.fragments_dropped;
  if (s.outline.status != hullgrind::outline_t::STATUS_OK) return a;
  a.ok = true;
  if (!s.poses.empty()) a.part_area = s.poses.front().area;
  const auto loops = table_loops(s.outline, f);
  std::vector<Ring2> got;
  double sq = 0;
  int n = 0;
  for (const auto& [hole, r] : loops) {
    (hole ? a.holes : a.outer) += 1;
    a.area += hole ? -std::abs(ring_area(r)) : std::abs(ring_area(r));
    got.push_back(r);
    for (const auto& p : r) {
      const double d = rings_dist(p, truth_rings);
      sq += d * d, ++n, a.max = std::max(a.max, d);
    }
    if (!hole) continue;
    // A hole is a true cut-out's when its centroid lies in that cut-out; any other hole is extra.
    const Eigen::Vector2d c = ring_centroid(r);
    bool matched = false;
    for (std::size_t k = 1; k < truth_rings.size() && !matched; ++k)
      if (ring_contains(truth_rings[k], c)) matched = true, a.hole_areas[k - 1] = std::abs(ring_area(r));
    if (!matched) ++a.holes_extra;
  }
  a.rms = n ? std::sqrt(sq / n) : 0;
  for (double h : a.hole_areas) a.holes_found += h > 0;
  for (const Ring2& t : truth_rings)  // the other half of the Hausdorff distance: truth to outline
    for (const auto& p : densified(t, 5e-4)) a.max = std::max(a.max, rings_dist(p, got));
  return a;
}

// Poses of the repeatability property: three face up, three flipped, anywhere near the table's middle, any
// angle (from `seed`).
inline std::vector<Pose> six_poses(std::uint64_t seed) {
  partgen::Rng rng(seed);
  std::vector<Pose> p;
  for (int i = 0; i < 6; ++i)
    p.push_back({-0.12 + 0.24 * rng.uniform(), -0.08 + 0.16 * rng.uniform(), 2 * M_PI * rng.uniform(), i >= 3});
  return p;
}

// One scan of the realistic frame as the processes run it: the bridge's defaults, the frame's intensity
// image, the shipped cell's outline rules.
inline Accuracy realistic_scan(const std::string& shape, const std::string& profile, const Pose& pose,
                               std::uint64_t seed) {
  const sim::RenderedFrame f = realistic_frame(shape, profile, pose, seed);
  return measure(scan(f, camera_bridge::SegmentParams{}, shipped_rules(), f.intensity), f);
}

}  // namespace hg::test
