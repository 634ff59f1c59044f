// A catalogue part (sim/partgen) seen by a tilted pinhole camera: the point spacing on the plate grows
// from the near to the far side. Every pixel ray is cast onto the plate plane (z = 0); the pixel is a
// point when the ray hits the part (pixel centre inside, partgen::contains). Points are in the plate
// plane, scan order. For hg-radius-table --tilted and the outline core's local-mode tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "outline_core/outline.hpp"
#include "sim/partgen/shapes.hpp"

namespace hg::outline::synth {

class TiltedCamera {
 public:
  // Camera at (x_mid, y_near - offset, height) aimed at the part's bounding-box centre.
  TiltedCamera(const partgen::Box& box, double offset, double height) {
    const double xm = (box.min_x + box.max_x) / 2, ym = (box.min_y + box.max_y) / 2;
    c_ = {xm, box.min_y - offset, height};
    fwd_ = (Eigen::Vector3d(xm, ym, 0) - c_).normalized();
    right_ = Eigen::Vector3d(1, 0, 0);
    up_ = right_.cross(fwd_).normalized();  // image up, towards the far side
  }
  // Image coordinates (tangent-plane units) of a plate point, and back (ray cast onto z = 0).
  Eigen::Vector2d project(const partgen::Vec2& p) const {
    const Eigen::Vector3d q = Eigen::Vector3d(p.x(), p.y(), 0) - c_;
    return {q.dot(right_) / q.dot(fwd_), q.dot(up_) / q.dot(fwd_)};
  }
  partgen::Vec2 cast(double u, double v) const {
    const Eigen::Vector3d d = fwd_ + u * right_ + v * up_;
    const double t = -c_.z() / d.z();
    return {c_.x() + t * d.x(), c_.y() + t * d.y()};
  }
  // The footprint of a pixel of pitch delta at plate point p: its longer side (the local spacing along
  // the worse direction) and sqrt of its area.
  void footprint(const partgen::Vec2& p, double delta, double& longer, double& root_area) const {
    const Eigen::Vector2d uv = project(p);
    const double e = delta * 1e-3;
    const partgen::Vec2 du = (cast(uv.x() + e, uv.y()) - cast(uv.x() - e, uv.y())) / (2e-3);
    const partgen::Vec2 dv = (cast(uv.x(), uv.y() + e) - cast(uv.x(), uv.y() - e)) / (2e-3);
    longer = std::max(du.norm(), dv.norm());
    root_area = std::sqrt(std::fabs(du.x() * dv.y() - du.y() * dv.x()));
  }

 private:
  Eigen::Vector3d c_, fwd_, right_, up_;
};

struct TiltedView {
  std::vector<Vec2> points;
  partgen::PolygonWithHoles truth;  // the placed part, in the same plane coordinates
  TiltedCamera camera{partgen::Box{0, 0, 1, 1}, 0, 1};
  double pitch = 0;                          // pixel pitch in image units
  double spacing_near = 0, spacing_far = 0;  // sqrt(footprint area) at the nearest / farthest box edge
  double spacing(const partgen::Vec2& p, bool longer_side) const {
    double l, a;
    camera.footprint(p, pitch, l, a);
    return longer_side ? l : a;
  }
};

// The part seen (camera above the near edge of its bounding box, at the height found by bisection) so
// that the spacing (sqrt of the pixel footprint) at the far edge of its bounding box is
// `gradient` times that at the near edge, with about `target_points` points; pixel jitter (uniform,
// +-jitter pixels in the image) gives noise that scales with the local spacing.
inline TiltedView tilted_view(const partgen::Shape& shape, double gradient, double target_points, double jitter,
                              std::uint64_t seed) {
  TiltedView view;
  view.truth = partgen::single_part_scene(shape, 0.05).parts[0].placed;
  const partgen::Box box = partgen::bounding_box(view.truth);
  const double L = box.max_y - box.min_y, xm = (box.min_x + box.max_x) / 2;
  // The camera stands above the near edge, aimed at the centre; the lower it is, the steeper the gradient.
  auto ratio = [&](double height) {
    const TiltedCamera cam(box, 0, height);
    double l, a_near, a_far;
    cam.footprint({xm, box.min_y}, 1e-3, l, a_near);
    cam.footprint({xm, box.max_y}, 1e-3, l, a_far);
    return a_far / a_near;
  };
  double lo = 0.02 * L, hi = 1000 * L;
  for (int i = 0; i < 80; ++i) (ratio(std::sqrt(lo * hi)) > gradient ? lo : hi) = std::sqrt(lo * hi);
  view.camera = TiltedCamera(box, 0, std::sqrt(lo * hi));
  auto render = [&](double delta) {
    std::vector<Vec2> pts;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-jitter, jitter);
    double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
    for (const partgen::Vec2& p : view.truth.outer) {
      const Eigen::Vector2d q = view.camera.project(p);
      u0 = std::min(u0, q.x()), u1 = std::max(u1, q.x()), v0 = std::min(v0, q.y()), v1 = std::max(v1, q.y());
    }
    for (long j = long(std::ceil(v1 / delta)) + 1; j >= long(std::floor(v0 / delta)) - 1; --j)
      for (long i = long(std::floor(u0 / delta)) - 1; i <= long(std::ceil(u1 / delta)) + 1; ++i) {
        const double ju = jitter > 0 ? u(rng) : 0, jv = jitter > 0 ? u(rng) : 0;
        const partgen::Vec2 x = view.camera.cast((double(i) + ju) * delta, (double(j) + jv) * delta);
        if (partgen::contains(view.truth, x.x(), x.y())) pts.push_back({x.x(), x.y()});
      }
    return pts;
  };
  double delta = 1e-2;
  for (int it = 0; it < 3; ++it) {
    const std::size_t n = render(delta).size();
    delta *= std::sqrt(std::max<double>(1.0, double(n)) / target_points);
  }
  view.pitch = delta;
  view.points = render(delta);
  double l;
  view.camera.footprint({xm, box.min_y}, delta, l, view.spacing_near);
  view.camera.footprint({xm, box.max_y}, delta, l, view.spacing_far);
  return view;
}

}  // namespace hg::outline::synth
