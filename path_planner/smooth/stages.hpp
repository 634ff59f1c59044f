// The smoothing step as stages over one list of pieces (smooth.cpp composes them; see the comment there).
// Every stage reads the SmoothContext, computed once per ring, and returns the pieces it was given,
// refined. Internal to path_planner; the tests call the stages one by one.
#pragma once

#include "path_planner/smooth/fits.hpp"

#include <optional>
#include <vector>

namespace hg::path_planner::smooth {

// Everything the stages share about one ring: its moments and the scales derived from pitch and noise.
struct SmoothContext {
  Unrolled u;
  int n = 0;                // vertices
  double pitch = 0;         // the pixel pitch given (0: unknown)
  double spacing = 0;       // median vertex spacing
  double total = 0;         // ring length
  double unit = 0;          // length unit of the scales: max(pitch, spacing)
  int win = 5;              // vertices in a residual window
  double sigma = 0;         // noise of a window mean
  double scale = 0;         // length of the corner detector's one-sided lines
  double tolerance = 0;     // largest window mean residual that is noise or staircase, not misfit
  long min_piece = 10;      // fewest vertices of a piece (two windows)
  double bias_scale = 0;    // 1: edge compensation on, 0: off
  double corner_angle = 0;  // smallest turn of a corner
  explicit SmoothContext(const Ring& ring) : u(ring), n(int(ring.size())) {}
};
// The context of a ring, or nothing when the ring is left as it is (too few vertices, or a sparse polygon
// of unknown pitch).
std::optional<SmoothContext> make_context(const Ring& ring, double pitch, const SmoothOptions& o);

// Residual windows: 2 x window_pitches vertices, at least 5.
int window_of(const SmoothOptions& o);
// Noise of a window mean from the ring's moments (smooth/noise.cpp); appends one |E| per vertex to `dev`.
void append_window_noise(const Unrolled& u, int win, std::vector<double>& dev);
// Median of |E| as a Gaussian sigma (0 for no samples).
double sigma_of(std::vector<double>& dev);

// A fillet between two straights: an arc tangent to both (smooth/fillet.cpp).
struct Fillet {
  Line a, b;        // the straights, refitted without the fillet's vertices
  long a_last = 0;  // last vertex of a, first of b (unwrapped)
  long b_first = 0;
  Primitive arc;                              // the fillet: a circle tangent to both
  Vec2 t1 = Vec2::Zero(), t2 = Vec2::Zero();  // its tangent points on a and b
};

// One piece of the smoothed ring: a primitive over a vertex range, the run (between two corners) it
// belongs to, and how it joins the next piece of its run.
struct Piece {
  Primitive prim;
  int run = 0;                   // run k starts at corner k (one run 0 for a ring without corners)
  bool tangent_next = false;     // made tangent to the next piece (stage make_tangent)
  std::optional<Fillet> fillet;  // a fillet joins it to the next piece
};
using Pieces = std::vector<Piece>;

// A corner: the vertex the detector found, its turn there, and (once confirmed) where the pieces meet.
struct Corner {
  long vertex = 0;
  double turn = 0;
  Vec2 at = Vec2::Zero();
};
using Corners = std::vector<Corner>;

// ---- stages, in the order smooth_ring runs them ----
// Corner candidates: turn between one-sided TLS lines at one and two corner scales (smooth/corners.cpp).
Corners corner_candidates(const SmoothContext& c);
// Segments the runs between the corners and drops the corners that the pieces beside them do not confirm,
// refitting until every remaining corner is confirmed (its `at` set). Returns the pieces.
Pieces confirm_corners(const SmoothContext& c, Corners& corners);
// Run segmentation (smooth/segment.cpp): vertices j0..j1 as greedy line and circle pieces of run `run`,
// their junctions refined and collinear straights merged. `wrap`: the run is the whole ring.
Pieces segment_run(const SmoothContext& c, long j0, long j1, int run, bool wrap);
// The vertex range of run k between corners k and k + 1, less the gap at both; false when none is left.
bool run_range(const SmoothContext& c, const Corners& corners, int k, long& j0, long& j1);
// A straight long enough to hold a fillet's tangent.
bool long_line(const SmoothContext& c, const Primitive& p);
// Arcs made tangent to the straights beside them in their run (smooth/tangency.cpp).
Pieces make_tangent(const SmoothContext& c, Pieces pieces, bool one_run);
// Straight - fillet - straight fitted to vertices w0..w1, straights from w0..a1 and b0..w1 (smooth/fillet.cpp).
bool fit_fillet(const SmoothContext& c, long w0, long a1, long b0, long w1, Fillet& f);
// Fillets where two straights meet at a bend better explained by a tangent arc (smooth/fillet.cpp).
Pieces fit_fillets(const SmoothContext& c, Pieces pieces, bool has_corners);
// Corners moved to where the final pieces beside them meet, if still near (smooth/corners.cpp).
void replace_corners(const SmoothContext& c, const Pieces& pieces, Corners& corners);
// The smoothed ring: corners, line end points, sampled arcs, all edge-compensated (smooth/emit.cpp).
SmoothedRing emit_ring(const SmoothContext& c, const Pieces& pieces, const Corners& corners);

// The safety net (smooth/fallback.cpp): true when three consecutive vertices of the outline lie farther than
// `band` from the smoothed ring (or it has fewer than three points); then local_smoothing replaces it: a
// Gaussian of 1.5 vertices along the outline with the same edge compensation, no corners.
bool strays_from(const Ring& outline, const Ring& smoothed, double band);
SmoothedRing local_smoothing(const SmoothContext& c, const Ring& ring);

}  // namespace hg::path_planner::smooth
