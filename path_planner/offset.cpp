// Step 2: offset by the tool's effective radius with Clipper (libpolyclipping), on integer coordinates of
// 1 micrometre about the ring's first vertex. Round joins: around a convex corner the tool centre keeps its
// distance from the corner, which is what a round tool does.
#include "path_planner/pipeline.hpp"

#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <cmath>

namespace hg::path_planner {

namespace {
constexpr double kUnit = 1e-6;  // metres per Clipper unit
// Clipper rounds the offset's vertices to whole units, which leaves vertices a unit or two from their
// neighbour, some of them stepping back against the travel: a zig-zag of a few micrometres that the robot
// bridge sees as a corner of a fraction of a millimetre radius. Vertices within this distance of a
// neighbour or of the line through their neighbours are removed (CleanPolygon); it is far below the arc
// tolerance (10 um) and the accuracy targets (0.3 mm).
constexpr double kCleanUnits = 3;
}  // namespace

std::vector<Ring> offset_ring(const Ring& ring, bool hole, double distance, double arc_tolerance) {
  std::vector<Ring> out;
  if (ring.size() < 3) return out;
  const Vec2 ref = ring[0];
  ClipperLib::Path path;
  path.reserve(ring.size());
  for (const Vec2& p : ring)
    path.emplace_back(ClipperLib::cInt(std::llround((p.x() - ref.x()) / kUnit)),
                      ClipperLib::cInt(std::llround((p.y() - ref.y()) / kUnit)));
  // Clipper grows positively oriented (counter-clockwise) regions for a positive delta. A hole's region is
  // the air inside it: give it counter-clockwise and shrink it.
  if (!ClipperLib::Orientation(path)) std::reverse(path.begin(), path.end());
  ClipperLib::ClipperOffset co;
  co.ArcTolerance = std::max(1.0, arc_tolerance / kUnit);
  co.AddPath(path, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  ClipperLib::Paths solution;
  co.Execute(solution, (hole ? -distance : distance) / kUnit);
  ClipperLib::CleanPolygons(solution, kCleanUnits);
  for (ClipperLib::Path& sp : solution) {
    // Negative rings after growing an outer loop are pockets the tool closed off (a notch narrower than
    // the tool): not reachable, not part of the path.
    if (!ClipperLib::Orientation(sp) || sp.size() < 3) continue;
    Ring r;
    r.reserve(sp.size());
    for (const ClipperLib::IntPoint& q : sp)
      r.emplace_back(ref.x() + double(q.X) * kUnit, ref.y() + double(q.Y) * kUnit);
    if (hole) std::reverse(r.begin(), r.end());  // canonical: material on the left
    out.push_back(std::move(r));
  }
  // Largest first: callers that expect one ring take the front.
  std::sort(out.begin(), out.end(),
            [](const Ring& a, const Ring& b) { return std::abs(signed_area(a)) > std::abs(signed_area(b)); });
  return out;
}

}  // namespace hg::path_planner
