// Rings for the smoothing stages' tests (smooth_<stage>_test.cpp), built from exact geometry with the
// vertex indices of their features known: polygons sampled with a vertex on every corner, a square with one
// filleted corner, a stadium; isotropic Gaussian noise on top.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "path_planner/smooth/stages.hpp"

namespace hg::path_planner::stage_test {

using smooth::Primitive;
constexpr double kPi = 3.14159265358979323846;

// The polygon's edges divided into equal steps of at most `spacing`; corner[k] is the index of poly[k].
struct Sampled {
  Ring ring;
  std::vector<long> corner;
};
inline Sampled sample_polygon(const Ring& poly, double spacing) {
  Sampled s;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Vec2 a = poly[k], b = poly[(k + 1) % poly.size()];
    const int steps = int(std::ceil((b - a).norm() / spacing));
    s.corner.push_back(long(s.ring.size()));
    for (int i = 0; i < steps; ++i) s.ring.push_back(a + (b - a) * (double(i) / steps));
  }
  return s;
}

// Square [0, side]^2, counter-clockwise from (0, 0), its corner at (side, 0) rounded by a fillet of radius R
// (R = 0: sharp), sampled at `spacing` along the edge. arc_first / arc_last: the arc's first and last vertex.
struct FilletedSquare {
  Ring ring;
  long arc_first = 0, arc_last = 0;
  Vec2 centre;  // the fillet's centre
};
inline FilletedSquare filleted_square(double side, double R, double spacing) {
  FilletedSquare f;
  f.centre = Vec2(side - R, R);
  auto straight = [&](const Vec2& a, const Vec2& b) {
    const int steps = int(std::ceil((b - a).norm() / spacing));
    for (int i = 0; i < steps; ++i) f.ring.push_back(a + (b - a) * (double(i) / steps));
  };
  straight(Vec2(0, 0), Vec2(side - R, 0));
  f.arc_first = long(f.ring.size());
  if (R > 0) {
    const int steps = int(std::ceil(R * kPi / 2 / spacing));
    for (int i = 0; i < steps; ++i) {
      const double a = -kPi / 2 + kPi / 2 * i / steps;
      f.ring.push_back(f.centre + R * Vec2(std::cos(a), std::sin(a)));
    }
  }
  f.arc_last = long(f.ring.size());  // (side, R): the first vertex after the arc
  straight(Vec2(side, R), Vec2(side, side));
  straight(Vec2(side, side), Vec2(0, side));
  straight(Vec2(0, side), Vec2(0, 0));
  return f;
}

// Stadium: two straights of length `length` and two half circles of radius R, counter-clockwise, starting at
// the first straight's start (a tangent point). tangent[k]: the index where piece k (line, arc, line, arc)
// starts.
struct Stadium {
  Ring ring;
  std::vector<long> start;
  Vec2 centre[2];
};
inline Stadium stadium(double length, double R, double spacing) {
  Stadium s;
  s.centre[0] = Vec2(length, R), s.centre[1] = Vec2(0, R);
  const int line_steps = int(std::ceil(length / spacing)), arc_steps = int(std::ceil(kPi * R / spacing));
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? 1 : -1;
    const Vec2 from = side == 0 ? Vec2(0, 0) : Vec2(length, 2 * R);
    s.start.push_back(long(s.ring.size()));
    for (int i = 0; i < line_steps; ++i) s.ring.push_back(from + Vec2(sign * length * i / line_steps, 0));
    s.start.push_back(long(s.ring.size()));
    for (int i = 0; i < arc_steps; ++i) {
      const double a = -kPi / 2 + side * kPi + kPi * i / arc_steps;
      s.ring.push_back(s.centre[side] + R * Vec2(std::cos(a), std::sin(a)));
    }
  }
  return s;
}

inline Ring with_noise(Ring r, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, sigma);
  for (Vec2& p : r) p += Vec2(g(rng), g(rng));
  return r;
}

// Options for a ring sampled at the pitch with no pixel staircase: no edge compensation.
inline SmoothOptions exact_options() {
  SmoothOptions o;
  o.edge_compensation = false;
  return o;
}

// The TLS line over vertices a..b as a piece's primitive.
inline Primitive line_piece(const smooth::Unrolled& u, long a, long b) {
  const smooth::Line l = smooth::fit_line(u, a, b);
  Primitive p;
  p.centre = l.centre, p.dir = l.dir, p.first = a, p.last = b;
  return p;
}

}  // namespace hg::path_planner::stage_test
