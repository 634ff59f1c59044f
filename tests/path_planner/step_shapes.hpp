// Shapes and measures shared by the planner steps' unit tests (<step>_test.cpp): polygons, circles, pixel
// staircases (partgen), distances to rings, corner turns of a smoothed ring.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <sstream>
#include <string_view>

#include "sim/partgen/synth.hpp"
#include "path_planner/io.hpp"
#include "path_planner/modifiers.hpp"
#include "path_planner/pipeline.hpp"
#include "robot_bridge/path.hpp"
#include "tests/path_planner/truth.hpp"

using namespace hg::path_planner;

namespace {

constexpr double kPi = 3.14159265358979323846;
inline double deg(double d) { return d * kPi / 180; }

using hg::path_planner::test::densify;
using hg::path_planner::test::turn;
inline double ring_dist(const Vec2& p, const Ring& r) { return hg::path_planner::test::ring_distance(p, r); }
// Distance from p to the nearest vertex of `r`.
inline double vertex_dist(const Vec2& p, const Ring& r) {
  double d = 1e300;
  for (const Vec2& v : r) d = std::min(d, (p - v).norm());
  return d;
}

inline Ring rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }
inline Ring rotated(const Ring& r, double a, const Vec2& c) {
  const Eigen::Rotation2Dd R(a);
  Ring o;
  for (const Vec2& p : r) o.push_back(c + R * (p - c));
  return o;
}
inline Ring circle(const Vec2& c, double R, int n, bool cw = false) {
  Ring o;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * kPi * k / n * (cw ? -1 : 1);
    o.emplace_back(c.x() + R * std::cos(t), c.y() + R * std::sin(t));
  }
  return o;
}

// A pixel staircase of a polygon (partgen::pixel_staircase): symmetric +-pitch/2 error, no inward bias (so
// tests of it turn edge compensation off).
inline Ring staircase(const Ring& poly, double pitch) { return hg::partgen::pixel_staircase(poly, pitch); }

// Turn at each detected corner of a smoothed ring, measured from the corner to the ring points `reach`
// away on both sides (the fitted straight runs).
inline std::vector<std::pair<Vec2, double>> corner_turns(const SmoothedRing& s, double reach) {
  std::vector<std::pair<Vec2, double>> out;
  const long n = long(s.points.size());
  for (long i = 0; i < n; ++i) {
    if (!s.corner[i]) continue;
    const Vec2 c = s.points[i];
    long b = i - 1, f = i + 1;
    while ((s.points[((b % n) + n) % n] - c).norm() < reach && i - b < n) --b;
    while ((s.points[f % n] - c).norm() < reach && f - i < n) ++f;
    out.push_back({c, turn(c - s.points[((b % n) + n) % n], s.points[f % n] - c)});
  }
  return out;
}

inline SmoothOptions no_compensation() {
  SmoothOptions o;
  o.edge_compensation = false;
  return o;
}

}  // namespace
