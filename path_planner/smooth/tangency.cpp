// Tangency: arcs refitted tangent to the straights beside them in the same run (no corner between).
#include "path_planner/smooth/stages.hpp"

#include <cmath>

namespace hg::path_planner::smooth {

Pieces make_tangent(const SmoothContext& c, Pieces p, bool one_run) {
  const std::size_t np = p.size();
  for (std::size_t i = 0; i < np && np >= 2; ++i) {
    if (!p[i].prim.circle) continue;
    std::vector<const Primitive*> lines;
    const std::size_t before = i == 0 ? np - 1 : i - 1, after = i + 1 == np ? 0 : i + 1;
    const bool wraps_before = i == 0, wraps_after = i + 1 == np;
    // only a straight of some length that the free circle already nearly touches: a short line piece
    // inside an arc, or a line that crosses the circle, is not a tangent neighbour
    auto tangent_line = [&](std::size_t j) {
      const Primitive& l = p[j].prim;
      const double gap = std::abs(std::abs(cross(l.dir, p[i].prim.centre - l.centre)) - p[i].prim.radius);
      return !l.circle && l.last - l.first + 1 >= 2 * c.min_piece && gap <= 2 * c.tolerance;
    };
    if (p[before].run == p[i].run && (!wraps_before || one_run) && tangent_line(before))
      lines.push_back(&p[before].prim), p[before].tangent_next = true;
    if (after != before && p[after].run == p[i].run && (!wraps_after || one_run) && tangent_line(after))
      lines.push_back(&p[after].prim), p[i].tangent_next = true;
    refit_tangent(c.u, p[i].prim, lines);
  }
  return p;
}

}  // namespace hg::path_planner::smooth
