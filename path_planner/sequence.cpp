// Steps 4 and 5: tool orientation per waypoint, loop order and start points, one pass per loop; the
// lead-in/lead-out arcs here are the leads modifier's (modifiers.cpp).
#include "path_planner/pipeline.hpp"

#include <cmath>
#include <limits>

namespace hg::path_planner {

namespace {
Vec2 right_of(const Vec2& t) { return Vec2(t.y(), -t.x()); }
}  // namespace

bool travel_reversed(Direction direction, bool spindle_clockwise) {
  const bool climb = direction == Direction::Climb;
  return climb == spindle_clockwise;
}

Eigen::Quaterniond tool_orientation(const Vec2& tangent, const Vec2& away_normal, double tilt) {
  const Vec3 x(tangent.x(), tangent.y(), 0);
  const Vec3 z = std::cos(tilt) * Vec3(0, 0, -1) - std::sin(tilt) * Vec3(away_normal.x(), away_normal.y(), 0);
  const Vec3 y = z.cross(x);
  Eigen::Matrix3d R;
  R.col(0) = x.normalized();
  R.col(1) = y.normalized();
  R.col(2) = z.normalized();
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // one of the two equal quaternions, for reproducible output
  return q;
}

Ordering order_loops(const std::vector<GrindLoop>& loops, const Vec2& start) {
  Ordering o;
  std::vector<std::uint8_t> used(loops.size(), 0);
  Vec2 here = start;
  for (std::size_t step = 0; step < loops.size(); ++step) {
    double best = std::numeric_limits<double>::infinity();
    int best_loop = -1, best_vertex = 0;
    for (std::size_t k = 0; k < loops.size(); ++k) {
      if (used[k]) continue;
      const SampledRing& r = loops[k].ring;
      bool any_smooth = false;
      for (std::uint8_t c : r.corner) any_smooth |= !c;
      for (std::size_t i = 0; i < r.points.size(); ++i) {
        if (any_smooth && r.corner[i]) continue;  // never start (and lead in) at a corner
        const double d = (r.points[i] - here).squaredNorm();
        if (d < best) best = d, best_loop = int(k), best_vertex = int(i);
      }
    }
    if (best_loop < 0) break;
    used[best_loop] = 1;
    o.order.push_back(best_loop);
    o.start_vertex.push_back(best_vertex);
    here = loops[best_loop].ring.points[best_vertex];
  }
  return o;
}

std::vector<Vec2> lead_in_arc(const Vec2& p0, const Vec2& t, const Vec2& m, double radius, double sweep, double step) {
  // Circle centre c = p0 + radius m; P(phi) = c - radius (m cos phi + t sin phi), phi from sweep down to 0:
  // at phi = 0 the point is p0 and the motion is along +t.
  const Vec2 c = p0 + radius * m;
  const int segs = std::max(3, int(std::ceil(radius * sweep / std::max(step, 1e-9))));
  std::vector<Vec2> pts;
  pts.reserve(segs + 1);
  for (int k = segs; k >= 0; --k) {
    const double phi = sweep * double(k) / segs;
    pts.push_back(k == 0 ? p0 : Vec2(c - radius * (m * std::cos(phi) + t * std::sin(phi))));
  }
  return pts;
}

std::vector<Vec2> lead_out_arc(const Vec2& p0, const Vec2& t, const Vec2& m, double radius, double sweep, double step) {
  // Mirror image of the lead-in: Q(phi) = c - radius (m cos phi - t sin phi), phi from 0 up to sweep.
  const Vec2 c = p0 + radius * m;
  const int segs = std::max(3, int(std::ceil(radius * sweep / std::max(step, 1e-9))));
  std::vector<Vec2> pts;
  pts.reserve(segs + 1);
  for (int k = 0; k <= segs; ++k) {
    const double phi = sweep * double(k) / segs;
    pts.push_back(k == 0 ? p0 : Vec2(c - radius * (m * std::cos(phi) - t * std::sin(phi))));
  }
  return pts;
}

namespace {

// The loop's vertices from vertex s round to it again, in the travel direction.
std::vector<Vec2> traversal(const Ring& P, long s, bool reversed) {
  const long n = long(P.size());
  std::vector<Vec2> trav;
  trav.reserve(n + 1);
  for (long k = 0; k <= n; ++k) trav.push_back(P[((reversed ? s - k : s + k) % n + n) % n]);
  return trav;
}

Pass make_pass(const GrindLoop& gl, long s, bool reversed, const SequenceOptions& o) {
  const std::vector<Vec2> trav = traversal(gl.ring.points, s, reversed);
  Pass pass;
  pass.loop = std::int16_t(gl.loop_index);
  pass.hole = gl.hole;
  pass.area = std::abs(signed_area(gl.ring.points));
  const std::size_t T = trav.size();
  for (std::size_t k = 0; k < T; ++k) {
    // Tangent (central difference) and away-from-material normal; the closing point repeats the start's.
    const Vec2 prev = trav[k == 0 ? T - 2 : k - 1], next = trav[k + 1 == T ? 1 : k + 1];
    Vec2 t = next - prev;
    if (t.squaredNorm() == 0) t = Vec2::UnitX();
    t.normalize();
    // Canonical travel has material on the left, so away = right of the canonical tangent.
    const Vec2 away = reversed ? Vec2(-right_of(t)) : right_of(t);
    if (k == 0) pass.tangent = t, pass.away = away;
    const bool entry = k == 0;
    pass.waypoints.push_back({Vec3(trav[k].x(), trav[k].y(), o.z), tool_orientation(t, away, o.tilt),
                              entry ? o.approach_speed : o.grind_speed, entry ? kApproach : kGrind, pass.loop});
  }
  return pass;
}

}  // namespace

std::vector<Pass> sequence(const std::vector<GrindLoop>& loops, const Vec2& start, const SequenceOptions& o) {
  const Ordering ord = order_loops(loops, start);
  const bool reversed = travel_reversed(o.direction, o.spindle_clockwise);
  std::vector<Pass> passes;
  for (std::size_t e = 0; e < ord.order.size(); ++e)
    passes.push_back(make_pass(loops[ord.order[e]], ord.start_vertex[e], reversed, o));
  return passes;
}

}  // namespace hg::path_planner
