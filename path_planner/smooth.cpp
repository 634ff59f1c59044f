// Step 1: de-noise the outline's pixel staircase without rounding real corners.
//
// The outline core's loops run through the outermost pixel centres of the plate, so they zig-zag by up to
// one pixel pitch and sit on average half a pitch inside the true edge; with in-plane noise the vertices
// scatter by the noise as well. Local smoothing windows cannot average that away (a few vertices each), so
// the loop is modelled by long primitives instead:
//  1. corners: turning angle between total-least-squares lines fitted one corner scale behind and ahead of
//     every vertex (O(1) each from prefix sums of the coordinate moments); a corner turns by at least
//     corner_angle and its turn does not grow by half when the scale doubles (an arc's turn grows with the
//     scale, a corner's does not); the local maximum within one scale wins;
//  2. each run between corners (minus a gap at both ends, where the alpha shape cuts or fills the corner)
//     is split recursively into pieces that a TLS line or a geometric circle fit (Kasa start, Gauss-Newton)
//     explains: no window of vertices may have a mean residual above what the noise and the staircase
//     allow. Pieces that neither explains are halved; the smallest ones keep their better fit;
//  3. corners are re-placed at the intersection of the primitives on both sides (their angle comes from the
//     whole runs); a candidate whose primitives meet far from it, or at a shallow angle, is a tight arc or
//     noise, not a corner: it is dropped and the runs beside it are fitted as one;
//  3b. fillets: where two straights meet at a bend the pieces between them (or a corner, or two) do not
//     explain as well as straight - tangent arc - straight, the arc is fitted (fit_fillet) and replaces them;
//  4. edge compensation moves each primitive outward by half the pitch times max(|t_x|, |t_y|) for its
//     tangent t: the mean gap between the outermost pixel centres and an edge of that direction, assuming
//     the pixel grid is aligned with the plate's u, v axes (top-down camera).
// Output: line pieces as their end points, circle pieces sampled with a 5 um chord error: few vertices, so
// the offset and everything after it is cheap. Cost O(n log n) (recursive halving), O(n) for typical loops.
#include "path_planner/pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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
  // A staircase has many short axis-parallel steps, all one pitch long; a hand-drawn polygon (few long
  // edges) has no pitch. Noise tilts the steps: then too few are axis-parallel and there is no estimate
  // (the lattice is not recoverable from a noisy boundary; see docs/path_planner.md).
  if (lengths.size() < 16 || lengths.size() * 4 < edges) return 0;
  auto mid = lengths.begin() + lengths.size() / 2;
  std::nth_element(lengths.begin(), mid, lengths.end());
  const double median = *mid;
  // Lattice steps are all one pitch long; noisy edges that happen to lie near an axis are not.
  const std::size_t exact = std::size_t(std::count_if(lengths.begin(), lengths.end(),
                                                      [&](double l) { return std::abs(l - median) <= 0.02 * median; }));
  if (exact * 2 < lengths.size()) return 0;
  return median <= longest_loop / 200 ? median : 0;
}

namespace {

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
double turn(const Vec2& a, const Vec2& b) { return std::atan2(cross(a, b), a.dot(b)); }
// Outward (away from material, i.e. right of travel) normal of a travel direction.
Vec2 right_of(const Vec2& t) { return Vec2(t.y(), -t.x()); }

// The ring unrolled three times (unwrapped index j in [-n, 2n)) with prefix sums of the moments of the
// coordinates (relative to the first vertex, for precision), so that a TLS line over any index range
// costs O(1).
struct Unrolled {
  int n = 0;
  Vec2 origin;
  std::vector<Vec2> q;                          // q[j + n]: vertex j relative to origin
  std::vector<double> s;                        // s[j + n]: arc length at vertex j
  std::vector<double> mx, my, mxx, mxy, myy;    // prefix sums over q[0 .. k-1]

  explicit Unrolled(const Ring& ring) : n(int(ring.size())), origin(ring[0]) {
    const int m = 3 * n;
    q.resize(m);
    s.resize(m);
    for (int k = 0; k < m; ++k) q[k] = ring[k % n] - origin;
    double length = 0;
    for (int k = 0; k < n; ++k) length += (ring[(k + 1) % n] - ring[k]).norm();
    double acc = -length;
    for (int k = 0; k < m; ++k) {
      s[k] = acc;
      acc += (ring[(k + 1) % n] - ring[k % n]).norm();
    }
    mx.assign(m + 1, 0), my.assign(m + 1, 0), mxx.assign(m + 1, 0), mxy.assign(m + 1, 0), myy.assign(m + 1, 0);
    for (int k = 0; k < m; ++k) {
      const Vec2& p = q[k];
      mx[k + 1] = mx[k] + p.x();
      my[k + 1] = my[k] + p.y();
      mxx[k + 1] = mxx[k] + p.x() * p.x();
      mxy[k + 1] = mxy[k] + p.x() * p.y();
      myy[k + 1] = myy[k] + p.y() * p.y();
    }
  }
  const Vec2& at(long j) const { return q[j + n]; }
  double S(long j) const { return s[j + n]; }
  long wrap(long j) const { return ((j % n) + n) % n; }
};

struct Line {
  Vec2 centre = Vec2::Zero();  // relative to Unrolled::origin
  Vec2 dir = Vec2::UnitX();    // unit, along travel
  double rms = 0;              // root mean square distance of the vertices from the line
  bool ok = false;
};

// TLS line through vertices j0..j1 (unwrapped, inclusive, at most 2n apart), oriented from j0 toward j1.
Line fit_line(const Unrolled& u, long j0, long j1) {
  Line f;
  const double cnt = double(j1 - j0 + 1);
  if (cnt < 2) return f;
  const long a = j0 + u.n, b = j1 + u.n + 1;
  const double sx = u.mx[b] - u.mx[a], sy = u.my[b] - u.my[a];
  const Vec2 c(sx / cnt, sy / cnt);
  const double cxx = (u.mxx[b] - u.mxx[a]) / cnt - c.x() * c.x();
  const double cxy = (u.mxy[b] - u.mxy[a]) / cnt - c.x() * c.y();
  const double cyy = (u.myy[b] - u.myy[a]) / cnt - c.y() * c.y();
  // Major axis of the 2x2 covariance in closed form (no trigonometry: this runs for every vertex); the
  // minor eigenvalue is the mean squared residual.
  const double tr = cxx + cyy, det = cxx * cyy - cxy * cxy;
  const double root = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
  const double major = 0.5 * tr + root, minor = 0.5 * tr - root;
  // eigenvector of `major`: (cxy, major - cxx) or (major - cyy, cxy), whichever is better conditioned
  Vec2 dir = (major - cxx) * (major - cxx) > (major - cyy) * (major - cyy) ? Vec2(cxy, major - cxx)
                                                                          : Vec2(major - cyy, cxy);
  const double len = dir.norm();
  dir = len > 0 ? Vec2(dir / len) : Vec2(u.at(j1) - u.at(j0)).normalized();
  if (dir.dot(u.at(j1) - u.at(j0)) < 0) dir = -dir;
  f.centre = c;
  f.dir = dir;
  f.rms = std::sqrt(std::max(0.0, minor));
  f.ok = true;
  return f;
}

// A fitted primitive: a line (centre, dir) or a circle (centre, radius; ccw = travel counter-clockwise).
struct Primitive {
  bool circle = false;
  Vec2 centre = Vec2::Zero();
  Vec2 dir = Vec2::UnitX();
  double radius = 0;
  bool ccw = true;
  long first = 0, last = 0;  // unwrapped vertex range explained
};

// Geometric circle fit: Kasa's algebraic fit as the start, then Gauss-Newton on the orthogonal distances.
bool fit_circle(const Unrolled& u, long j0, long j1, Primitive& c) {
  const long m = j1 - j0 + 1;
  if (m < 5) return false;
  const Vec2 ref = u.at((j0 + j1) / 2);
  // Kasa: x^2 + y^2 + D x + E y + F = 0 in least squares.
  double sxx = 0, sxy = 0, syy = 0, sx = 0, sy = 0, sz = 0, sxz = 0, syz = 0;
  for (long j = j0; j <= j1; ++j) {
    const Vec2 p = u.at(j) - ref;
    const double z = p.squaredNorm();
    sxx += p.x() * p.x(), sxy += p.x() * p.y(), syy += p.y() * p.y();
    sx += p.x(), sy += p.y(), sz += z, sxz += p.x() * z, syz += p.y() * z;
  }
  Eigen::Matrix3d A;
  A << sxx, sxy, sx, sxy, syy, sy, sx, sy, double(m);
  const Eigen::Vector3d rhs(-sxz, -syz, -sz);
  const Eigen::Vector3d def = A.ldlt().solve(rhs);
  if (!def.allFinite()) return false;
  Vec2 centre(-def[0] / 2, -def[1] / 2);
  double r2 = centre.squaredNorm() - def[2];
  if (!(r2 > 0)) return false;
  double r = std::sqrt(r2);
  for (int it = 0; it < 4; ++it) {
    Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Jtr = Eigen::Vector3d::Zero();
    for (long j = j0; j <= j1; ++j) {
      const Vec2 d = u.at(j) - ref - centre;
      const double dn = d.norm();
      if (dn <= 0) continue;
      const Eigen::Vector3d J(-d.x() / dn, -d.y() / dn, -1);
      const double res = dn - r;
      JtJ += J * J.transpose();
      Jtr += J * res;
    }
    const Eigen::Vector3d step = JtJ.ldlt().solve(-Jtr);
    if (!step.allFinite()) return false;
    centre += step.head<2>();
    r += step[2];
    if (step.norm() < 1e-10) break;
  }
  if (!(r > 0) || !std::isfinite(r)) return false;
  double area2 = 0;  // orientation of travel about the centre
  for (long j = j0; j < j1; ++j) area2 += cross(u.at(j) - ref - centre, u.at(j + 1) - ref - centre);
  c.circle = true;
  c.centre = ref + centre;
  c.radius = r;
  c.ccw = area2 > 0;
  c.first = j0, c.last = j1;
  return true;
}

// Refit circle `c` over its vertices tangent to the given lines (its neighbours within a run, where the
// edge is smooth by construction: no corner was found there). A free circle fitted to a part of a noisy
// arc comes out off in centre and radius by a fair fraction of the noise (the shorter the arc, the worse);
// tangency lets the straights' many vertices hold it in place. Soft constraints, weighted to be nearly
// hard, in the same Gauss-Newton as fit_circle; the centre stays on the side of each line it is on.
void refit_tangent(const Unrolled& u, Primitive& c, const std::vector<const Primitive*>& lines) {
  const long m = c.last - c.first + 1;
  if (lines.empty() || m < 5) return;
  const double weight = std::sqrt(100.0 * double(m));
  std::vector<double> side;
  for (const Primitive* l : lines) side.push_back(cross(l->dir, c.centre - l->centre) >= 0 ? 1.0 : -1.0);
  Vec2 centre = c.centre;
  double r = c.radius;
  for (int it = 0; it < 8; ++it) {
    Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Jtr = Eigen::Vector3d::Zero();
    for (long j = c.first; j <= c.last; ++j) {
      const Vec2 d = u.at(j) - centre;
      const double dn = d.norm();
      if (dn <= 0) continue;
      const Eigen::Vector3d J(-d.x() / dn, -d.y() / dn, -1);
      JtJ += J * J.transpose();
      Jtr += J * (dn - r);
    }
    for (std::size_t k = 0; k < lines.size(); ++k) {
      const Primitive& l = *lines[k];
      const double res = weight * (side[k] * cross(l.dir, centre - l.centre) - r);
      const Eigen::Vector3d J(-weight * side[k] * l.dir.y(), weight * side[k] * l.dir.x(), -weight);
      JtJ += J * J.transpose();
      Jtr += J * res;
    }
    const Eigen::Vector3d step = JtJ.ldlt().solve(-Jtr);
    if (!step.allFinite()) return;
    centre += step.head<2>();
    r += step[2];
    if (step.norm() < 1e-10) break;
  }
  if (!(r > 0) || !std::isfinite(r) || !centre.allFinite()) return;
  c.centre = centre;
  c.radius = r;
}

double residual(const Primitive& p, const Vec2& q) {
  if (p.circle) return (q - p.centre).norm() - p.radius;
  return cross(p.dir, q - p.centre);  // left of travel positive
}

// Largest |mean residual| over any `w` consecutive vertices of the piece (the whole piece when shorter):
// a systematic misfit shows up there, noise averages out.
double worst_window_mean(const Unrolled& u, const Primitive& p, long j0, long j1, int w, std::vector<double>& r) {
  const long m = j1 - j0 + 1;
  r.resize(m);
  for (long j = j0; j <= j1; ++j) r[j - j0] = residual(p, u.at(j));
  const long win = std::min<long>(w, m);
  double sum = 0, worst = 0;
  for (long k = 0; k < m; ++k) {
    sum += r[k];
    if (k >= win) sum -= r[k - win];
    if (k >= win - 1) worst = std::max(worst, std::abs(sum) / double(win));
  }
  return worst;
}

// Tangent (travel direction) of a primitive at point q.
Vec2 tangent_at(const Primitive& p, const Vec2& q) {
  if (!p.circle) return p.dir;
  const Vec2 radial = (q - p.centre).normalized();
  return p.ccw ? Vec2(-radial.y(), radial.x()) : Vec2(radial.y(), -radial.x());
}

double edge_bias(const Vec2& t, double pitch) { return 0.5 * pitch * std::max(std::abs(t.x()), std::abs(t.y())); }

// Intersection of two primitives (edge-compensated by `bias_a`, `bias_b` along their outward normals) nearest
// to `near`. False when they do not meet.
bool intersect(const Primitive& a, const Primitive& b, double pitch, double bias_scale, const Vec2& near, Vec2& x) {
  auto shifted_line = [&](const Primitive& p, Vec2& c, Vec2& d) {
    d = p.dir;
    c = p.centre + bias_scale * edge_bias(d, pitch) * right_of(d);
  };
  auto shifted_radius = [&](const Primitive& p, const Vec2& at) {
    // outward is away from the centre when travelling counter-clockwise (material inside)
    const double b = bias_scale * edge_bias(tangent_at(p, at), pitch);
    return p.radius + (p.ccw ? b : -b);
  };
  if (!a.circle && !b.circle) {
    Vec2 ca, da, cb, db;
    shifted_line(a, ca, da);
    shifted_line(b, cb, db);
    const double den = cross(da, db);
    if (std::abs(den) < 1e-12) return false;
    x = ca + (cross(cb - ca, db) / den) * da;
    return true;
  }
  if (a.circle != b.circle) {
    const Primitive& l = a.circle ? b : a;
    const Primitive& c = a.circle ? a : b;
    Vec2 cl, dl;
    shifted_line(l, cl, dl);
    const double r = shifted_radius(c, near);
    const double t0 = (c.centre - cl).dot(dl);
    const Vec2 foot = cl + t0 * dl;
    const double h2 = r * r - (foot - c.centre).squaredNorm();
    if (h2 < 0) return false;
    const double h = std::sqrt(h2);
    const Vec2 x1 = foot + h * dl, x2 = foot - h * dl;
    x = (x1 - near).squaredNorm() < (x2 - near).squaredNorm() ? x1 : x2;
    return true;
  }
  const double ra = shifted_radius(a, near), rb = shifted_radius(b, near);
  const Vec2 d = b.centre - a.centre;
  const double L = d.norm();
  if (!(L > 0) || L > ra + rb || L < std::abs(ra - rb)) return false;
  const double t = (L * L + ra * ra - rb * rb) / (2 * L);
  const double h = std::sqrt(std::max(0.0, ra * ra - t * t));
  const Vec2 e = d / L, base = a.centre + t * e, perp(-e.y(), e.x());
  const Vec2 x1 = base + h * perp, x2 = base - h * perp;
  x = (x1 - near).squaredNorm() < (x2 - near).squaredNorm() ? x1 : x2;
  return true;
}

// A fillet between two straights: an arc tangent to both. Under camera noise the greedy pieces share a
// short fillet out between the straights beside it (a line misses an R15 arc by less than the misfit
// tolerance for a third of its length at each end, and the middle alone bows too little to be told from a
// line), or the corner detector takes it for a corner at its scale; joining the straights at their
// intersection would then cut the corner the fillet rounds -- into the material at a concave one.
struct Fillet {
  Line a, b;           // the straights, refitted without the fillet's vertices
  long a_last = 0;     // last vertex of a, first of b (unwrapped)
  long b_first = 0;
  Primitive arc;       // the fillet: a circle tangent to both
  Vec2 t1 = Vec2::Zero(), t2 = Vec2::Zero();  // its tangent points on a and b
};

// Signed distance (left of travel positive) of q from straight a, fillet, straight b, whichever is nearest.
double fillet_residual(const Line& a, const Line& b, const Primitive& arc, const Vec2& t1, const Vec2& t2, const Vec2& q) {
  const double s1 = (q - t1).dot(a.dir), s2 = (q - t2).dot(b.dir);
  double best = s1 <= 0 ? cross(a.dir, q - t1) : std::numeric_limits<double>::max();
  auto take = [&](double d) {
    if (std::abs(d) < std::abs(best)) best = d;
  };
  if (s2 >= 0) take(cross(b.dir, q - t2));
  const Vec2 r1 = t1 - arc.centre, r2 = t2 - arc.centre, rq = q - arc.centre;
  const double sense = cross(r1, r2);
  if (cross(r1, rq) * sense >= 0 && cross(rq, r2) * sense >= 0) take(arc.ccw ? arc.radius - rq.norm() : rq.norm() - arc.radius);
  if (best == std::numeric_limits<double>::max()) {  // between the pieces' ranges (a sharp bend): the nearer end
    const double d1 = (q - t1).norm(), d2 = (q - t2).norm();
    best = d1 < d2 ? (cross(a.dir, q - t1) >= 0 ? d1 : -d1) : (cross(b.dir, q - t2) >= 0 ? d2 : -d2);
  }
  return best;
}

// Fits straight, fillet, straight to vertices w0..w1, the straights starting from vertices w0..a1 and
// b0..w1, the tangent points at most max_tangent from the bend: the radius by a 1-D search of the squared
// distances (coarse scan, then golden section) with the straights held, then each straight refitted on its
// vertices outside the fillet; four rounds. Accepted
// when the model explains the vertices as the pieces must (no window of `win` vertices with a mean
// residual above `tolerance`) and the fillet is real: under 15 deg of bend it bows too little to matter,
// a radius under 3 units is what pixels and the alpha shape make of a sharp corner, and the fit must be
// significantly better than the sharp bend (below).
bool fit_fillet(const Unrolled& u, long w0, long a1, long b0, long w1, double unit, double tolerance, int win,
                double max_tangent, Fillet& f) {
  if (a1 - w0 < 5 || w1 - b0 < 5 || b0 <= a1) return false;
  Line la = fit_line(u, w0, a1), lb = fit_line(u, b0, w1);
  double r = 0, phi = 0;
  long i1 = a1, i2 = b0;
  Vec2 x;
  thread_local std::vector<long> near;
  auto bend = [&] {
    phi = turn(la.dir, lb.dir);
    const double den = cross(la.dir, lb.dir);
    if (std::abs(phi) < 15 * M_PI / 180 || std::abs(den) < 1e-9) return false;
    x = la.centre + (cross(lb.centre - la.centre, lb.dir) / den) * la.dir;
    return true;
  };
  for (int round = 0; round < 4; ++round) {
    if (!bend()) return false;
    const double tan_half = std::tan(std::abs(phi) / 2);
    // The tangent points stay within the window (most of each side of it), and within max_tangent of the
    // bend: a longer fillet is an arc the greedy segmentation fits by itself.
    const double reach = std::min(max_tangent, 0.8 * std::min((x - u.at(w0)).dot(la.dir), (u.at(w1) - x).dot(lb.dir)));
    const double r_max = reach / tan_half;
    if (!(r_max > unit)) return false;
    const Vec2 side = phi > 0 ? Vec2(-la.dir.y(), la.dir.x()) : Vec2(la.dir.y(), -la.dir.x());  // towards the centre
    // Only vertices near the bend depend on r: beyond the farthest tangent point they are scored against
    // the same straight for every r, and leaving them out does not move the minimum (a 10 k vertex loop has
    // straights of thousands).
    near.clear();
    for (long j = w0; j <= w1; ++j)
      if ((u.at(j) - x).norm() <= reach + 2 * unit) near.push_back(j);
    auto cost = [&](double rr) {
      const double l = rr * tan_half;
      const Vec2 p1 = x - l * la.dir, p2 = x + l * lb.dir;
      Primitive arc;
      arc.centre = p1 + rr * side, arc.radius = rr, arc.ccw = phi > 0;
      double sum = 0;
      for (const long j : near) sum += std::pow(fillet_residual(la, lb, arc, p1, p2, u.at(j)), 2);
      return sum;
    };
    const int steps = 32;
    int best = 1;
    double best_cost = std::numeric_limits<double>::max();
    for (int k = 1; k <= steps; ++k)
      if (const double c = cost(r_max * k / steps); c < best_cost) best_cost = c, best = k;
    double lo = r_max * (best - 1) / steps, hi = r_max * std::min(best + 1, steps) / steps;
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo), c1 = cost(m1), c2 = cost(m2);
    for (int it = 0; it < 20; ++it) {
      if (c1 < c2) hi = m2, m2 = m1, c2 = c1, m1 = hi - g * (hi - lo), c1 = cost(m1);
      else lo = m1, m1 = m2, c1 = c2, m2 = lo + g * (hi - lo), c2 = cost(m2);
    }
    r = 0.5 * (lo + hi);
    // Each straight refitted on its vertices up to its tangent point.
    const double l = r * tan_half;
    i1 = w0, i2 = w1;
    while (i1 < w1 && (u.at(i1 + 1) - x).dot(la.dir) < -l) ++i1;
    while (i2 > w0 && (u.at(i2 - 1) - x).dot(lb.dir) > l) --i2;
    if (i1 - w0 < 5 || w1 - i2 < 5 || i2 <= i1) return false;
    la = fit_line(u, w0, i1), lb = fit_line(u, i2, w1);
  }
  if (!bend()) return false;
  if (!(r >= 3 * unit)) return false;
  const double l = r * std::tan(std::abs(phi) / 2);
  const Vec2 side = phi > 0 ? Vec2(-la.dir.y(), la.dir.x()) : Vec2(la.dir.y(), -la.dir.x());
  f.a = la, f.b = lb, f.a_last = i1, f.b_first = i2;
  f.t1 = x - l * la.dir, f.t2 = x + l * lb.dir;
  f.arc = Primitive{};
  f.arc.circle = true;
  f.arc.centre = f.t1 + r * side;
  f.arc.radius = r;
  f.arc.ccw = phi > 0;
  f.arc.first = i1, f.arc.last = i2;
  // The misfit test of the pieces (worst_window_mean) applied to the whole model, and the fillet's
  // significance: the sum of squares it saves over the sharp bend of the same straights, against the
  // residual variance (an F statistic of one parameter). At the alpha shape's rounding of sharp corners
  // it stays under 15 (pm806, lsr-l and the noisy accuracy parts); the l-bracket's R15 fillet gives over
  // 130 at pm806, an R10 fillet about 20-30.
  const long m = w1 - w0 + 1, w = std::min<long>(win, m);
  Primitive tip = f.arc;
  tip.radius = 0, tip.centre = x;
  double sum = 0, sharp_ss = 0, fillet_ss = 0;
  thread_local std::vector<double> res;
  res.resize(m);
  for (long j = w0; j <= w1; ++j) {
    res[j - w0] = fillet_residual(la, lb, f.arc, f.t1, f.t2, u.at(j));
    fillet_ss += res[j - w0] * res[j - w0];
    sharp_ss += std::pow(fillet_residual(la, lb, tip, x, x, u.at(j)), 2);
  }
  if (!(m > 10 && (sharp_ss - fillet_ss) > 25 * fillet_ss / double(m - 5))) return false;
  for (long k = 0; k < m; ++k) {
    sum += res[k];
    if (k >= w) sum -= res[k - w];
    if (k >= w - 1 && std::abs(sum) / double(w) > tolerance) return false;
  }
  return true;
}

int window_of(const SmoothOptions& o) { return std::max(5, int(std::lround(2 * o.window_pitches))); }

// Noise of a window mean (the mean of `win` consecutive vertices): from five adjacent window means M-2..M2
// around each vertex, E = 3/4 M0 - (M-1 + M1)/2 + (M-2 + M2)/8 cancels a straight or evenly curved edge
// (position, slope and curvature) and leaves noise and staircase with variance 1.094 sigma^2 for
// independent windows. It measures the noise as it is, correlated between neighbouring vertices or not.
// Appends |E| across the edge at every vertex (none for a loop shorter than the five windows).
void append_window_noise(const Unrolled& u, int win, std::vector<double>& dev) {
  const long n = u.n;
  if (n < 5 * win) return;
  auto mean_at = [&](long centre) {
    const long a = centre - win / 2 + n, b = a + win;
    return Vec2((u.mx[b] - u.mx[a]) / win, (u.my[b] - u.my[a]) / win);
  };
  for (long i = 0; i < n; ++i) {
    const Vec2 m0 = mean_at(i), m1 = mean_at(i + win), m_1 = mean_at(i - win), m2 = mean_at(i + 2 * win),
               m_2 = mean_at(i - 2 * win);
    const Vec2 e = 0.75 * m0 - 0.5 * (m_1 + m1) + 0.125 * (m_2 + m2);
    const Vec2 along = m1 - m_1;
    const double len = along.norm();
    dev.push_back(len > 0 ? std::abs(cross(along, e)) / len : e.norm());
  }
}
// Median of |E| as a Gaussian sigma.
double sigma_of(std::vector<double>& dev) {
  if (dev.empty()) return 0;
  std::nth_element(dev.begin(), dev.begin() + dev.size() / 2, dev.end());
  return 1.4826 * dev[dev.size() / 2] / std::sqrt(1.094);
}

}  // namespace

double estimate_noise(const std::vector<Loop>& loops, const SmoothOptions& o) {
  std::vector<double> dev;
  for (const Loop& l : loops)
    if (l.points.size() >= 8) append_window_noise(Unrolled(l.points), window_of(o), dev);
  return sigma_of(dev);
}

SmoothedRing smooth_ring(const Ring& ring, double pitch, const SmoothOptions& o) {
  SmoothedRing out;
  const int n = int(ring.size());
  auto unchanged = [&] {
    out.points = ring;
    out.corner.assign(ring.size(), 0);
    return out;
  };
  if (n < 8 || !(pitch >= 0)) return unchanged();
  const Unrolled u(ring);
  const double total = u.S(n) - u.S(0);
  // Length unit of the scales: the pitch, or the vertex spacing when noise spreads the vertices further.
  double spacing = 0;
  {
    std::vector<double> e(n);
    for (int i = 0; i < n; ++i) e[i] = u.S(i + 1) - u.S(i);
    std::nth_element(e.begin(), e.begin() + n / 2, e.end());
    spacing = e[n / 2];
  }
  // Unknown pitch: a densely sampled boundary (a noisy one, whose lattice is lost) is still fitted, with the
  // vertex spacing as the unit and without edge compensation; a drawn polygon (long edges) is left alone.
  if (pitch == 0 && !(spacing > 0 && spacing <= total / 200)) return unchanged();
  const double unit = std::max(pitch, spacing);
  // ---- noise level of a window mean: the outline's (all loops pooled), or this loop's own ----
  const int win = window_of(o);
  double sigma = o.noise;
  if (!(sigma > 0)) {
    std::vector<double> dev;
    append_window_noise(u, win, dev);
    sigma = sigma_of(dev);
  }
  // The corner detector's lines are at least 60 window-mean noise levels long: noise then tilts them by
  // about 1/60 rad, so that a tight arc (a 20 mm slot end under pm806 noise, where one corner scale of
  // 8 pixels turns by ~30 deg) cannot pass for a corner by the noise inflating its turn at one scale.
  const double scale = std::max(o.corner_scale_pitches * unit, 60.0 * sigma);
  const double bias_scale = o.edge_compensation && pitch > 0 ? 1.0 : 0.0;

  // ---- 1. corner candidates: turn between one-sided TLS lines at scale and 2 x scale (two-pointer) ----
  std::vector<double> t1(n, 0), t2(n, 0);
  {
    const double cos_corner = std::cos(o.corner_angle);
    // b: first index with S >= S(i) - scale, f: last with S <= S(i) + scale (both move forward only)
    long b1 = -n + 1, f1 = 0, b2 = -n + 1, f2 = 0;
    for (long i = 0; i < n; ++i) {
      const double si = u.S(i);
      while (b1 < i && u.S(b1) < si - scale) ++b1;
      while (b2 < i && u.S(b2) < si - 2 * scale) ++b2;
      while (f1 + 1 < i + n && u.S(f1 + 1) <= si + scale) ++f1;
      while (f2 + 1 < i + n && u.S(f2 + 1) <= si + 2 * scale) ++f2;
      if (f1 < i) f1 = i;
      if (f2 < i) f2 = i;
      if (i - b1 < 2 || f1 - i < 2) continue;
      const Vec2 back = fit_line(u, b1, i).dir, ahead = fit_line(u, i, f1).dir;
      if (back.dot(ahead) > cos_corner) continue;  // turns less than corner_angle: skip the atan2
      t1[i] = turn(back, ahead);
      t2[i] = turn(fit_line(u, b2, i).dir, fit_line(u, i, f2).dir);
    }
  }
  std::vector<long> corners;
  for (long i = 0; i < n; ++i) {
    if (!(std::abs(t1[i]) >= o.corner_angle && std::abs(t2[i]) < 1.5 * std::abs(t1[i]))) continue;
    bool best = true;
    const double si = u.S(i);
    for (long j = i - 1; best && i - j < n / 2 && si - u.S(j) <= scale; --j)
      if (std::abs(t1[u.wrap(j)]) > std::abs(t1[i])) best = false;
    for (long j = i + 1; best && j - i < n / 2 && u.S(j) - si <= scale; ++j)
      if (std::abs(t1[u.wrap(j)]) >= std::abs(t1[i])) best = false;
    if (best) corners.push_back(i);
  }
  if (total < 8 * scale) corners.clear();  // a loop this small has no room for corners and runs

  // A window mean beyond this is a misfit, not noise or staircase. 4 sigma, not 3: a loop has a hundred or
  // more windows and the noise of a real camera's edge has heavy tails (mixed pixels), so a 3 sigma bump is
  // expected on most loops and would split a straight edge or bend it into a large arc.
  const double tolerance = 0.1 * (pitch > 0 ? pitch : spacing) + 4.0 * sigma;
  const long min_piece = 2 * win;

  // ---- 2. + 3. fit the runs between corners; drop corners whose primitives do not make one ----
  std::vector<Primitive> prims;
  std::vector<int> piece_run;  // run index of each primitive (run k starts at corner k)
  std::vector<double> scratch;
  std::vector<std::pair<long, long>> stack;
  // Best primitive for vertices a..b and its worst window mean residual.
  auto best_fit = [&](long a, long b, Primitive& best) {
    Primitive line;
    const Line lf = fit_line(u, a, b);
    line.centre = lf.centre, line.dir = lf.dir, line.first = a, line.last = b;
    const double line_err = worst_window_mean(u, line, a, b, win, scratch);
    best = line;
    if (line_err <= tolerance || b - a < 5) return line_err;
    Primitive circ;
    if (!fit_circle(u, a, b, circ) || !(circ.radius > 2 * unit && circ.radius < 1e3 * total)) return line_err;
    // A circle that bows off its chord by less than twice the tolerance is not told apart from a straight by
    // the data (a noise bump made the line miss by a little): the piece stays a line, split if it must be.
    const double half_sweep = std::min(M_PI, 0.5 * (u.S(b) - u.S(a)) / circ.radius);
    if (circ.radius * (1 - std::cos(half_sweep)) < 2 * tolerance) return line_err;
    const double circ_err = worst_window_mean(u, circ, a, b, win, scratch);
    if (circ_err < line_err) best = circ;
    return std::min(line_err, circ_err);
  };
  // Greedy segmentation of vertices j0..j1: from the start, the longest piece that a line or a circle
  // explains (doubling, then bisection: O(m log m) for a piece of m vertices), and so on.
  auto fit_run = [&](long j0, long j1, int k) {
    Primitive p;
    for (long a = j0; a <= j1;) {
      if (best_fit(a, j1, p) <= tolerance || j1 - a + 1 <= min_piece) {
        if (j1 - a + 1 < min_piece && j1 - j0 + 1 >= min_piece) {
          // a short rest: fit it with the vertices before it, keep only its own range
          best_fit(j1 - min_piece + 1, j1, p);
          p.first = a;
        }
        prims.push_back(p), piece_run.push_back(k);
        break;
      }
      long good = a + min_piece - 1, bad = j1;  // good: known to fit (or the minimum); bad: known not to
      Primitive pg;
      best_fit(a, good, pg);
      for (long len = 2 * min_piece; a + len - 1 < bad; len *= 2) {
        if (best_fit(a, a + len - 1, p) > tolerance) {
          bad = a + len - 1;
          break;
        }
        good = a + len - 1, pg = p;
      }
      while (bad - good > 1) {
        const long mid = (good + bad) / 2;
        if (best_fit(a, mid, p) <= tolerance) good = mid, pg = p;
        else bad = mid;
      }
      prims.push_back(pg), piece_run.push_back(k);
      a = good + 1;
    }
  };
  // The greedy pieces run past the true junctions (a misfit must build up before it shows): move each
  // boundary between two pieces of a run to where the two primitives' squared residuals split best, then
  // refit both; repeated until no boundary moves, since a piece that held vertices of its neighbour is bent
  // toward it and gives them up a few at a time. `wrap`: the run is the whole loop (no corners), so the
  // last piece also borders the first, one loop length (n) further on.
  auto refine_junctions = [&](std::size_t from, bool wrap) {
    const std::size_t count = prims.size();
    for (int pass = 0; pass < 8; ++pass) {
      bool moved = false;
      for (std::size_t i = from; i < count; ++i) {
        const bool wrapping = i + 1 == count;
        if (wrapping && !(wrap && count - from >= 2)) break;
        const std::size_t k = wrapping ? from : i + 1;
        if (piece_run[i] != piece_run[k]) continue;
        Primitive& pa = prims[i];
        Primitive& pb = prims[k];
        const long shift = wrapping ? n : 0;  // pb's vertices unwrapped to follow pa's
        const long lo = pa.first + 2, hi = pb.last + shift - 2;
        if (hi - lo < 2) continue;
        auto rb = [&](long j) { return residual(pb, u.at(j - shift)); };
        // cost(t) = sum_{j<=t} ra^2 + sum_{j>t} rb^2 over lo-1 .. hi
        double sb = 0;
        for (long j = lo; j <= hi; ++j) sb += std::pow(rb(j), 2);
        double sa = 0, best = sb;
        long best_t = lo - 1;
        for (long t = lo; t < hi; ++t) {
          sa += std::pow(residual(pa, u.at(t)), 2);
          sb -= std::pow(rb(t), 2);
          if (sa + sb < best) best = sa + sb, best_t = t;
        }
        if (best_t == pa.last) continue;
        const long a0 = pa.first, b1 = pb.last + shift;
        best_fit(a0, best_t, pa);
        best_fit(best_t + 1 - shift, b1 - shift, pb);
        moved = true;
      }
      if (!moved) break;
    }
  };
  // Neighbouring straights of a run that one line explains about as well (its rms residual within a quarter
  // of the worse piece's) are one edge that a noise bump split: merged, so the short piece beside the bump
  // does not tilt. A real bend, however shallow, raises the merged residual far more than that.
  auto merge_lines = [&](std::size_t from) {
    for (std::size_t i = from; i + 1 < prims.size();) {
      Primitive& pa = prims[i];
      const Primitive& pb = prims[i + 1];
      if (pa.circle || pb.circle || piece_run[i] != piece_run[i + 1]) { ++i; continue; }
      const Line a = fit_line(u, pa.first, pa.last), b = fit_line(u, pb.first, pb.last), ab = fit_line(u, pa.first, pb.last);
      if (!(ab.rms <= 1.25 * std::max(a.rms, b.rms))) { ++i; continue; }
      pa.centre = ab.centre, pa.dir = ab.dir, pa.last = pb.last;
      prims.erase(prims.begin() + long(i) + 1);
      piece_run.erase(piece_run.begin() + long(i) + 1);
    }
  };
  // A straight long enough to hold a fillet's tangent: the pieces a noisy fillet is split into are shorter.
  auto long_line = [&](const Primitive& p) { return !p.circle && p.last - p.first + 1 >= 4 * min_piece; };
  std::vector<Vec2> corner_pos;
  for (int attempt = 0;; ++attempt) {
    if (attempt == 8) corners.clear();  // give up on corners: the loop as one smooth run
    const int nc = int(corners.size());
    prims.clear();
    piece_run.clear();
    corner_pos.assign(nc, Vec2::Zero());
    if (nc == 0) {
      fit_run(0, n - 1, 0);
      refine_junctions(0, true);
      merge_lines(0);
      break;
    }
    // Gap at each corner: the alpha shape fills a concave corner and the pixels thin out toward an acute
    // tip, over about two units divided by sin(interior / 2).
    std::vector<double> gap(nc);
    for (int k = 0; k < nc; ++k) gap[k] = 2.0 * unit / std::sin(std::max(0.2, M_PI - std::abs(t1[corners[k]])) / 2);
    int crowded = -1;
    for (int k = 0; k < nc && crowded < 0; ++k) {
      const long c0 = corners[k], c1 = corners[(k + 1) % nc] + (k + 1 == nc ? n : 0);
      long j0 = c0, j1 = c1;
      while (j0 < c1 && u.S(j0) < u.S(c0) + gap[k]) ++j0;
      while (j1 > j0 && u.S(j1) > u.S(c1) - gap[(k + 1) % nc]) --j1;
      if (j1 - j0 < 2) {  // corners too close together for a run between them: drop the weaker one
        crowded = std::abs(t1[corners[k]]) < std::abs(t1[corners[(k + 1) % nc]]) ? k : (k + 1) % nc;
        break;
      }
      const std::size_t from = prims.size();
      fit_run(j0, j1, k);
      refine_junctions(from, false);
      merge_lines(from);
    }
    if (crowded >= 0) {
      corners.erase(corners.begin() + crowded);
      continue;
    }
    // Corner positions from the primitives on both sides.
    std::vector<int> drop;
    std::size_t after = 0;
    for (int k = 0; k < nc; ++k) {
      while (piece_run[after] != k) ++after;  // first primitive of run k
      const Primitive& pa = prims[(after == 0 ? prims.size() : after) - 1];
      const Primitive& pb = prims[after];
      const Vec2 near = u.at(corners[k]);
      const double interior = std::max(0.2, M_PI - std::abs(t1[corners[k]]));
      Vec2 x;
      const bool met = intersect(pa, pb, pitch, bias_scale, near, x);
      const double angle = met ? std::abs(turn(tangent_at(pa, x), tangent_at(pb, x))) : 0;
      // The primitives must meet near the candidate (within the gap it was cut by) at a real angle.
      // And the outline must come close to where they meet: at a sharp corner the pixels reach the tip up
      // to the alpha shape's chamfer (about half the gap) and a pitch of staircase, while a fillet of radius
      // R stays R (1/sin(interior/2) - 1) away from it (0.41 R at 90 deg) -- a fillet is an arc, not a corner.
      double closest = std::numeric_limits<double>::max();
      if (met) {
        const long c = corners[k];
        const double reach = gap[k] + 2 * unit;
        for (long j = c; j > c - n + 1 && u.S(c) - u.S(j) <= reach; --j) closest = std::min(closest, (u.at(j) - x).norm());
        for (long j = c; j < c + n - 1 && u.S(j) - u.S(c) <= reach; ++j) closest = std::min(closest, (u.at(j) - x).norm());
      }
      // A fillet that the closest vertex alone does not reveal (noise brought one near the tip) shows in a
      // fit of straight, fillet, straight from the last long straight before to the first after, over at
      // most two short pieces on each side (the greedy fit may have made them of parts of the fillet). A
      // wide fillet may also have been taken for two corners with short pieces between: both go.
      bool fillet = false;
      if (met) {
        const long np = long(prims.size()), pa_seq = (after == 0 ? np : long(after)) - 1;
        // piece at sequence position `seq` (one loop on: vertices n further)
        auto at = [&](long seq) { return ((seq % np) + np) % np; };
        auto first = [&](long seq) { return prims[at(seq)].first + (seq - at(seq)) / np * n; };
        auto last = [&](long seq) { return prims[at(seq)].last + (seq - at(seq)) / np * n; };
        auto is_long_line = [&](long seq) { return long_line(prims[at(seq)]); };
        long ia = pa_seq, ib = pa_seq + 1;
        for (int step = 0; step < 2 && !is_long_line(ia); ++step) --ia;
        for (int step = 0; step < 2 && !is_long_line(ib); ++step) ++ib;
        std::vector<int> crossed;  // the corners between: run r starts at corner r
        for (long q = ia; q < ib; ++q)
          if (piece_run[at(q)] != piece_run[at(q + 1)]) crossed.push_back(piece_run[at(q + 1)]);
        Fillet f;
        fillet = ib - ia < np && crossed.size() <= 2 && is_long_line(ia) && is_long_line(ib) &&
                 fit_fillet(u, first(ia), last(ia), first(ib), last(ib), unit, tolerance, win, 3 * scale, f);
        if (fillet) drop.insert(drop.end(), crossed.begin(), crossed.end());
      }
      if (!met || (x - near).norm() > gap[k] + 2 * unit / std::sin(interior / 2) || angle < 0.6 * o.corner_angle ||
          closest > 0.5 * gap[k] + unit || fillet)
        drop.push_back(k);
      else
        corner_pos[k] = x;
    }
    std::sort(drop.begin(), drop.end());
    drop.erase(std::unique(drop.begin(), drop.end()), drop.end());
    if (drop.empty()) break;
    for (auto it = drop.rbegin(); it != drop.rend(); ++it) corners.erase(corners.begin() + *it);
  }

  // Arcs tangent to the straights beside them in the same run (the corners beside them are re-placed below).
  std::vector<char> tangent_junction(prims.size(), 0);  // [i]: prims[i] and its successor made tangent
  {
    const std::size_t np = prims.size();
    const bool one_run = corners.empty();
    for (std::size_t i = 0; i < np && np >= 2; ++i) {
      if (!prims[i].circle) continue;
      std::vector<const Primitive*> lines;
      const std::size_t before = i == 0 ? np - 1 : i - 1, after = i + 1 == np ? 0 : i + 1;
      const bool wraps_before = i == 0, wraps_after = i + 1 == np;
      // only a straight of some length that the free circle already nearly touches: a short line piece
      // inside an arc, or a line that crosses the circle, is not a tangent neighbour
      auto tangent_line = [&](std::size_t j) {
        const Primitive& l = prims[j];
        const double gap = std::abs(std::abs(cross(l.dir, prims[i].centre - l.centre)) - prims[i].radius);
        return !l.circle && l.last - l.first + 1 >= 2 * min_piece && gap <= 2 * tolerance;
      };
      if (piece_run[before] == piece_run[i] && (!wraps_before || one_run) && tangent_line(before))
        lines.push_back(&prims[before]), tangent_junction[before] = 1;
      if (after != before && piece_run[after] == piece_run[i] && (!wraps_after || one_run) && tangent_line(after))
        lines.push_back(&prims[after]), tangent_junction[i] = 1;
      refit_tangent(u, prims[i], lines);
    }
  }

  // Fillets (fit_fillet). First a run between two corners as a whole: straight, fillet, straight (the
  // greedy pieces of a noisy fillet and its straights can be anything, a long flat arc over the fillet's end
  // and half a straight included). Then, within runs, between a straight and the next straight past at
  // most two short pieces, each taken with the nearly collinear straights beyond it (a noise bump may have
  // split one). Every piece between is replaced by the refitted straights and the fillet. No fillet is
  // looked for across the start of a loop without corners.
  std::vector<char> has_fillet(prims.size(), 0);  // [i]: a fillet joins prims[i] to prims[i + 1]
  std::vector<Fillet> fillets(prims.size());
  {
    auto is_long_line = [&](std::size_t i) { return long_line(prims[i]); };
    // Replaces prims[ia..ib] by the fillet's two straights.
    auto replace = [&](std::size_t ia, std::size_t ib, const Fillet& f) {
      const int run = piece_run[ia];
      Primitive a = prims[ia], b = prims[ib];
      a.circle = b.circle = false;
      a.centre = f.a.centre, a.dir = f.a.dir, a.last = f.a_last;
      b.centre = f.b.centre, b.dir = f.b.dir, b.first = f.b_first;
      const char tangent_after = tangent_junction[ib];
      const long from = long(ia), to = long(ib) + 1;
      prims.erase(prims.begin() + from, prims.begin() + to);
      prims.insert(prims.begin() + from, {a, b});
      piece_run.erase(piece_run.begin() + from, piece_run.begin() + to);
      piece_run.insert(piece_run.begin() + from, {run, run});
      tangent_junction.erase(tangent_junction.begin() + from, tangent_junction.begin() + to);
      tangent_junction.insert(tangent_junction.begin() + from, {0, tangent_after});
      has_fillet.erase(has_fillet.begin() + from, has_fillet.begin() + to);
      has_fillet.insert(has_fillet.begin() + from, {1, 0});
      fillets.erase(fillets.begin() + from, fillets.begin() + to);
      fillets.insert(fillets.begin() + from, {f, Fillet{}});
    };
    if (!corners.empty())
      for (std::size_t i0 = 0; i0 < prims.size();) {
        std::size_t i1 = i0;
        while (i1 + 1 < prims.size() && piece_run[i1 + 1] == piece_run[i0]) ++i1;
        if (i1 > i0) {
          const long w0 = prims[i0].first, w1 = prims[i1].last, third = (w1 - w0) / 3;
          const long a1 = is_long_line(i0) ? prims[i0].last : w0 + third;
          const long b0 = is_long_line(i1) ? prims[i1].first : w1 - third;
          Fillet f;
          if (fit_fillet(u, w0, a1, b0, w1, unit, tolerance, win, 3 * scale, f)) {
            replace(i0, i1, f);
            i1 = i0 + 1;
          }
        }
        i0 = i1 + 1;
      }
    const double collinear = 5 * M_PI / 180;
    for (std::size_t i = 0; i + 1 < prims.size(); ++i) {
      const int run = piece_run[i];
      if (!is_long_line(i) || has_fillet[i]) continue;
      std::size_t j = i + 1;
      while (j < prims.size() && j <= i + 3 && piece_run[j] == run && !is_long_line(j)) ++j;
      if (j >= prims.size() || j > i + 3 || piece_run[j] != run) continue;
      std::size_t ia = i, ib = j;
      while (ia > 0 && piece_run[ia - 1] == run && is_long_line(ia - 1) && !has_fillet[ia - 1] &&
             !(ia >= 2 && has_fillet[ia - 2]) && std::abs(turn(prims[ia - 1].dir, prims[i].dir)) < collinear)
        --ia;
      while (ib + 1 < prims.size() && piece_run[ib + 1] == run && is_long_line(ib + 1) &&
             std::abs(turn(prims[j].dir, prims[ib + 1].dir)) < collinear)
        ++ib;
      Fillet f;
      if (!fit_fillet(u, prims[ia].first, prims[i].last, prims[j].first, prims[ib].last, unit, tolerance, win, 3 * scale, f)) continue;
      replace(ia, ib, f);
      i = ia;  // on from the straight after the fillet
    }
    // Corners re-placed where the refitted arcs and straights beside them now meet (if still near).
    const std::size_t np = prims.size();
    std::size_t after = 0;
    for (std::size_t k = 0; k < corners.size(); ++k) {
      while (piece_run[after] != int(k)) ++after;
      const std::size_t before = after == 0 ? np - 1 : after - 1;
      Vec2 x;
      if (intersect(prims[before], prims[after], pitch, bias_scale, corner_pos[k], x) &&
          (x - corner_pos[k]).norm() <= 2 * unit)
        corner_pos[k] = x;
    }
  }

  // ---- 4. emit: corners, line end points, sampled arcs, all edge-compensated ----
  const int nc = int(corners.size());
  auto project = [&](const Primitive& p, const Vec2& q) -> Vec2 {
    const Vec2 t = tangent_at(p, q);
    const double b = bias_scale * edge_bias(t, pitch);
    if (!p.circle) return p.centre + (q - p.centre).dot(p.dir) * p.dir + b * right_of(p.dir);
    const Vec2 radial = (q - p.centre).normalized();
    return p.centre + (p.radius + (p.ccw ? b : -b)) * radial;
  };
  auto emit = [&](const Vec2& p, bool corner) {
    out.points.push_back(u.origin + p);
    out.corner.push_back(corner ? 1 : 0);
  };
  const double chord = 5e-6;
  auto emit_piece = [&](const Primitive& p, const Vec2* from, const Vec2* to) {
    const Vec2 a = from ? *from : project(p, u.at(p.first));
    const Vec2 b = to ? *to : project(p, u.at(p.last));
    if (!p.circle) {
      if (!from) emit(a, false);
      if (!to) emit(b, false);
      return;
    }
    double a0 = std::atan2((a - p.centre).y(), (a - p.centre).x());
    double sweep = turn(a - p.centre, b - p.centre);
    if (p.first + u.n - 1 <= p.last) {
      sweep = p.ccw ? 2 * M_PI : -2 * M_PI;  // a whole loop
    } else {
      // The piece's own sweep, from its end vertices, in the circle's sense (it can exceed half a turn).
      const Vec2 own_a = project(p, u.at(p.first)), own_b = project(p, u.at(p.last));
      double own = turn(own_a - p.centre, own_b - p.centre);
      if (p.ccw && own < 0) own += 2 * M_PI;
      if (!p.ccw && own > 0) own -= 2 * M_PI;
      // Between given end points (junctions), the sweep is the one nearest the piece's own: the junctions
      // can fall on either side of its end vertices, and both on one point when the circle is all of a
      // loop but a short straight (a dropout's flat), where the principal angle (0) lost the whole turn.
      sweep += 2 * M_PI * std::round((own - sweep) / (2 * M_PI));
      // Ends that passed each other (a short arc between two junctions) leave the chord between them.
      if (p.ccw ? sweep < 0 : sweep > 0) {
        if (!from) emit(a, false);
        if (!to) emit(b, false);
        return;
      }
    }
    const double dstep = 2 * std::sqrt(2 * chord / p.radius);
    const int steps = std::max(1, int(std::ceil(std::abs(sweep) / dstep)));
    const int last = (p.first + u.n - 1 <= p.last) ? steps - 1 : steps;
    for (int s = from ? 1 : 0; s <= last; ++s) {
      if (s == steps && to) break;
      const double ang = a0 + sweep * s / steps;
      emit(project(p, p.centre + Vec2(std::cos(ang), std::sin(ang))), false);
    }
  };
  // Junctions between neighbouring pieces of a run: where the two primitives meet (or, for a line passing
  // just outside a circle, the middle of their closest approach), not each piece's own projected end vertex.
  // A circle fitted to an arc that runs into a tangent straight keeps curving past the tangent point, and the
  // split between the pieces lands wherever the noise puts it: emitting the arc up to its own end vertex
  // then dents the edge by up to (overshoot)^2 / 2R before the line resumes.
  // Straights joined by a fillet: the piece before it ends at jin, the one after starts at jout.
  const std::size_t np = prims.size();
  std::vector<Vec2> jin(np), jout(np);  // [i]: between prims[i] and its successor in the same run
  std::vector<char> has_junction(np, 0);
  for (std::size_t i = 0; i < np; ++i) {
    const std::size_t j = (i + 1) % np;
    if (np < 2 || piece_run[i] != piece_run[j] || (j == 0 && nc > 0)) continue;
    const Primitive& pa = prims[i];
    const Primitive& pb = prims[j];
    if (has_fillet[i]) {
      jin[i] = project(pa, fillets[i].t1), jout[i] = project(pb, fillets[i].t2);
      has_junction[i] = 1;
      continue;
    }
    const Vec2 ea = project(pa, u.at(pa.last)), sb = project(pb, u.at(pb.first));
    const Vec2 near = 0.5 * (ea + sb);
    // A tangent pair meets at the tangent point wherever the noise put the split between their vertices.
    const double reach = 3 * unit + (ea - sb).norm() +
                         (tangent_junction[i] ? 0.5 * std::min(u.S(pa.last) - u.S(pa.first), u.S(pb.last) - u.S(pb.first)) : 0);
    Vec2 x;
    bool ok = intersect(pa, pb, pitch, bias_scale, near, x) && (x - near).norm() <= reach;
    if (!ok && pa.circle != pb.circle) {
      // no crossing: the line's foot of the circle's centre and the circle point above it
      const Primitive& c = pa.circle ? pa : pb;
      const Primitive& l = pa.circle ? pb : pa;
      const Vec2 foot = project(l, c.centre);
      const Vec2 on_circle = project(c, foot);
      x = 0.5 * (foot + on_circle);
      ok = (foot - on_circle).norm() <= tolerance + 0.5 * unit && (x - near).norm() <= reach;
    }
    if (ok) jin[i] = jout[i] = x, has_junction[i] = 1;
  }
  // The joint after piece i: its start, the fillet between, and (with_out) its end where the next piece starts.
  auto emit_joint = [&](std::size_t i, bool with_out) {
    emit(jin[i], false);
    if (!has_fillet[i]) return;
    emit_piece(fillets[i].arc, &jin[i], &jout[i]);
    if (with_out) emit(jout[i], false);
  };
  // emit_piece() leaves out the `from` and `to` points it is given: corners and joints are emitted here.
  if (nc == 0) {
    const bool wraps = np >= 2 && has_junction[np - 1];
    if (wraps) emit(jout[np - 1], false);
    for (std::size_t i = 0; i < np; ++i) {
      const Vec2* from = i == 0 ? (wraps ? &jout[np - 1] : nullptr) : has_junction[i - 1] ? &jout[i - 1] : nullptr;
      const Vec2* to = has_junction[i] ? &jin[i] : nullptr;
      emit_piece(prims[i], from, to);
      if (to) {
        if (i + 1 < np) emit_joint(i, true);
        else if (has_fillet[i]) emit_joint(i, false);  // the wrap-around joint: its end was emitted first
      }
    }
    return out;
  }
  for (int k = 0; k < nc; ++k) {
    emit(corner_pos[k], true);
    for (std::size_t i = 0; i < np; ++i) {
      if (piece_run[i] != k) continue;
      const bool first = i == 0 || piece_run[i - 1] != k;
      const bool last = i + 1 == np || piece_run[i + 1] != k;
      // arcs next to a corner start / end exactly at it; lines run through it anyway
      const Vec2* from = first ? &corner_pos[k] : has_junction[i - 1] ? &jout[i - 1] : nullptr;
      const Vec2* to = last ? &corner_pos[(k + 1) % nc] : has_junction[i] ? &jin[i] : nullptr;
      emit_piece(prims[i], from, to);
      if (!last && has_junction[i]) emit_joint(i, true);
    }
  }
  return out;
}

}  // namespace hg::path_planner
