// Corner candidates and their confirmation by the pieces fitted beside them.
#include "path_planner/smooth/stages.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hg::path_planner::smooth {

namespace {

// Turn at every vertex between one-sided TLS lines one scale (t1) and two scales (t2) behind and ahead of
// it (two pointers); 0 where the turn at one scale is under the corner angle.
void two_scale_turns(const SmoothContext& c, std::vector<double>& t1, std::vector<double>& t2) {
  const Unrolled& u = c.u;
  const long n = c.n;
  const double scale = c.scale, cos_corner = std::cos(c.corner_angle);
  t1.assign(n, 0), t2.assign(n, 0);
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

// Gap at a corner: the alpha shape fills a concave corner and the pixels thin out toward an acute tip,
// over about two units divided by sin(interior / 2).
double gap_at(const SmoothContext& c, const Corner& k) {
  return 2.0 * c.unit / std::sin(std::max(0.2, M_PI - std::abs(k.turn)) / 2);
}

// The corner to drop because it leaves no run between it and its successor (the weaker of the two), or -1.
// A run needs one residual window of vertices: fewer fit a line of any direction, and two candidates that
// close are one bend the noise split (a slot's 20 mm end under pm806 noise turns by 40-55 deg over one
// corner scale at two spots a few vertices apart), not two corners with a straight between.
int crowded_corner(const SmoothContext& c, const Corners& corners) {
  const int nc = int(corners.size());
  long j0 = 0, j1 = 0;
  for (int k = 0; k < nc; ++k)
    if (!run_range(c, corners, k, j0, j1) || j1 - j0 + 1 < c.win)
      return std::abs(corners[k].turn) < std::abs(corners[(k + 1) % nc].turn) ? k : (k + 1) % nc;
  return -1;
}

// Nearest distance from x of the ring's vertices within `reach` (arc length) of vertex v.
double closest_vertex(const SmoothContext& c, long v, double reach, const Vec2& x) {
  const Unrolled& u = c.u;
  const long n = c.n;
  double closest = std::numeric_limits<double>::max();
  for (long j = v; j > v - n + 1 && u.S(v) - u.S(j) <= reach; --j) closest = std::min(closest, (u.at(j) - x).norm());
  for (long j = v; j < v + n - 1 && u.S(j) - u.S(v) <= reach; ++j) closest = std::min(closest, (u.at(j) - x).norm());
  return closest;
}

// A fillet that the closest vertex alone does not reveal (noise brought one near the tip) shows in a fit of
// straight, fillet, straight from the last long straight before the corner (piece `pa_seq`) to the first
// after, over at most two short pieces on each side (the greedy fit may have made them of parts of the
// fillet). A wide fillet may also have been taken for two corners with short pieces between: the corners
// crossed are appended to `crossed` (run r starts at corner r).
bool fillet_at_corner(const SmoothContext& c, const Pieces& p, long pa_seq, std::vector<int>& crossed) {
  const long np = long(p.size()), n = c.n;
  // piece at sequence position `seq` (one loop on: vertices n further)
  auto at = [&](long seq) { return ((seq % np) + np) % np; };
  auto first = [&](long seq) { return p[at(seq)].prim.first + (seq - at(seq)) / np * n; };
  auto last = [&](long seq) { return p[at(seq)].prim.last + (seq - at(seq)) / np * n; };
  auto is_long_line = [&](long seq) { return long_line(c, p[at(seq)].prim); };
  long ia = pa_seq, ib = pa_seq + 1;
  for (int step = 0; step < 2 && !is_long_line(ia); ++step) --ia;
  for (int step = 0; step < 2 && !is_long_line(ib); ++step) ++ib;
  std::vector<int> between;
  for (long q = ia; q < ib; ++q)
    if (p[at(q)].run != p[at(q + 1)].run) between.push_back(p[at(q + 1)].run);
  Fillet f;
  const bool fillet = ib - ia < np && between.size() <= 2 && is_long_line(ia) && is_long_line(ib) &&
                      fit_fillet(c, first(ia), last(ia), first(ib), last(ib), f);
  if (fillet) crossed.insert(crossed.end(), between.begin(), between.end());
  return fillet;
}

// A line and a circle beside a candidate that a circle tangent to the line explains, its vertices as well as
// the greedy fit explains a piece (no window mean beyond the tolerance): a straight running into its tangent
// arc (a slot's end), not a corner. The free circle fitted to a part of an arc is off in centre and radius
// by the noise, and a line that a circle of radius R crosses a depth d deep meets it at acos(1 - d / R), about
// sqrt(2 d / R): d at the tolerance (1.2 mm at pm806) makes 19 deg at R20, above 0.6 corner_angle, from noise
// alone. The corner stays where the tangent hypothesis misfits (a real corner bends the vertices off it).
bool tangent_arc_at_corner(const SmoothContext& c, const Primitive& pa, const Primitive& pb) {
  thread_local std::vector<double> scratch;
  if (pa.circle == pb.circle) return false;
  Primitive arc = pa.circle ? pa : pb;
  refit_tangent(c.u, arc, {pa.circle ? &pb : &pa});
  return worst_window_mean(c.u, arc, arc.first, arc.last, c.win, scratch) <= c.tolerance;
}

// Corner positions from the primitives on both sides; the corners (indices) that they do not confirm.
std::vector<int> unconfirmed(const SmoothContext& c, const Pieces& p, Corners& corners) {
  std::vector<int> drop;
  std::size_t after = 0;
  for (int k = 0; k < int(corners.size()); ++k) {
    while (p[after].run != k) ++after;  // first primitive of run k
    const long pa_seq = long(after == 0 ? p.size() : after) - 1;
    const Primitive& pa = p[pa_seq].prim;
    const Primitive& pb = p[after].prim;
    const Vec2 near = c.u.at(corners[k].vertex);
    const double interior = std::max(0.2, M_PI - std::abs(corners[k].turn)), gap = gap_at(c, corners[k]);
    Vec2 x;
    const bool met = intersect(pa, pb, c.pitch, c.bias_scale, near, x);
    const double angle = met ? std::abs(turn(tangent_at(pa, x), tangent_at(pb, x))) : 0;
    // The primitives must meet near the candidate (within the gap it was cut by) at a real angle.
    // And the outline must come close to where they meet: at a sharp corner the pixels reach the tip up
    // to the alpha shape's chamfer (about half the gap) and a pitch of staircase, while a fillet of radius
    // R stays R (1/sin(interior/2) - 1) away from it (0.41 R at 90 deg) -- a fillet is an arc, not a corner.
    const double closest =
        met ? closest_vertex(c, corners[k].vertex, gap + 2 * c.unit, x) : std::numeric_limits<double>::max();
    const bool fillet = met && fillet_at_corner(c, p, pa_seq, drop);
    if (!met || (x - near).norm() > gap + 2 * c.unit / std::sin(interior / 2) || angle < 0.6 * c.corner_angle ||
        closest > 0.5 * gap + c.unit || fillet || tangent_arc_at_corner(c, pa, pb))
      drop.push_back(k);
    else
      corners[k].at = x;
  }
  std::sort(drop.begin(), drop.end());
  drop.erase(std::unique(drop.begin(), drop.end()), drop.end());
  return drop;
}

}  // namespace

bool run_range(const SmoothContext& c, const Corners& corners, int k, long& j0, long& j1) {
  const int nc = int(corners.size());
  const Unrolled& u = c.u;
  const long c0 = corners[k].vertex, c1 = corners[(k + 1) % nc].vertex + (k + 1 == nc ? c.n : 0);
  const double gap0 = gap_at(c, corners[k]), gap1 = gap_at(c, corners[(k + 1) % nc]);
  j0 = c0, j1 = c1;
  while (j0 < c1 && u.S(j0) < u.S(c0) + gap0) ++j0;
  while (j1 > j0 && u.S(j1) > u.S(c1) - gap1) --j1;
  return j1 - j0 >= 2;
}

Corners corner_candidates(const SmoothContext& c) {
  const Unrolled& u = c.u;
  const long n = c.n;
  std::vector<double> t1, t2;
  two_scale_turns(c, t1, t2);
  // A corner turns by at least the corner angle, its turn does not grow by half when the scale doubles (an
  // arc's does), and it is the largest turn within one scale.
  Corners corners;
  for (long i = 0; i < n; ++i) {
    if (!(std::abs(t1[i]) >= c.corner_angle && std::abs(t2[i]) < 1.5 * std::abs(t1[i]))) continue;
    bool best = true;
    const double si = u.S(i);
    for (long j = i - 1; best && i - j < n / 2 && si - u.S(j) <= c.scale; --j)
      if (std::abs(t1[u.wrap(j)]) > std::abs(t1[i])) best = false;
    for (long j = i + 1; best && j - i < n / 2 && u.S(j) - si <= c.scale; ++j)
      if (std::abs(t1[u.wrap(j)]) >= std::abs(t1[i])) best = false;
    if (best) corners.push_back({i, t1[i], Vec2::Zero()});
  }
  if (c.total < 8 * c.scale) corners.clear();  // a loop this small has no room for corners and runs
  return corners;
}

Pieces confirm_corners(const SmoothContext& c, Corners& corners) {
  for (int attempt = 0;; ++attempt) {
    if (attempt == 8) corners.clear();  // give up on corners: the loop as one smooth run
    if (corners.empty()) return segment_run(c, 0, c.n - 1, 0, true);
    if (const int crowded = crowded_corner(c, corners); crowded >= 0) {
      corners.erase(corners.begin() + crowded);
      continue;
    }
    Pieces pieces;
    for (int k = 0; k < int(corners.size()); ++k) {
      long j0 = 0, j1 = 0;
      run_range(c, corners, k, j0, j1);
      Pieces run = segment_run(c, j0, j1, k, false);
      pieces.insert(pieces.end(), run.begin(), run.end());
    }
    const std::vector<int> drop = unconfirmed(c, pieces, corners);
    if (drop.empty()) return pieces;
    for (auto it = drop.rbegin(); it != drop.rend(); ++it) corners.erase(corners.begin() + *it);
  }
}

void replace_corners(const SmoothContext& c, const Pieces& pieces, Corners& corners) {
  const std::size_t np = pieces.size();
  std::size_t after = 0;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    while (pieces[after].run != int(k)) ++after;
    const std::size_t before = after == 0 ? np - 1 : after - 1;
    Vec2 x;
    if (intersect(pieces[before].prim, pieces[after].prim, c.pitch, c.bias_scale, corners[k].at, x) &&
        (x - corners[k].at).norm() <= 2 * c.unit)
      corners[k].at = x;
  }
}

}  // namespace hg::path_planner::smooth
