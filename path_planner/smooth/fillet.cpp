// Fillets: where two straights meet at a bend, straight - tangent arc - straight instead of the pieces
// between them (or a corner, or two).
//
// Under camera noise the greedy pieces share a short fillet out between the straights beside it (a line
// misses an R15 arc by less than the misfit tolerance for a third of its length at each end, and the middle
// alone bows too little to be told from a line), or the corner detector takes it for a corner at its scale;
// joining the straights at their intersection would then cut the corner the fillet rounds -- into the
// material at a concave one.
#include "path_planner/smooth/stages.hpp"

#include <cmath>
#include <limits>

namespace hg::path_planner::smooth {

namespace {

// Signed distance (left of travel positive) of q from straight a, fillet, straight b, whichever is nearest.
double fillet_residual(const Line& a, const Line& b, const Primitive& arc, const Vec2& t1, const Vec2& t2,
                       const Vec2& q) {
  const double s1 = (q - t1).dot(a.dir), s2 = (q - t2).dot(b.dir);
  double best = s1 <= 0 ? cross(a.dir, q - t1) : std::numeric_limits<double>::max();
  auto take = [&](double d) {
    if (std::abs(d) < std::abs(best)) best = d;
  };
  if (s2 >= 0) take(cross(b.dir, q - t2));
  const Vec2 r1 = t1 - arc.centre, r2 = t2 - arc.centre, rq = q - arc.centre;
  const double sense = cross(r1, r2);
  if (cross(r1, rq) * sense >= 0 && cross(rq, r2) * sense >= 0)
    take(arc.ccw ? arc.radius - rq.norm() : rq.norm() - arc.radius);
  if (best == std::numeric_limits<double>::max()) {  // between the pieces' ranges (a sharp bend): the nearer end
    const double d1 = (q - t1).norm(), d2 = (q - t2).norm();
    best = d1 < d2 ? (cross(a.dir, q - t1) >= 0 ? d1 : -d1) : (cross(b.dir, q - t2) >= 0 ? d2 : -d2);
  }
  return best;
}

// Turn phi from a to b and their intersection x; false under 15 deg (a fillet there bows too little to
// matter) or for parallel lines.
bool bend_of(const Line& a, const Line& b, double& phi, Vec2& x) {
  phi = turn(a.dir, b.dir);
  const double den = cross(a.dir, b.dir);
  if (std::abs(phi) < 15 * M_PI / 180 || std::abs(den) < 1e-9) return false;
  x = a.centre + (cross(b.centre - a.centre, b.dir) / den) * a.dir;
  return true;
}

// Towards the fillet's centre from straight a.
Vec2 centre_side(const Line& a, double phi) {
  return phi > 0 ? Vec2(-a.dir.y(), a.dir.x()) : Vec2(a.dir.y(), -a.dir.x());
}

// Radius in (0, r_max] minimising the squared distances of the vertices `near` from straight a, fillet,
// straight b (the bend at x): coarse scan, then golden section.
double fillet_radius(const Unrolled& u, const Line& la, const Line& lb, double phi, const Vec2& x, double r_max,
                     const std::vector<long>& near) {
  const double tan_half = std::tan(std::abs(phi) / 2);
  const Vec2 side = centre_side(la, phi);
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
    else
      lo = m1, m1 = m2, c1 = c2, m2 = lo + g * (hi - lo), c2 = cost(m2);
  }
  return 0.5 * (lo + hi);
}

// The misfit test of the pieces (worst_window_mean) applied to the whole model w0..w1, and the fillet's
// significance: the sum of squares it saves over the sharp bend x of the same straights, against the
// residual variance (an F statistic of one parameter; F > 25: docs/decisions/smooth-fillet-f-25.md).
bool fillet_explains(const SmoothContext& c, long w0, long w1, const Fillet& f, const Vec2& x) {
  const Unrolled& u = c.u;
  const long m = w1 - w0 + 1, w = std::min<long>(c.win, m);
  Primitive tip = f.arc;
  tip.radius = 0, tip.centre = x;
  double sum = 0, sharp_ss = 0, fillet_ss = 0;
  thread_local std::vector<double> res;
  res.resize(m);
  for (long j = w0; j <= w1; ++j) {
    res[j - w0] = fillet_residual(f.a, f.b, f.arc, f.t1, f.t2, u.at(j));
    fillet_ss += res[j - w0] * res[j - w0];
    sharp_ss += std::pow(fillet_residual(f.a, f.b, tip, x, x, u.at(j)), 2);
  }
  if (!(m > 10 && (sharp_ss - fillet_ss) > 25 * fillet_ss / double(m - 5))) return false;
  for (long k = 0; k < m; ++k) {
    sum += res[k];
    if (k >= w) sum -= res[k - w];
    if (k >= w - 1 && std::abs(sum) / double(w) > c.tolerance) return false;
  }
  return true;
}

}  // namespace

// The radius by a 1-D search with the straights held (fillet_radius), then each straight refitted on its
// vertices outside the fillet; four rounds. The tangent points stay within three corner scales of the
// bend. Accepted when the model explains the vertices as the pieces must and the fillet is real
// (fillet_explains): a radius under 3 units is what pixels and the alpha shape make of a sharp corner.
bool fit_fillet(const SmoothContext& c, long w0, long a1, long b0, long w1, Fillet& f) {
  if (a1 - w0 < 5 || w1 - b0 < 5 || b0 <= a1) return false;
  const Unrolled& u = c.u;
  const double unit = c.unit, max_tangent = 3 * c.scale;
  Line la = fit_line(u, w0, a1), lb = fit_line(u, b0, w1);
  double r = 0, phi = 0;
  long i1 = a1, i2 = b0;
  Vec2 x;
  thread_local std::vector<long> near;
  for (int round = 0; round < 4; ++round) {
    if (!bend_of(la, lb, phi, x)) return false;
    const double tan_half = std::tan(std::abs(phi) / 2);
    // The tangent points stay within the window (most of each side of it), and within max_tangent of the
    // bend: a longer fillet is an arc the greedy segmentation fits by itself.
    const double reach = std::min(max_tangent, 0.8 * std::min((x - u.at(w0)).dot(la.dir), (u.at(w1) - x).dot(lb.dir)));
    const double r_max = reach / tan_half;
    if (!(r_max > unit)) return false;
    // Only vertices near the bend depend on r: beyond the farthest tangent point they are scored against
    // the same straight for every r, and leaving them out does not move the minimum (a 10 k vertex loop has
    // straights of thousands).
    near.clear();
    for (long j = w0; j <= w1; ++j)
      if ((u.at(j) - x).norm() <= reach + 2 * unit) near.push_back(j);
    r = fillet_radius(u, la, lb, phi, x, r_max, near);
    // Each straight refitted on its vertices up to its tangent point.
    const double l = r * tan_half;
    i1 = w0, i2 = w1;
    while (i1 < w1 && (u.at(i1 + 1) - x).dot(la.dir) < -l) ++i1;
    while (i2 > w0 && (u.at(i2 - 1) - x).dot(lb.dir) > l) --i2;
    if (i1 - w0 < 5 || w1 - i2 < 5 || i2 <= i1) return false;
    la = fit_line(u, w0, i1), lb = fit_line(u, i2, w1);
  }
  if (!bend_of(la, lb, phi, x)) return false;
  if (!(r >= 3 * unit)) return false;
  const double l = r * std::tan(std::abs(phi) / 2);
  f.a = la, f.b = lb, f.a_last = i1, f.b_first = i2;
  f.t1 = x - l * la.dir, f.t2 = x + l * lb.dir;
  f.arc = Primitive{};
  f.arc.circle = true;
  f.arc.centre = f.t1 + r * centre_side(la, phi);
  f.arc.radius = r;
  f.arc.ccw = phi > 0;
  f.arc.first = i1, f.arc.last = i2;
  return fillet_explains(c, w0, w1, f, x);
}

namespace {

// Replaces pieces ia..ib by the fillet's two straights, the first carrying the fillet.
void replace(Pieces& p, std::size_t ia, std::size_t ib, const Fillet& f) {
  Piece a = p[ia], b = p[ib];
  a.prim.circle = b.prim.circle = false;
  a.prim.centre = f.a.centre, a.prim.dir = f.a.dir, a.prim.last = f.a_last;
  b.prim.centre = f.b.centre, b.prim.dir = f.b.dir, b.prim.first = f.b_first;
  b.run = a.run;
  a.tangent_next = false, a.fillet = f;
  b.fillet.reset();
  p.erase(p.begin() + long(ia), p.begin() + long(ib) + 1);
  p.insert(p.begin() + long(ia), {a, b});
}

// A run between two corners as a whole: straight, fillet, straight (the greedy pieces of a noisy fillet and
// its straights can be anything, a long flat arc over the fillet's end and half a straight included).
void fillet_whole_runs(const SmoothContext& c, Pieces& p) {
  for (std::size_t i0 = 0; i0 < p.size();) {
    std::size_t i1 = i0;
    while (i1 + 1 < p.size() && p[i1 + 1].run == p[i0].run) ++i1;
    if (i1 > i0) {
      const long w0 = p[i0].prim.first, w1 = p[i1].prim.last, third = (w1 - w0) / 3;
      const long a1 = long_line(c, p[i0].prim) ? p[i0].prim.last : w0 + third;
      const long b0 = long_line(c, p[i1].prim) ? p[i1].prim.first : w1 - third;
      Fillet f;
      if (fit_fillet(c, w0, a1, b0, w1, f)) {
        replace(p, i0, i1, f);
        i1 = i0 + 1;
      }
    }
    i0 = i1 + 1;
  }
}

// Within runs, between a straight and the next straight past at most two short pieces, each taken with the
// nearly collinear straights beyond it (a noise bump may have split one).
void fillet_between_straights(const SmoothContext& c, Pieces& p) {
  const double collinear = 5 * M_PI / 180;
  auto is_long_line = [&](std::size_t i) { return long_line(c, p[i].prim); };
  auto filleted = [&](std::size_t i) { return p[i].fillet.has_value(); };
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    const int run = p[i].run;
    if (!is_long_line(i) || filleted(i)) continue;
    std::size_t j = i + 1;
    while (j < p.size() && j <= i + 3 && p[j].run == run && !is_long_line(j)) ++j;
    if (j >= p.size() || j > i + 3 || p[j].run != run) continue;
    std::size_t ia = i, ib = j;
    while (ia > 0 && p[ia - 1].run == run && is_long_line(ia - 1) && !filleted(ia - 1) &&
           !(ia >= 2 && filleted(ia - 2)) && std::abs(turn(p[ia - 1].prim.dir, p[i].prim.dir)) < collinear)
      --ia;
    while (ib + 1 < p.size() && p[ib + 1].run == run && is_long_line(ib + 1) &&
           std::abs(turn(p[j].prim.dir, p[ib + 1].prim.dir)) < collinear)
      ++ib;
    Fillet f;
    if (!fit_fillet(c, p[ia].prim.first, p[i].prim.last, p[j].prim.first, p[ib].prim.last, f)) continue;
    replace(p, ia, ib, f);
    i = ia;  // on from the straight after the fillet
  }
}

}  // namespace

// Every piece between the straights is replaced by the refitted straights and the fillet. No fillet is
// looked for across the start of a loop without corners.
Pieces fit_fillets(const SmoothContext& c, Pieces pieces, bool has_corners) {
  if (has_corners) fillet_whole_runs(c, pieces);
  fillet_between_straights(c, pieces);
  return pieces;
}

}  // namespace hg::path_planner::smooth
