// Organized frames of one catalogue part for the scan tests (issue 23 §2): rendered by the scene renderer
// (sim/scene), then damaged here by independent, known models of what real scans show (dropout patches,
// table perforations, chips, an edge in shadow), and taken through the camera bridge's segmentation and
// the outline service's computation, as the processes do. Link hg_camera_scene, hg_camera_bridge,
// hg_outline_service.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "camera_bridge/camera_bridge.hpp"
#include "camera_bridge/segment.hpp"
#include "cell/cell.hpp"
#include "outline_service/outline_service.hpp"
#include "sim/partgen/shapes.hpp"
#include "sim/partgen/synth.hpp"
#include "sim/scene/scene.hpp"

namespace hg::test {

// Where the part lies on the table: bounding-box centre (x, y), turned by theta; flipped: upside down
// (mirrored about its own y axis).
struct Pose {
  double x = 0, y = 0, theta = 0;
  bool flipped = false;
};

// One catalogue part at `pose` on the presets' table (its tilt), noise seed `seed`.
inline sim::SceneSpec part_scene(const std::string& shape, const Pose& pose, std::uint64_t seed) {
  sim::SceneSpec spec = sim::scene_preset(shape);
  spec.seed = seed;
  sim::ScenePart& p = spec.parts.at(0);
  p.x = pose.x, p.y = pose.y, p.theta = pose.theta;
  if (pose.flipped) {
    partgen::PolygonWithHoles poly = partgen::make_shape(shape).polygon;
    auto mirror = [](partgen::Ring& ring) {
      for (auto& q : ring) q.x() = -q.x();
      std::reverse(ring.begin(), ring.end());  // mirroring turns the ring's direction: turn it back
    };
    mirror(poly.outer);
    for (auto& h : poly.holes) mirror(h);
    p.shape.clear();
    p.polygon = poly;
  }
  return spec;
}

// The frame source of the repeatability test: a part, a camera profile, a pose, a seed -> one frame. The
// renderer as it is by default; point it at other presets (realistic sensor effects) to test those.
using FrameSource =
    std::function<sim::RenderedFrame(const std::string& shape, const std::string& profile, const Pose&, std::uint64_t)>;

inline sim::RenderedFrame rendered_frame(const std::string& shape, const std::string& profile, const Pose& pose,
                                         std::uint64_t seed) {
  return sim::render(part_scene(shape, pose, seed), sim::camera_profile(profile), 0);
}

// The same frame without the renderer's mixed pixels (the same random stream: only those pixels differ).
inline sim::RenderedFrame unmixed_frame(const std::string& shape, const std::string& profile, const Pose& pose,
                                        std::uint64_t seed) {
  sim::CameraProfile prof = sim::camera_profile(profile);
  prof.flying_pixel_prob = 0;
  return sim::render(part_scene(shape, pose, seed), prof, 0);
}

// Pixel <-> table frame for a rendered frame.
struct FrameGeometry {
  explicit FrameGeometry(const sim::RenderedFrame& f) : f(f), table_from_camera(f.camera_from_table.inverse()) {}
  // The table-frame point at height z (0: the table) that pixel (c, r)'s ray meets.
  Eigen::Vector2d on_table(int c, int r, double z = 0) const {
    const Eigen::Vector3d d((c - f.intrinsics.cx) / f.intrinsics.fx, (r - f.intrinsics.cy) / f.intrinsics.fy, 1);
    const Eigen::Vector3d p = table_from_camera * ((f.table_offset + z) / f.table_normal.dot(d) * d);
    return p.head<2>();
  }
  // Pixel size on the table under the camera, metres.
  double pixel_size() const { return -f.table_offset / f.intrinsics.fx; }
  const sim::RenderedFrame& f;
  Eigen::Isometry3d table_from_camera;
};

// Damage models. Each sets depth counts of chosen pixels; none looks at what the bridge does.

// A patch of no return: every pixel whose table-frame point lies within `radius` of `centre` stretched by
// `elongation` along angle `angle` (1: a disc; a streak otherwise), restricted to the part's top face.
inline int punch_no_return(sim::RenderedFrame& f, const Eigen::Vector2d& centre, double radius, double elongation,
                           double angle) {
  const FrameGeometry g(f);
  const Eigen::Vector2d along(std::cos(angle), std::sin(angle)), across(-along.y(), along.x());
  int n = 0;
  for (int r = 0; r < f.depth.rows; ++r)
    for (int c = 0; c < f.depth.cols; ++c) {
      if (!f.truth_labels.ptr<std::uint8_t>(r)[c]) continue;
      const Eigen::Vector2d q = g.on_table(c, r) - centre;
      const double a = q.dot(along) / elongation, b = q.dot(across);
      if (a * a + b * b <= radius * radius) f.depth.ptr<std::uint16_t>(r)[c] = 0, ++n;
    }
  return n;
}

// Distance from point p to the part's nearest edge (outer or hole), metres; negative outside the steel.
inline double depth_into_steel(const partgen::PolygonWithHoles& poly, const Eigen::Vector2d& p) {
  double d = 1e9;
  auto ring_dist = [&](const partgen::Ring& ring) {
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
      const Eigen::Vector2d a = ring[j], b = ring[i], ab = b - a;
      const double t = std::clamp((p - a).dot(ab) / std::max(1e-18, ab.squaredNorm()), 0.0, 1.0);
      d = std::min(d, (a + t * ab - p).norm());
    }
  };
  ring_dist(poly.outer);
  for (const auto& h : poly.holes) ring_dist(h);
  return partgen::contains(poly, p.x(), p.y()) ? d : -d;
}

// `count` dropout patches inside the plate, each at least `margin` from every edge: discs and streaks of
// radius [r0, r1] (streaks up to 4 times longer), at random from `seed`. Returns the patches' centres.
inline std::vector<Eigen::Vector2d> punch_dropout(sim::RenderedFrame& f, std::uint64_t seed, int count, double r0,
                                                  double r1, double margin) {
  partgen::Rng rng(seed);
  const auto& poly = f.part_polygons.at(0);
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const auto& q : poly.outer)
    x0 = std::min(x0, q.x()), x1 = std::max(x1, q.x()), y0 = std::min(y0, q.y()), y1 = std::max(y1, q.y());
  std::vector<Eigen::Vector2d> centres;
  for (int tries = 0; int(centres.size()) < count && tries < 20000; ++tries) {
    const Eigen::Vector2d c(x0 + rng.uniform() * (x1 - x0), y0 + rng.uniform() * (y1 - y0));
    const double radius = r0 + rng.uniform() * (r1 - r0), elong = rng.uniform() < 0.5 ? 1.0 : 1 + 3 * rng.uniform();
    if (depth_into_steel(poly, c) < margin + radius * elong) continue;
    bool apart = true;  // patches apart, so each is one gap
    for (const auto& o : centres) apart &= (o - c).norm() > 2 * (margin + 4 * r1);
    if (!apart) continue;
    punch_no_return(f, c, radius, elong, rng.uniform() * M_PI);
    centres.push_back(c);
  }
  return centres;
}

// A perforated table: no return from holes of diameter `hole` on a square `pitch` (table frame), wherever
// the ray reaches the table (outside the part, and through its cut-outs).
inline void perforate_table(sim::RenderedFrame& f, double hole, double pitch) {
  const FrameGeometry g(f);
  for (int r = 0; r < f.depth.rows; ++r)
    for (int c = 0; c < f.depth.cols; ++c) {
      if (f.truth_labels.ptr<std::uint8_t>(r)[c]) continue;
      const Eigen::Vector2d q = g.on_table(c, r);
      const double dx = q.x() - pitch * std::round(q.x() / pitch), dy = q.y() - pitch * std::round(q.y() / pitch);
      if (dx * dx + dy * dy <= 0.25 * hole * hole) f.depth.ptr<std::uint16_t>(r)[c] = 0;
    }
}

// The longest straight edge of the part's outer ring: its ends (counter-clockwise order) and outward normal.
struct Edge {
  Eigen::Vector2d a, b, out;
};
inline Edge longest_outer_edge(const partgen::PolygonWithHoles& poly) {
  Edge e;
  double best = -1;
  const auto& ring = poly.outer;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const double len = (ring[i] - ring[j]).norm();
    if (len > best) best = len, e.a = ring[j], e.b = ring[i];
  }
  const Eigen::Vector2d t = (e.b - e.a).normalized();
  e.out = Eigen::Vector2d(t.y(), -t.x());  // right of the direction of travel: outside a ccw ring
  return e;
}

// The occlusion shadow of a triangulation sensor beside an outer edge: no return within `width` outside the
// edge, over the stretch [s0, s0 + length] along it from its first end: from the table there and from the
// side wall below the edge (every pixel whose ray passes the top face's level outside the edge). A mixed
// pixel needs returns from both surfaces: with the table in shadow the renderer's mixed pixels there (those
// that differ from `unmixed`, the frame rendered without them) return nothing either.
inline void shadow_beside(sim::RenderedFrame& f, const sim::RenderedFrame& unmixed, const Edge& e, double s0,
                          double length, double width) {
  const FrameGeometry g(f);
  const Eigen::Vector2d t = (e.b - e.a).normalized();
  const double top = f.part_thickness.at(0), px = g.pixel_size();
  for (int r = 0; r < f.depth.rows; ++r)
    for (int c = 0; c < f.depth.cols; ++c) {
      const Eigen::Vector2d q = g.on_table(c, r, top) - e.a;
      const double s = q.dot(t), d = q.dot(e.out);
      if (s < s0 || s > s0 + length || d > width || d <= -3 * px) continue;
      std::uint16_t& z = f.depth.ptr<std::uint16_t>(r)[c];
      if (d > 0 || z != unmixed.depth.ptr<std::uint16_t>(r)[c]) z = 0;
    }
}

// Chips on the table: `count` square blobs of side `side` at plate height, `gap` beyond the outer edge.
inline void chips_beside(sim::RenderedFrame& f, std::uint64_t seed, int count, double side, double gap) {
  const FrameGeometry g(f);
  partgen::Rng rng(seed);
  const auto& poly = f.part_polygons.at(0);
  const auto& ring = poly.outer;
  const double thick = f.part_thickness.at(0);
  std::vector<Eigen::Vector2d> centres;
  while (int(centres.size()) < count) {
    const std::size_t i = std::size_t(rng.uniform() * ring.size()), j = (i + 1) % ring.size();
    const Eigen::Vector2d t = (ring[j] - ring[i]), out = Eigen::Vector2d(t.y(), -t.x()).normalized();
    const Eigen::Vector2d c = ring[i] + rng.uniform() * t + out * (gap + side);
    if (depth_into_steel(poly, c) > -(gap + 0.4 * side)) continue;  // next to another edge, or in a notch
    bool apart = true;                                              // chips apart: each one fragment
    for (const auto& o : centres) apart &= (o - c).norm() > 3 * side;
    if (apart) centres.push_back(c);
  }
  const Eigen::Isometry3d& T = f.camera_from_table;
  for (int r = 0; r < f.depth.rows; ++r)
    for (int c = 0; c < f.depth.cols; ++c) {
      if (f.truth_labels.ptr<std::uint8_t>(r)[c]) continue;
      const Eigen::Vector2d q = g.on_table(c, r);
      for (const auto& m : centres)
        if (std::abs(q.x() - m.x()) <= side / 2 && std::abs(q.y() - m.y()) <= side / 2) {
          const Eigen::Vector3d p = T * Eigen::Vector3d(q.x(), q.y(), thick);
          f.depth.ptr<std::uint16_t>(r)[c] = std::uint16_t(std::lround(p.z() / f.intrinsics.depth_unit));
        }
    }
}

// The chain as the processes run it: segmentation, the plate cloud message, the outline service.
struct Scan {
  camera_bridge::Segmentation seg;
  hullgrind::plate_cloud_t cloud;
  hullgrind::outline_t outline;
  std::vector<hullgrind::part_pose_t> poses;
};
inline Scan scan(const sim::RenderedFrame& f, const camera_bridge::SegmentParams& sp,
                 const outline_service::ServiceOptions& so, const cv::Mat& intensity = cv::Mat()) {
  Scan s;
  s.seg = camera_bridge::segment(f.depth, f.intrinsics, sp, intensity);
  s.cloud = hullgrind::plate_cloud_t{};
  s.cloud.header.frame_id = "camera";
  camera_bridge::fill_plate_cloud(s.seg, s.cloud);
  outline_service::Computed c = outline_service::compute(s.cloud, so);
  s.outline = std::move(c.outline);
  s.poses = std::move(c.poses);
  return s;
}

// The service's options as a cell with the shipped outline rules gives them.
inline outline_service::ServiceOptions shipped_rules() {
  outline_service::ServiceOptions o;
  const cell::OutlineRules rules;
  o.min_part_area = rules.min_part_area;
  o.max_edge_dropout = rules.max_edge_dropout;
  o.max_edge_gap = rules.max_edge_gap;
  return o;
}

inline int count_loops(const hullgrind::outline_t& o, bool hole) {
  return int(std::count_if(o.loops.begin(), o.loops.end(), [&](const auto& l) { return l.hole == hole; }));
}

}  // namespace hg::test
