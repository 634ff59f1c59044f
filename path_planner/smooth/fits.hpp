// The smoothing step's geometry (smooth/fits.cpp): the ring's coordinate moments, TLS lines, geometric
// circles, residuals and intersections of the fitted primitives. Internal to path_planner.
#pragma once

#include "path_planner/pipeline.hpp"

#include <cmath>
#include <vector>

namespace hg::path_planner::smooth {

inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
inline double turn(const Vec2& a, const Vec2& b) { return std::atan2(cross(a, b), a.dot(b)); }
// Outward (away from material, i.e. right of travel) normal of a travel direction.
inline Vec2 right_of(const Vec2& t) { return Vec2(t.y(), -t.x()); }

// The ring unrolled three times (unwrapped index j in [-n, 2n)) with prefix sums of the moments of the
// coordinates (relative to the first vertex, for precision), so that a TLS line over any index range
// costs O(1).
struct Unrolled {
  int n = 0;
  Vec2 origin;
  std::vector<Vec2> q;                        // q[j + n]: vertex j relative to origin
  std::vector<double> s;                      // s[j + n]: arc length at vertex j
  std::vector<double> mx, my, mxx, mxy, myy;  // prefix sums over q[0 .. k-1]

  explicit Unrolled(const Ring& ring);
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
Line fit_line(const Unrolled& u, long j0, long j1);

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
bool fit_circle(const Unrolled& u, long j0, long j1, Primitive& c);
// Refit circle `c` over its vertices tangent to the given lines (its neighbours within a run, where the
// edge is smooth by construction: no corner was found there). A free circle fitted to a part of a noisy
// arc comes out off in centre and radius by a fair fraction of the noise (the shorter the arc, the worse);
// tangency lets the straights' many vertices hold it in place. Soft constraints, weighted to be nearly
// hard, in the same Gauss-Newton as fit_circle; the centre stays on the side of each line it is on.
void refit_tangent(const Unrolled& u, Primitive& c, const std::vector<const Primitive*>& lines);

// Signed distance of q from the primitive: left of travel positive for a line, outside positive for a circle.
double residual(const Primitive& p, const Vec2& q);
// Largest |mean residual| over any `w` consecutive vertices of the piece (the whole piece when shorter):
// a systematic misfit shows up there, noise averages out. `r` is scratch space.
double worst_window_mean(const Unrolled& u, const Primitive& p, long j0, long j1, int w, std::vector<double>& r);
// Tangent (travel direction) of a primitive at point q.
Vec2 tangent_at(const Primitive& p, const Vec2& q);
// Mean gap between the outermost pixel centres and an edge of tangent t (pixel grid along the plate axes).
double edge_bias(const Vec2& t, double pitch);
// Intersection of two primitives (edge-compensated by bias_scale * edge_bias along their outward normals)
// nearest to `near`. False when they do not meet.
bool intersect(const Primitive& a, const Primitive& b, double pitch, double bias_scale, const Vec2& near, Vec2& x);

}  // namespace hg::path_planner::smooth
