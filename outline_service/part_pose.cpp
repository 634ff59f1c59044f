#include "outline_service/part_pose.hpp"

#include "polygon/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace hg::outline_service {
namespace {

std::vector<polygon::Vec2> ring_of(const std::vector<outline::Vec2>& points) {
  std::vector<polygon::Vec2> ring;
  ring.reserve(points.size());
  for (const auto& p : points) ring.emplace_back(p.x, p.y);
  return ring;
}

bool inside(const std::vector<outline::Vec2>& poly, outline::Vec2 q) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto &a = poly[i], &b = poly[j];
    if ((a.y > q.y) != (b.y > q.y) && q.x < (b.x - a.x) * (q.y - a.y) / (b.y - a.y) + a.x) in = !in;
  }
  return in;
}

// The lattice points on the ring (Pick's B): each edge holds gcd(|du|, |dv|) lattice steps of `spacing`
// along the u, v axes (a chord across a staircase's notch holds one, a straight along the lattice one per
// pixel), at least its first vertex, a point of the cloud.
long lattice_points(const std::vector<outline::Vec2>& ring, double spacing) {
  long b = 0;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const long du = std::lround(std::abs(ring[i].x - ring[j].x) / spacing);
    const long dv = std::lround(std::abs(ring[i].y - ring[j].y) / spacing);
    b += std::max(1L, std::gcd(du, dv));
  }
  return b;
}

}  // namespace

std::vector<PartPose> part_poses(const std::vector<outline::Loop>& loops, double spacing) {
  std::vector<PartPose> out;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (loops[i].hole || loops[i].points.size() < 3) continue;
    PartPose pose;
    pose.outer_loop = i;
    const auto& outer = loops[i].points;
    // Moments about a nearby point keep the sums well conditioned.
    polygon::MomentSum sum(polygon::Vec2(outer[0].x, outer[0].y));
    sum.add(ring_of(outer));
    const bool lattice = spacing > 0;
    long boundary = lattice ? lattice_points(outer, spacing) : 0;
    int holes = 0;
    for (std::size_t j = 0; j < loops.size(); ++j) {
      if (!loops[j].hole || loops[j].points.empty()) continue;
      // A hole belongs to the smallest outer loop that contains it; holes of nested parts are rare on a
      // grinding table, so "contains its first vertex" decides.
      const auto& hole = loops[j].points;
      if (!inside(outer, hole[0])) continue;
      bool in_smaller = false;
      for (std::size_t k = 0; k < loops.size(); ++k)
        if (k != i && !loops[k].hole && loops[k].area < loops[i].area && inside(loops[k].points, hole[0]))
          in_smaller = true;
      if (in_smaller) continue;
      pose.holes.push_back(j);
      sum.add(ring_of(hole));
      if (lattice) boundary += lattice_points(hole, spacing);
      ++holes;
    }
    const polygon::AreaMoments m = sum.moments();
    if (m.area <= 0) continue;
    // Pick's theorem: the pixels of a polygon through lattice points number A / h^2 + B / 2 + 1 - holes.
    pose.area = lattice ? m.area + spacing * spacing * (0.5 * double(boundary) + 1 - holes) : m.area;
    pose.centroid = {m.centroid.x(), m.centroid.y()};
    const double angle = m.principal_axis_angle();  // major axis of the area's second moments
    pose.principal_axis_angle = angle;
    double c = std::cos(angle), s = std::sin(angle);
    double lo1 = std::numeric_limits<double>::max(), hi1 = -lo1, lo2 = lo1, hi2 = -lo1;
    pose.bbox_min = {lo1, lo1};
    pose.bbox_max = {hi1, hi1};
    for (const auto& p : outer) {
      pose.bbox_min = {std::min(pose.bbox_min.x, p.x), std::min(pose.bbox_min.y, p.y)};
      pose.bbox_max = {std::max(pose.bbox_max.x, p.x), std::max(pose.bbox_max.y, p.y)};
      double a = (p.x - pose.centroid.x) * c + (p.y - pose.centroid.y) * s;
      double b = -(p.x - pose.centroid.x) * s + (p.y - pose.centroid.y) * c;
      lo1 = std::min(lo1, a), hi1 = std::max(hi1, a), lo2 = std::min(lo2, b), hi2 = std::max(hi2, b);
    }
    pose.major_extent = hi1 - lo1;
    pose.minor_extent = hi2 - lo2;
    out.push_back(pose);
  }
  std::sort(out.begin(), out.end(), [](const PartPose& a, const PartPose& b) { return a.area > b.area; });
  return out;
}

}  // namespace hg::outline_service
