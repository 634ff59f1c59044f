// Steps 4 and 5: tool orientation per waypoint, loop order and start points, lead-in/lead-out arcs,
// approach and retract at a safe height, travel between loops.
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

std::vector<PlateWaypoint> sequence(const std::vector<GrindLoop>& loops, const Vec2& start, const SequenceOptions& o) {
  std::vector<PlateWaypoint> path;
  const Ordering ord = order_loops(loops, start);
  const bool reversed = travel_reversed(o.direction, o.spindle_clockwise);
  const double z = o.z, zs = o.z + o.safe_height;
  for (std::size_t e = 0; e < ord.order.size(); ++e) {
    const GrindLoop& gl = loops[ord.order[e]];
    const Ring& P = gl.ring.points;
    const long n = long(P.size());
    const long s = ord.start_vertex[e];
    const auto idx = std::int16_t(gl.loop_index);
    // Traversal order of the ring's vertices, starting (and ending) at s.
    std::vector<Vec2> trav;
    trav.reserve(n + 1);
    for (long k = 0; k <= n; ++k) trav.push_back(P[((reversed ? s - k : s + k) % n + n) % n]);
    // Tangent (central difference) and away-from-material normal for each traversal point.
    const std::size_t T = trav.size();
    std::vector<Vec2> tan(T), away(T);
    for (std::size_t k = 0; k < T; ++k) {
      const Vec2 prev = trav[k == 0 ? T - 2 : k - 1], next = trav[k + 1 == T ? 1 : k + 1];
      Vec2 t = next - prev;
      if (t.squaredNorm() == 0) t = Vec2::UnitX();
      tan[k] = t.normalized();
      // Canonical travel has material on the left, so away = right of the canonical tangent.
      away[k] = reversed ? Vec2(-right_of(tan[k])) : right_of(tan[k]);
    }
    const Eigen::Quaterniond q0 = tool_orientation(tan[0], away[0], o.tilt);
    double radius = o.lead_radius;
    if (gl.hole) radius = std::min(radius, 0.3 * std::sqrt(std::abs(signed_area(P)) / M_PI));
    const std::vector<Vec2> lin = lead_in_arc(trav[0], tan[0], away[0], radius, o.lead_angle, o.step);
    const std::vector<Vec2> lout = lead_out_arc(trav[0], tan[0], away[0], radius, o.lead_angle, o.step);
    auto add = [&](const Vec2& p, double h, const Eigen::Quaterniond& q, double speed, std::int8_t kind,
                   std::int16_t loop) {
      path.push_back({Vec3(p.x(), p.y(), h), q, speed, kind, loop});
    };
    add(lin.front(), zs, q0, o.travel_speed, e == 0 ? kApproach : kTravel, -1);
    add(lin.front(), z, q0, o.approach_speed, kApproach, idx);
    for (std::size_t k = 1; k < lin.size(); ++k) add(lin[k], z, q0, o.grind_speed, kLeadIn, idx);
    for (std::size_t k = 1; k < T; ++k)
      add(trav[k], z, tool_orientation(tan[k], away[k], o.tilt), o.grind_speed, kGrind, idx);
    for (std::size_t k = 1; k < lout.size(); ++k) add(lout[k], z, q0, o.grind_speed, kLeadOut, idx);
    add(lout.back(), zs, q0, o.approach_speed, kRetract, idx);
  }
  return path;
}

}  // namespace hg::path_planner
