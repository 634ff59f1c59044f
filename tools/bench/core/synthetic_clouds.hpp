// Synthetic clouds with ground truth for the automatic radius (docs/outline-auto-radius.md): scan grids
// with circular cut-outs, in-plane noise and random or clustered (3x3) dropout; and catalogue parts seen
// by a tilted pinhole camera (point spacing growing across the part). Used by hg-radius-table and the
// outline core's tests. Header-only; the tilted camera needs hg_partgen.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "outline_core/outline.hpp"

namespace hg::outline::synth {

struct PlateSpec {
  int W = 200, H = 100;                // grid columns, rows (unit spacing)
  std::vector<double> hole_diameters;  // circular cut-outs along the middle row, in spacings
  bool holes_on_grid_points = false;   // hole centres on grid points (else a random offset in the cell)
  double uniform_amp = 0;              // in-plane noise, uniform in [-amp, amp] per coordinate
  double gauss_sigma = 0;              // in-plane noise, Gaussian
  double dropout = 0;                  // fraction of points lost in all (random + clustered)
  double clustered = 0;                // part of `dropout` lost as separated 3x3 blocks
  std::uint64_t seed = 1;
};

struct PlateCloud {
  std::vector<Vec2> points;  // scan order
  std::vector<Vec2> hole_centres;
  std::vector<double> hole_diameters;
  int clusters = 0;  // 3x3 gaps placed
};

// A pixel is removed by a hole when its centre is strictly inside the circle.
inline PlateCloud make_plate(const PlateSpec& s) {
  std::mt19937_64 rng(s.seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::normal_distribution<double> gauss(0, 1);
  PlateCloud c;
  const int nh = static_cast<int>(s.hole_diameters.size());
  for (int k = 0; k < nh; ++k) {
    const double ox = s.holes_on_grid_points ? 0 : unit(rng), oy = s.holes_on_grid_points ? 0 : unit(rng);
    c.hole_centres.push_back({std::floor((k + 1.0) * s.W / (nh + 1)) + ox, std::floor(s.H / 2.0) + oy});
    c.hole_diameters.push_back(s.hole_diameters[k]);
  }
  std::vector<std::uint8_t> gone(std::size_t(s.W) * s.H, 0);  // 1 hole, 2 cluster, 3 margin of a cluster
  auto at = [&](int x, int y) -> std::uint8_t& { return gone[std::size_t(y) * s.W + x]; };
  for (int y = 0; y < s.H; ++y)
    for (int x = 0; x < s.W; ++x)
      for (int k = 0; k < nh; ++k) {
        const double dx = x - c.hole_centres[k].x, dy = y - c.hole_centres[k].y, r = c.hole_diameters[k] / 2;
        if (dx * dx + dy * dy < r * r) at(x, y) = 1;
      }
  // 3x3 clusters: apart from each other, from the holes and from the edges by at least 2 pixels.
  const int want = static_cast<int>(std::lround(s.clustered * s.W * s.H / 9));
  std::uniform_int_distribution<int> cx(3, s.W - 4), cy(3, s.H - 4);
  for (int tries = 0; c.clusters < want && tries < 200 * (want + 1); ++tries) {
    const int x0 = cx(rng), y0 = cy(rng);
    bool free = true;
    for (int y = y0 - 3; y <= y0 + 3 && free; ++y)
      for (int x = x0 - 3; x <= x0 + 3 && free; ++x) free = at(x, y) == 0;
    if (!free) continue;
    for (int y = y0 - 2; y <= y0 + 2; ++y)
      for (int x = x0 - 2; x <= x0 + 2; ++x) at(x, y) = std::abs(x - x0) <= 1 && std::abs(y - y0) <= 1 ? 2 : 3;
    ++c.clusters;
  }
  const double random_drop = std::max(0.0, s.dropout - s.clustered);
  for (int y = 0; y < s.H; ++y)
    for (int x = 0; x < s.W; ++x) {
      const bool drop = unit(rng) < random_drop;
      double nx = 0, ny = 0;
      if (s.uniform_amp > 0) nx = s.uniform_amp * (2 * unit(rng) - 1), ny = s.uniform_amp * (2 * unit(rng) - 1);
      if (s.gauss_sigma > 0) nx += s.gauss_sigma * gauss(rng), ny += s.gauss_sigma * gauss(rng);
      const std::uint8_t g = at(x, y);
      if (g == 1 || g == 2 || drop) continue;
      c.points.push_back({x + nx, y + ny});
    }
  return c;
}

// Even-odd point in polygon.
inline bool inside_polygon(const std::vector<Vec2>& ring, Vec2 p) {
  bool in = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Vec2 &a = ring[i], &b = ring[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)) in = !in;
  }
  return in;
}

// Loops scored against the plate's truth: outer loops, real holes found (a hole loop around the cut-out's
// centre), spurious holes (hole loops around no cut-out centre).
struct PlateScore {
  int outers = 0, found = 0, missed = 0, spurious = 0;
};
inline PlateScore score_plate(const PlateCloud& c, const std::vector<Loop>& loops) {
  PlateScore s;
  std::vector<int> hit(c.hole_centres.size(), 0);
  for (const Loop& L : loops) {
    if (!L.hole) {
      ++s.outers;
      continue;
    }
    bool real = false;
    for (std::size_t k = 0; k < c.hole_centres.size(); ++k)
      if (inside_polygon(L.points, c.hole_centres[k])) hit[k] = 1, real = true;
    s.spurious += !real;
  }
  for (int h : hit) (h ? s.found : s.missed)++;
  return s;
}

}  // namespace hg::outline::synth
