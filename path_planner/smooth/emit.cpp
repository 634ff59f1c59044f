// Emit: the pieces as points -- corners, line end points, arcs sampled with a 5 um chord error, all
// edge-compensated.
#include "path_planner/smooth/stages.hpp"

#include <cmath>

namespace hg::path_planner::smooth {

namespace {

// Where one piece hands over to the next of its run: `in` ends the piece, `out` starts the next (the two
// differ across a fillet).
struct Joint {
  bool exists = false;
  Vec2 in = Vec2::Zero(), out = Vec2::Zero();
};

// q projected onto the edge-compensated primitive.
Vec2 project(const SmoothContext& c, const Primitive& p, const Vec2& q) {
  const Vec2 t = tangent_at(p, q);
  const double b = c.bias_scale * edge_bias(t, c.pitch);
  if (!p.circle) return p.centre + (q - p.centre).dot(p.dir) * p.dir + b * right_of(p.dir);
  const Vec2 radial = (q - p.centre).normalized();
  return p.centre + (p.radius + (p.ccw ? b : -b)) * radial;
}

// Junction of two neighbouring pieces of a run: where the two primitives meet (or, for a line passing just
// outside a circle, the middle of their closest approach), not each piece's own projected end vertex. A
// circle fitted to an arc that runs into a tangent straight keeps curving past the tangent point, and the
// split between the pieces lands wherever the noise puts it: emitting the arc up to its own end vertex then
// dents the edge by up to (overshoot)^2 / 2R before the line resumes. Straights joined by a fillet: the
// piece before it ends at its first tangent point, the one after starts at the second.
Joint joint_of(const SmoothContext& c, const Piece& a, const Piece& b) {
  const Unrolled& u = c.u;
  const Primitive& pa = a.prim;
  const Primitive& pb = b.prim;
  if (a.fillet) return {true, project(c, pa, a.fillet->t1), project(c, pb, a.fillet->t2)};
  const Vec2 ea = project(c, pa, u.at(pa.last)), sb = project(c, pb, u.at(pb.first));
  const Vec2 near = 0.5 * (ea + sb);
  // Two pieces of a run meet where their primitives meet wherever the noise put the split between their
  // vertices: no corner lies between them, and the greedy fit runs past the true junction (a circle keeps
  // explaining a straight's first vertices within the tolerance) by up to half the shorter piece. Tangent
  // pairs and pairs left free alike (a straight too short to hold its arc tangent): without a joint the two
  // pieces' own ends are bridged by a chord that turns twice by more than a corner, a notch the round tool
  // cannot enter in an edge that is smooth there.
  const double reach =
      3 * c.unit + (ea - sb).norm() + 0.5 * std::min(u.S(pa.last) - u.S(pa.first), u.S(pb.last) - u.S(pb.first));
  Vec2 x;
  bool ok = intersect(pa, pb, c.pitch, c.bias_scale, near, x) && (x - near).norm() <= reach;
  if (!ok && pa.circle != pb.circle) {
    // no crossing: the line's foot of the circle's centre and the circle point above it
    const Primitive& circle = pa.circle ? pa : pb;
    const Primitive& l = pa.circle ? pb : pa;
    const Vec2 foot = project(c, l, circle.centre);
    const Vec2 on_circle = project(c, circle, foot);
    x = 0.5 * (foot + on_circle);
    ok = (foot - on_circle).norm() <= c.tolerance + 0.5 * c.unit && (x - near).norm() <= reach;
  }
  if (!ok) return {};
  return {true, x, x};
}

// Appends points to the smoothed ring.
struct Emitter {
  const SmoothContext& c;
  SmoothedRing out;

  void point(const Vec2& p, bool corner) {
    out.points.push_back(c.u.origin + p);
    out.corner.push_back(corner ? 1 : 0);
  }
  // A piece from `from` to `to` (its own projected end vertices when null), leaving those two out.
  void piece(const Primitive& p, const Vec2* from, const Vec2* to);
  // The joint after a piece: its start, the fillet between, and (with_out) its end where the next starts.
  void joint(const Piece& p, const Joint& j, bool with_out) {
    point(j.in, false);
    if (!p.fillet) return;
    piece(p.fillet->arc, &j.in, &j.out);
    if (with_out) point(j.out, false);
  }
};

void Emitter::piece(const Primitive& p, const Vec2* from, const Vec2* to) {
  const Unrolled& u = c.u;
  const Vec2 a = from ? *from : project(c, p, u.at(p.first));
  const Vec2 b = to ? *to : project(c, p, u.at(p.last));
  const bool whole_loop = p.first + u.n - 1 <= p.last;
  if (!p.circle) {
    if (!from) point(a, false);
    if (!to) point(b, false);
    return;
  }
  double a0 = std::atan2((a - p.centre).y(), (a - p.centre).x());
  double sweep = turn(a - p.centre, b - p.centre);
  if (whole_loop) {
    sweep = p.ccw ? 2 * M_PI : -2 * M_PI;
  } else {
    // The piece's own sweep, from its end vertices, in the circle's sense (it can exceed half a turn).
    const Vec2 own_a = project(c, p, u.at(p.first)), own_b = project(c, p, u.at(p.last));
    double own = turn(own_a - p.centre, own_b - p.centre);
    if (p.ccw && own < 0) own += 2 * M_PI;
    if (!p.ccw && own > 0) own -= 2 * M_PI;
    // Between given end points (junctions), the sweep is the one nearest the piece's own: the junctions
    // can fall on either side of its end vertices, and both on one point when the circle is all of a
    // loop but a short straight (a dropout's flat), where the principal angle (0) lost the whole turn.
    sweep += 2 * M_PI * std::round((own - sweep) / (2 * M_PI));
    // Ends that passed each other (a short arc between two junctions) leave the chord between them.
    if (p.ccw ? sweep < 0 : sweep > 0) {
      if (!from) point(a, false);
      if (!to) point(b, false);
      return;
    }
  }
  const double chord = 5e-6;
  const double dstep = 2 * std::sqrt(2 * chord / p.radius);
  const int steps = std::max(1, int(std::ceil(std::abs(sweep) / dstep)));
  const int last = whole_loop ? steps - 1 : steps;
  for (int s = from ? 1 : 0; s <= last; ++s) {
    if (s == steps && to) break;
    const double ang = a0 + sweep * s / steps;
    point(project(c, p, p.centre + Vec2(std::cos(ang), std::sin(ang))), false);
  }
}

}  // namespace

SmoothedRing emit_ring(const SmoothContext& c, const Pieces& p, const Corners& corners) {
  const std::size_t np = p.size();
  const int nc = int(corners.size());
  std::vector<Joint> joint(np);  // [i]: between p[i] and its successor in the same run
  for (std::size_t i = 0; i < np; ++i) {
    const std::size_t j = (i + 1) % np;
    if (np < 2 || p[i].run != p[j].run || (j == 0 && nc > 0)) continue;
    joint[i] = joint_of(c, p[i], p[j]);
  }
  Emitter e{c, {}};
  // Emitter::piece() leaves out the `from` and `to` points it is given: corners and joints are emitted here.
  if (nc == 0) {
    const bool wraps = np >= 2 && joint[np - 1].exists;
    if (wraps) e.point(joint[np - 1].out, false);
    for (std::size_t i = 0; i < np; ++i) {
      const Vec2* from = i == 0                ? (wraps ? &joint[np - 1].out : nullptr)
                         : joint[i - 1].exists ? &joint[i - 1].out
                                               : nullptr;
      const Vec2* to = joint[i].exists ? &joint[i].in : nullptr;
      e.piece(p[i].prim, from, to);
      if (to) {
        if (i + 1 < np) e.joint(p[i], joint[i], true);
        else if (p[i].fillet)
          e.joint(p[i], joint[i], false);  // the wrap-around joint: its end was emitted first
      }
    }
    return e.out;
  }
  for (int k = 0; k < nc; ++k) {
    e.point(corners[k].at, true);
    for (std::size_t i = 0; i < np; ++i) {
      if (p[i].run != k) continue;
      const bool first = i == 0 || p[i - 1].run != k;
      const bool last = i + 1 == np || p[i + 1].run != k;
      // arcs next to a corner start / end exactly at it; lines run through it anyway
      const Vec2* from = first ? &corners[k].at : joint[i - 1].exists ? &joint[i - 1].out : nullptr;
      const Vec2* to = last ? &corners[(k + 1) % nc].at : joint[i].exists ? &joint[i].in : nullptr;
      e.piece(p[i].prim, from, to);
      if (!last && joint[i].exists) e.joint(p[i], joint[i], true);
    }
  }
  return e.out;
}

}  // namespace hg::path_planner::smooth
