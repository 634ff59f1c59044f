// Step 7: validation before publishing: workspace box, table, speeds, unit quaternions, the robot bridge's
// corner acceleration rule, and no self-intersection of any grind loop.
#include "path_planner/pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hg::path_planner {

namespace {

double orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}
bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= p.y() &&
         p.y() <= std::max(a.y(), b.y());
}
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return true;
  if (o1 == 0 && on_segment(a, b, c)) return true;
  if (o2 == 0 && on_segment(a, b, d)) return true;
  if (o3 == 0 && on_segment(c, d, a)) return true;
  if (o4 == 0 && on_segment(c, d, b)) return true;
  return false;
}

std::string fmt(const char* f, double a, double b = 0, double c = 0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

}  // namespace

bool self_intersects(const std::vector<Vec2>& p) {
  const std::size_t n = p.size();
  if (n < 4) return false;
  // Uniform grid over the bounding box with about one segment per cell; each segment is listed in every
  // cell its bounding box covers (CSR arrays), and only segments sharing a cell are tested.
  Vec2 lo = p[0], hi = p[0];
  double total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    lo = lo.cwiseMin(p[i]);
    hi = hi.cwiseMax(p[i]);
    total += (p[(i + 1) % n] - p[i]).norm();
  }
  const double cell = std::max({total / double(n) * 2, (hi - lo).maxCoeff() / 2048, 1e-12});
  const int gx = int((hi.x() - lo.x()) / cell) + 1, gy = int((hi.y() - lo.y()) / cell) + 1;
  auto cx = [&](double x) { return std::clamp(int((x - lo.x()) / cell), 0, gx - 1); };
  auto cy = [&](double y) { return std::clamp(int((y - lo.y()) / cell), 0, gy - 1); };
  std::vector<std::uint32_t> start(std::size_t(gx) * gy + 1, 0);
  auto for_cells = [&](std::size_t i, auto&& fn) {
    const Vec2 a = p[i], b = p[(i + 1) % n];
    for (int y = cy(std::min(a.y(), b.y())); y <= cy(std::max(a.y(), b.y())); ++y)
      for (int x = cx(std::min(a.x(), b.x())); x <= cx(std::max(a.x(), b.x())); ++x) fn(std::size_t(y) * gx + x);
  };
  for (std::size_t i = 0; i < n; ++i) for_cells(i, [&](std::size_t c) { ++start[c + 1]; });
  for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1), segs(start.back());
  for (std::size_t i = 0; i < n; ++i) for_cells(i, [&](std::size_t c) { segs[fill[c]++] = std::uint32_t(i); });
  for (std::size_t c = 0; c + 1 < start.size(); ++c) {
    for (std::uint32_t a = start[c]; a < start[c + 1]; ++a)
      for (std::uint32_t b = a + 1; b < start[c + 1]; ++b) {
        const std::size_t i = std::min(segs[a], segs[b]), j = std::max(segs[a], segs[b]);
        if (j == i + 1 || (i == 0 && j == n - 1)) continue;  // neighbours share an end point
        if (segments_meet(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n])) return true;
      }
  }
  return false;
}

std::string validate(const std::vector<Waypoint>& path, const Limits& L, const Vec3& up, const Vec3& start) {
  if (path.empty()) return "path is empty";
  for (std::size_t i = 0; i < path.size(); ++i) {
    const Waypoint& w = path[i];
    const std::string at = "waypoint " + std::to_string(i) + ": ";
    if (!w.position.allFinite() || !w.orientation.coeffs().allFinite() || !std::isfinite(w.speed))
      return at + "non-finite value";
    if (!motion::inside_workspace(w.position, L))
      return at + fmt("position (%.4f, %.4f, %.4f) m", w.position.x(), w.position.y(), w.position.z()) +
             fmt(" is outside the workspace box (%.4f, %.4f, %.4f)", L.workspace_min.x(), L.workspace_min.y(),
                 L.workspace_min.z()) +
             fmt(" .. (%.4f, %.4f, %.4f) m (base frame)", L.workspace_max.x(), L.workspace_max.y(),
                 L.workspace_max.z());
    if (!motion::above_table(w.position, L))
      return at + fmt("z = %.4f m is not above the table (z = %.4f m)", w.position.z(), L.table_z);
    if (!(w.speed > 0) || w.speed > L.max_speed)
      return at + fmt("speed %.4f m/s is outside (0, %.4f] m/s", w.speed, L.max_speed);
    if (std::abs(w.orientation.norm() - 1) > 1e-6) return at + "orientation is not a unit quaternion";
  }
  // Corners, with the rule the robot bridge checks (motion/motion.hpp).
  std::vector<Vec3> position;
  std::vector<double> speed;
  for (const Waypoint& w : path) {
    position.push_back(w.position);
    speed.push_back(w.speed);
  }
  if (const auto fault = motion::first_corner_fault(position, speed, start, L.max_accel)) {
    const std::string at =
        "waypoint " + std::to_string(fault->waypoint) + " (" + waypoint::kind_name(path[fault->waypoint].kind) + "): ";
    if (fault->radius == 0) return at + "the path reverses here (corner radius 0): no speed can take it";
    return at +
           fmt("the corner (radius %.6f mm) at %.6f m/s needs %.6f m/s^2", fault->radius * 1e3, fault->speed,
               fault->lateral) +
           fmt(", more than max_accel %.6f m/s^2", L.max_accel);
  }
  // Grind loops: the lead-in's last point (the loop's start) and the grind waypoints that follow.
  const Vec3 e1 = up.unitOrthogonal(), e2 = up.normalized().cross(e1);
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (path[i].kind != kGrind || (i > 0 && path[i - 1].kind == kGrind)) continue;
    std::vector<Vec2> ring;
    if (i > 0) ring.emplace_back(path[i - 1].position.dot(e1), path[i - 1].position.dot(e2));
    std::size_t j = i;
    for (; j < path.size() && path[j].kind == kGrind && path[j].loop == path[i].loop; ++j)
      ring.emplace_back(path[j].position.dot(e1), path[j].position.dot(e2));
    if (ring.size() > 1 && (ring.back() - ring.front()).norm() == 0) ring.pop_back();  // closed: drop the repeat
    if (self_intersects(ring))
      return "grind loop " + std::to_string(path[i].loop) + " (waypoints " + std::to_string(i) + ".." +
             std::to_string(j - 1) + ") intersects itself";
  }
  return "";
}

}  // namespace hg::path_planner
