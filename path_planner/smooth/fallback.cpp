// The smoothing's safety net: a smoothed ring that strays from the outline it came from is replaced by a
// local smoothing of that outline.
//
// The primitive fits need runs of at least two residual windows (smooth/segment.cpp) between corners and a
// noise level measured over five windows. On a coarse outline (a slot 8 pixels wide, a few dozen vertices
// all round) neither holds: the noise estimate takes in the shape itself, the misfit threshold grows to
// several pixels, and a slot comes out as a rectangle, or collapses. Such a ring is recognised by the
// distance of the outline's vertices from it: the vertices are the outermost pixel centres, within about
// one pitch of the edge plus their noise, so a run of vertices farther than 1.2 units (pitch, or the vertex
// spacing when noise spreads the vertices) plus 4 vertex noise levels from the smoothed ring (smooth.cpp
// sets the band) means a shape the fits did not follow.
#include "path_planner/smooth/stages.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <unordered_map>

namespace hg::path_planner::smooth {

namespace {

double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

// The closed ring's segments bucketed in square cells of side `cell`: every segment within `cell` of a
// point is in the point's cell or one of its eight neighbours.
struct SegmentGrid {
  double cell;
  std::unordered_map<long long, std::vector<int>> cells;
  static long long key(long long x, long long y) { return x * 2000003LL + y; }
  long long at(double v) const { return (long long)std::floor(v / cell); }
  SegmentGrid(const Ring& r, double cell_size) : cell(cell_size) {
    const int m = int(r.size());
    for (int i = 0; i < m; ++i) {
      const Vec2 &a = r[i], &b = r[(i + 1) % m];
      const int steps = 1 + int((b - a).norm() / (0.5 * cell));
      long long last = LLONG_MIN;
      for (int s = 0; s <= steps; ++s) {
        const Vec2 q = a + (b - a) * (double(s) / steps);
        const long long k = key(at(q.x()), at(q.y()));
        if (k != last) cells[k].push_back(i), last = k;
      }
    }
  }
  double distance(const Ring& r, const Vec2& p) const {
    double best = INFINITY;
    const int m = int(r.size());
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy) {
        const auto it = cells.find(key(at(p.x()) + dx, at(p.y()) + dy));
        if (it == cells.end()) continue;
        for (int i : it->second) best = std::min(best, segment_distance(p, r[i], r[(i + 1) % m]));
      }
    return best;
  }
};

}  // namespace

bool strays_from(const Ring& outline, const Ring& smoothed, double band) {
  if (smoothed.size() < 3) return true;
  const SegmentGrid grid(smoothed, band);
  const int n = int(outline.size());
  // Single vertices beyond the band are noise; three in a row are a shape the smoothed ring misses.
  int run = 0, first_run = -1;
  for (int i = 0; i < n + 2; ++i) {
    const bool far = grid.distance(smoothed, outline[i % n]) > band;
    run = far ? run + 1 : 0;
    if (i < n && !far && first_run < 0) first_run = i;
    if (run >= 3) return true;
  }
  return first_run < 0;  // every vertex far
}

SmoothedRing local_smoothing(const SmoothContext& c, const Ring& ring) {
  // A Gaussian of one vertex along the ring: the staircase's pixel-to-pixel steps average out (their
  // period is two to a few vertices), shapes of a few pixels and more are kept; arcs shrink by about
  // (1.5 spacings)^2 / (2 radius), a fraction of a pitch for radii above a few pitches.
  const int n = int(ring.size()), k = 4;
  const double s = 1.0;
  Ring mean(n);
  for (int i = 0; i < n; ++i) {
    Vec2 sum = Vec2::Zero();
    double w = 0;
    for (int d = -k; d <= k; ++d) {
      const double g = std::exp(-0.5 * d * d / (s * s));
      sum += g * ring[((i + d) % n + n) % n];
      w += g;
    }
    mean[i] = sum / w;
  }
  // Edge compensation as emit's: out of the material (right of travel) by pitch/2 x max(|t_x|, |t_y|).
  SmoothedRing out{Ring(n), std::vector<std::uint8_t>(n, 0)};
  for (int i = 0; i < n; ++i) {
    const Vec2 d = mean[(i + 2) % n] - mean[(i + n - 2) % n];
    const Vec2 t = d.norm() > 0 ? Vec2(d / d.norm()) : Vec2(1, 0);
    const double shift = c.bias_scale * 0.5 * c.pitch * std::max(std::abs(t.x()), std::abs(t.y()));
    out.points[i] = mean[i] + shift * Vec2(t.y(), -t.x());
  }
  return out;
}

}  // namespace hg::path_planner::smooth
