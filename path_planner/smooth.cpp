// Step 1: de-noise the outline's pixel staircase without rounding real corners.
//
// The outline core's loops run through the outermost pixel centres of the plate, so they zig-zag by up to
// one pixel pitch and sit on average half a pitch inside the true edge; with in-plane noise the vertices
// scatter by the noise as well. Local smoothing windows cannot average that away (a few vertices each), so
// the loop is modelled by long primitives instead:
//  1. corners: turning angle between total-least-squares lines fitted one corner scale behind and ahead of
//     every vertex (O(1) each from prefix sums of the coordinate moments); a corner turns by at least
//     corner_angle and its turn does not grow by half when the scale doubles (an arc's turn grows with the
//     scale, a corner's does not); the local maximum within one scale wins;
//  2. each run between corners (minus a gap at both ends, where the alpha shape cuts or fills the corner)
//     is split recursively into pieces that a TLS line or a geometric circle fit (Kasa start, Gauss-Newton)
//     explains: no window of vertices may have a mean residual above what the noise and the staircase
//     allow. Pieces that neither explains are halved; the smallest ones keep their better fit;
//  3. corners are re-placed at the intersection of the primitives on both sides (their angle comes from the
//     whole runs); a candidate whose primitives meet far from it, or at a shallow angle, is a tight arc or
//     noise, not a corner: it is dropped and the runs beside it are fitted as one;
//  3b. fillets: where two straights meet at a bend the pieces between them (or a corner, or two) do not
//     explain as well as straight - tangent arc - straight, the arc is fitted (fit_fillet) and replaces them;
//  4. edge compensation moves each primitive outward by half the pitch times max(|t_x|, |t_y|) for its
//     tangent t: the mean gap between the outermost pixel centres and an edge of that direction, assuming
//     the pixel grid is aligned with the plate's u, v axes (top-down camera).
// Output: line pieces as their end points, circle pieces sampled with a 5 um chord error: few vertices, so
// the offset and everything after it is cheap. Cost O(n log n) (recursive halving), O(n) for typical loops.
//
// The steps are stages over one list of pieces (path_planner/smooth/stages.hpp), each in its own file:
// smooth/context.cpp (scales from pitch and noise), smooth/noise.cpp (pitch and noise estimates),
// smooth/fits.cpp (moments, lines, circles), smooth/corners.cpp (1 and 3), smooth/segment.cpp (2),
// smooth/tangency.cpp, smooth/fillet.cpp (3b), smooth/emit.cpp (4); smooth/fallback.cpp: a result that
// strays from the outline (a shape too coarse for the fits) is replaced by a local smoothing.
#include "path_planner/smooth/stages.hpp"

#include <cmath>

namespace hg::path_planner {

namespace {

// The band of smooth/fallback.cpp: the staircase's 1.2 units plus the noise of single vertices (4 sigma;
// c.sigma is that of a window mean of c.win vertices, sqrt(win) times smaller for independent noise). On a
// noisy outline (pm806 frames: window-mean noise 0.2-0.35 units) the vertices scatter about a well-fitted
// ring by up to 4.4 units, and a run of three beyond 1.2 units is noise, not a missed shape (the light local
// smoothing would keep that noise). A window-mean noise above 0.45 units is no noise but the shape of a
// coarse outline taken into the estimate (the bundled samples' slots a few pixels wide: 0.54-0.99 units):
// no allowance then.
double stray_band(const smooth::SmoothContext& c) {
  const bool genuine_noise = c.sigma < 0.45 * c.unit;
  return 1.2 * c.unit + (genuine_noise ? 4.0 * c.sigma * std::sqrt(double(c.win)) : 0.0);
}

}  // namespace

SmoothedRing smooth_ring(const Ring& ring, double pitch, const SmoothOptions& o) {
  using namespace smooth;
  const std::optional<SmoothContext> c = make_context(ring, pitch, o);
  if (!c) return {ring, std::vector<std::uint8_t>(ring.size(), 0)};
  Corners corners = corner_candidates(*c);
  Pieces pieces = confirm_corners(*c, corners);
  pieces = make_tangent(*c, std::move(pieces), corners.empty());
  pieces = fit_fillets(*c, std::move(pieces), !corners.empty());
  replace_corners(*c, pieces, corners);
  SmoothedRing out = emit_ring(*c, pieces, corners);
  if (strays_from(ring, out.points, stray_band(*c))) return local_smoothing(*c, ring);
  return out;
}

}  // namespace hg::path_planner
