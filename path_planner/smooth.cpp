// Step 1: de-noise the outline's pixel staircase without rounding real corners.
//
// The outline core's loops run through the outermost pixel centres of the plate, so they zig-zag by up to
// one pixel pitch and sit on average half a pitch inside the true edge. Here:
//  1. corners: at every vertex, lines are fitted (PCA) to the loop one corner-scale behind and ahead; the
//     turn between them is a corner candidate when it exceeds corner_angle AND doubling the scale does
//     not grow the turn by half (an arc's turn grows with the scale, a corner's does not); the local
//     maximum within one scale wins;
//  2. each corner is re-placed at the intersection of lines fitted a little away from it on both sides
//     (the alpha shape cuts a corner off by about a pixel), so its angle comes from long straight runs; a
//     candidate whose lines meet farther from it than the alpha shape can cut a corner of that angle
//     (1.5 pitch / sin(interior angle / 2)) is a tight arc, not a corner;
//  3. between corners, each vertex is replaced by a local least-squares fit (a parabola in the frame of
//     the local PCA line when the window reaches both ways, the line itself near a corner);
//  4. edge compensation moves each point outward by half the pitch times max(|t_x|, |t_y|) for the local
//     tangent t: the expected gap between the outermost pixel centres and an edge of that direction,
//     assuming the pixel grid is aligned with the plate's u, v axes (top-down camera).
#include "path_planner/pipeline.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace hg::path_planner {

double estimate_pitch(const std::vector<Loop>& loops) {
  std::vector<double> lengths;
  std::size_t edges = 0;
  double longest_loop = 0;
  const double tan10 = std::tan(10.0 * M_PI / 180.0);
  for (const Loop& l : loops) {
    const std::size_t n = l.points.size();
    edges += n;
    longest_loop = std::max(longest_loop, ring_length(l.points));
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 d = l.points[(i + 1) % n] - l.points[i];
      const double a = std::abs(d.x()), b = std::abs(d.y());
      if (std::min(a, b) <= tan10 * std::max(a, b) && std::max(a, b) > 0) lengths.push_back(d.norm());
    }
  }
  // A staircase has many short axis-parallel steps; a hand-drawn polygon (few long edges) has no pitch.
  // In-plane noise tilts the steps: then the median of all edges stands in.
  if (lengths.size() < 16 || lengths.size() * 4 < edges) {
    lengths.clear();
    for (const Loop& l : loops)
      for (std::size_t i = 0; i < l.points.size(); ++i)
        lengths.push_back((l.points[(i + 1) % l.points.size()] - l.points[i]).norm());
    if (lengths.size() < 64) return 0;
  }
  auto mid = lengths.begin() + lengths.size() / 2;
  std::nth_element(lengths.begin(), mid, lengths.end());
  return *mid <= longest_loop / 200 ? *mid : 0;
}

namespace {

struct LineFit {
  Vec2 centre = Vec2::Zero();
  Vec2 dir = Vec2::UnitX();  // unit, along travel
  int count = 0;
};

// Unwrapped access: index j may be any integer; arc position grows by the loop length per turn.
struct Walk {
  const Ring& p;
  std::vector<double> s;  // s[i]: arc length at vertex i
  double total = 0;
  int n = 0;
  explicit Walk(const Ring& ring) : p(ring), n(int(ring.size())) {
    s.resize(n);
    for (int i = 0; i < n; ++i) {
      s[i] = total;
      total += (p[(i + 1) % n] - p[i]).norm();
    }
  }
  int wrap(long j) const { return int(((j % n) + n) % n); }
  const Vec2& at(long j) const { return p[wrap(j)]; }
  double S(long j) const {
    const long w = (j >= 0) ? j / n : -((-j + n - 1) / n);
    return s[wrap(j)] + double(w) * total;
  }
};

// PCA line through vertices j0..j1 (unwrapped, inclusive), oriented from j0 toward j1.
LineFit fit_line(const Walk& w, long j0, long j1) {
  LineFit f;
  f.count = int(j1 - j0 + 1);
  if (f.count < 2) return f;
  const Vec2 ref = w.at(j0);
  Vec2 c = Vec2::Zero();
  for (long j = j0; j <= j1; ++j) c += w.at(j) - ref;
  c /= f.count;
  double sxx = 0, sxy = 0, syy = 0;
  for (long j = j0; j <= j1; ++j) {
    const Vec2 d = w.at(j) - ref - c;
    sxx += d.x() * d.x();
    sxy += d.x() * d.y();
    syy += d.y() * d.y();
  }
  // Major axis of the 2x2 covariance in closed form.
  const double theta = 0.5 * std::atan2(2 * sxy, sxx - syy);
  Vec2 dir(std::cos(theta), std::sin(theta));
  if (dir.dot(w.at(j1) - w.at(j0)) < 0) dir = -dir;
  f.centre = ref + c;
  f.dir = dir;
  return f;
}

double turn(const Vec2& a, const Vec2& b) { return std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b)); }

// Outward (away from material, i.e. right of travel) normal of a travel direction.
Vec2 right_of(const Vec2& t) { return Vec2(t.y(), -t.x()); }

double edge_bias(const Vec2& t, double pitch) { return 0.5 * pitch * std::max(std::abs(t.x()), std::abs(t.y())); }

// Turn at vertex i between lines fitted over [S(i)-scale, S(i)] and [S(i), S(i)+scale].
double turn_at(const Walk& w, long i, double scale) {
  const double si = w.S(i);
  long b = i, f = i;
  while (i - b < w.n / 3 && w.S(b - 1) >= si - scale) --b;
  while (f - i < w.n / 3 && w.S(f + 1) <= si + scale) ++f;
  if (i - b < 2 || f - i < 2) return 0;
  return turn(fit_line(w, b, i).dir, fit_line(w, i, f).dir);
}

}  // namespace

SmoothedRing smooth_ring(const Ring& ring, double pitch, const SmoothOptions& o) {
  SmoothedRing out;
  const int n = int(ring.size());
  if (n < 8 || !(pitch > 0)) {
    out.points = ring;
    out.corner.assign(ring.size(), 0);
    return out;
  }
  const Walk w(ring);
  const double scale = o.corner_scale_pitches * pitch;
  const double window = o.window_pitches * pitch;
  const double gap = 1.5 * pitch;          // skip the alpha shape's cut-off at a corner
  const double corner_fit = 15.0 * pitch;   // length of the lines that re-place a corner
  const double bias_scale = o.edge_compensation ? 1.0 : 0.0;

  // 1. corner candidates and non-maximum suppression.
  std::vector<double> t1(n, 0);
  std::vector<std::uint8_t> cand(n, 0);
  for (int i = 0; i < n; ++i) {
    t1[i] = turn_at(w, i, scale);
    if (std::abs(t1[i]) >= o.corner_angle) {
      const double t2 = turn_at(w, i, 2 * scale);
      cand[i] = std::abs(t2) < 1.5 * std::abs(t1[i]);
    }
  }
  std::vector<long> corners;
  for (int i = 0; i < n; ++i) {
    if (!cand[i]) continue;
    bool best = true;
    const double si = w.S(i);
    for (long j = i - 1; best && i - j < n / 2 && si - w.S(j) <= scale; --j)
      if (std::abs(t1[w.wrap(j)]) > std::abs(t1[i])) best = false;
    for (long j = i + 1; best && j - i < n / 2 && w.S(j) - si <= scale; ++j)
      if (std::abs(t1[w.wrap(j)]) >= std::abs(t1[i])) best = false;
    if (best) corners.push_back(i);
  }

  // 2. corner positions from lines fitted away from the corner.
  const int nc = int(corners.size());
  std::vector<Vec2> corner_pos(nc);
  std::vector<std::uint8_t> is_corner(nc, 1);
  for (int k = 0; k < nc; ++k) {
    const long c = corners[k];
    const long prev = nc > 1 ? corners[(k + nc - 1) % nc] - (k == 0 ? n : 0) : c - n;
    const long next = nc > 1 ? corners[(k + 1) % nc] + (k == nc - 1 ? n : 0) : c + n;
    const double sc = w.S(c);
    // back: S in [max(sc - gap - corner_fit, S(prev) + gap), sc - gap]
    long b1 = c;
    while (b1 > prev && w.S(b1) > sc - gap) --b1;
    long b0 = b1;
    while (b0 - 1 > prev && w.S(b0 - 1) >= std::max(sc - gap - corner_fit, w.S(prev) + gap)) --b0;
    long f0 = c;
    while (f0 < next && w.S(f0) < sc + gap) ++f0;
    long f1 = f0;
    while (f1 + 1 < next && w.S(f1 + 1) <= std::min(sc + gap + corner_fit, w.S(next) - gap)) ++f1;
    corner_pos[k] = w.at(c);
    if (b1 - b0 < 2 || f1 - f0 < 2) continue;  // too short to refine: keep the vertex
    const LineFit lb = fit_line(w, b0, b1), lf = fit_line(w, f0, f1);
    const Vec2 pb = lb.centre + bias_scale * edge_bias(lb.dir, pitch) * right_of(lb.dir);
    const Vec2 pf = lf.centre + bias_scale * edge_bias(lf.dir, pitch) * right_of(lf.dir);
    const double den = lb.dir.x() * lf.dir.y() - lb.dir.y() * lf.dir.x();
    if (std::abs(den) < std::sin(10.0 * M_PI / 180.0)) {
      is_corner[k] = 0;
      continue;
    }
    const Vec2 d = pf - pb;
    const double tb = (d.x() * lf.dir.y() - d.y() * lf.dir.x()) / den;
    const Vec2 x = pb + tb * lb.dir;
    // The alpha shape cuts a true corner by at most about two pitches (acute ones the most); lines fitted
    // beside a tight arc that passed the detector meet several pitches outside it: not a corner.
    const double interior = M_PI - std::abs(turn(lb.dir, lf.dir));
    if ((x - w.at(c)).norm() <= 1.5 * pitch / std::sin(interior / 2)) corner_pos[k] = x;
    else is_corner[k] = 0;
  }
  {
    std::vector<long> kept;
    std::vector<Vec2> kept_pos;
    for (int k = 0; k < nc; ++k)
      if (is_corner[k]) kept.push_back(corners[k]), kept_pos.push_back(corner_pos[k]);
    corners.swap(kept);
    corner_pos.swap(kept_pos);
  }

  const int kept = int(corners.size());
  // 3. + 4. smoothing of the vertices between corners, with edge compensation.
  auto smooth_vertex = [&](long j, double lo, double hi) {
    // Window: vertices within `window` of j and inside (lo, hi) (arc positions, unwrapped).
    const double sj = w.S(j);
    long a = j, b = j;
    while (j - a < n / 2 && w.S(a - 1) > lo && sj - w.S(a - 1) <= window) --a;
    while (b - j < n / 2 && w.S(b + 1) < hi && w.S(b + 1) - sj <= window) ++b;
    if (b - a < 2) return w.at(j);
    const LineFit lf = fit_line(w, a, b);
    const Vec2 nrm = right_of(lf.dir);
    const bool two_sided = sj - w.S(a) >= window / 2 && w.S(b) - sj >= window / 2 && b - a >= 4;
    const Vec2 q = w.at(j) - lf.centre;
    const double xi = q.dot(lf.dir);
    double eta = 0, slope = 0;
    if (two_sided) {
      Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
      Eigen::Vector3d r = Eigen::Vector3d::Zero();
      for (long k = a; k <= b; ++k) {
        const Vec2 d = w.at(k) - lf.centre;
        const double x = d.dot(lf.dir), y = d.dot(nrm);
        const Eigen::Vector3d phi(1, x, x * x);
        A += phi * phi.transpose();
        r += phi * y;
      }
      const Eigen::Vector3d coef = A.ldlt().solve(r);
      if (coef.allFinite()) {
        eta = coef[0] + coef[1] * xi + coef[2] * xi * xi;
        slope = coef[1] + 2 * coef[2] * xi;
      }
    }
    const Vec2 tangent = (lf.dir + slope * nrm).normalized();
    return Vec2(lf.centre + xi * lf.dir + eta * nrm + bias_scale * edge_bias(tangent, pitch) * right_of(tangent));
  };

  if (kept == 0) {
    out.points.reserve(n);
    for (long j = 0; j < n; ++j) out.points.push_back(smooth_vertex(j, -1e300, 1e300));
    out.corner.assign(n, 0);
    return out;
  }
  out.points.reserve(n);
  for (int k = 0; k < kept; ++k) {
    const long c = corners[k];
    const long next = corners[(k + 1) % kept] + (k == kept - 1 ? n : 0);
    out.points.push_back(corner_pos[k]);
    out.corner.push_back(1);
    const double lo = w.S(c) + gap, hi = w.S(next) - gap;
    for (long j = c + 1; j < next; ++j) {
      const double sj = w.S(j);
      if (sj <= lo || sj >= hi) continue;
      out.points.push_back(smooth_vertex(j, lo, hi));
      out.corner.push_back(0);
    }
  }
  return out;
}

}  // namespace hg::path_planner
