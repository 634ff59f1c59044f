// Run segmentation: the vertices between two corners as greedy line and circle pieces, their junctions
// moved to where the primitives split best, and straights that one line explains merged.
#include "path_planner/smooth/stages.hpp"

#include <algorithm>
#include <cmath>

namespace hg::path_planner::smooth {

namespace {

// Best primitive for vertices a..b and its worst window mean residual.
double best_fit(const SmoothContext& c, long a, long b, Primitive& best) {
  thread_local std::vector<double> scratch;
  const Unrolled& u = c.u;
  Primitive line;
  const Line lf = fit_line(u, a, b);
  line.centre = lf.centre, line.dir = lf.dir, line.first = a, line.last = b;
  const double line_err = worst_window_mean(u, line, a, b, c.win, scratch);
  best = line;
  if (b - a < 5) return line_err;
  Primitive circ;
  if (!fit_circle(u, a, b, circ) || !(circ.radius > 2 * c.unit && circ.radius < 1e3 * c.total)) return line_err;
  // A circle that bows off its chord by less than twice the tolerance is not told apart from a straight by
  // the data (a noise bump made the line miss by a little): the piece stays a line, split if it must be.
  const double half_sweep = std::min(M_PI, 0.5 * (u.S(b) - u.S(a)) / circ.radius);
  if (circ.radius * (1 - std::cos(half_sweep)) < 2 * c.tolerance) return line_err;
  const double circ_err = worst_window_mean(u, circ, a, b, c.win, scratch);
  if (circ_err < line_err) best = circ;
  return std::min(line_err, circ_err);
}

// Greedy segmentation of vertices j0..j1: from the start, the longest piece that a line or a circle
// explains (doubling, then bisection: O(m log m) for a piece of m vertices), and so on.
Pieces greedy_pieces(const SmoothContext& c, long j0, long j1, int run) {
  Pieces pieces;
  const long min_piece = c.min_piece;
  const double tolerance = c.tolerance;
  Primitive p;
  for (long a = j0; a <= j1;) {
    if (best_fit(c, a, j1, p) <= tolerance || j1 - a + 1 <= min_piece) {
      if (j1 - a + 1 < min_piece && j1 - j0 + 1 >= min_piece) {
        // a short rest: fit it with the vertices before it, keep only its own range
        best_fit(c, j1 - min_piece + 1, j1, p);
        p.first = a;
      }
      pieces.push_back({p, run, false, std::nullopt});
      break;
    }
    long good = a + min_piece - 1, bad = j1;  // good: known to fit (or the minimum); bad: known not to
    Primitive pg;
    best_fit(c, a, good, pg);
    for (long len = 2 * min_piece; a + len - 1 < bad; len *= 2) {
      if (best_fit(c, a, a + len - 1, p) > tolerance) {
        bad = a + len - 1;
        break;
      }
      good = a + len - 1, pg = p;
    }
    while (bad - good > 1) {
      const long mid = (good + bad) / 2;
      if (best_fit(c, a, mid, p) <= tolerance) good = mid, pg = p;
      else
        bad = mid;
    }
    pieces.push_back({pg, run, false, std::nullopt});
    a = good + 1;
  }
  return pieces;
}

// Moves the boundary between pa and pb (pb's vertices `shift` further on) to where the two primitives'
// squared residuals split best and refits both; false when it stays.
bool move_junction(const SmoothContext& c, Primitive& pa, Primitive& pb, long shift) {
  const Unrolled& u = c.u;
  const long lo = pa.first + c.min_piece, hi = pb.last + shift - c.min_piece + 1;
  if (hi - lo < 2) return false;
  auto rb = [&](long j) { return residual(pb, u.at(j - shift)); };
  // cost(t) = sum_{j<=t} ra^2 + sum_{j>t} rb^2 over lo-1 .. hi
  double sb = 0;
  for (long j = lo; j <= hi; ++j) sb += std::pow(rb(j), 2);
  double sa = 0, best = sb;
  long best_t = lo - 1;
  for (long t = lo; t < hi; ++t) {
    sa += std::pow(residual(pa, u.at(t)), 2);
    sb -= std::pow(rb(t), 2);
    if (sa + sb < best) best = sa + sb, best_t = t;
  }
  if (best_t == pa.last) return false;
  const long a0 = pa.first, b1 = pb.last + shift;
  best_fit(c, a0, best_t, pa);
  best_fit(c, best_t + 1 - shift, b1 - shift, pb);
  return true;
}

// The greedy pieces run past the true junctions (a misfit must build up before it shows): each boundary
// moved (move_junction), repeated until none moves, since a piece that held vertices of its neighbour is
// bent toward it and gives them up a few at a time. `wrap`: the run is the whole loop (no corners), so the
// last piece also borders the first, one loop length (n) further on.
void refine_junctions(const SmoothContext& c, Pieces& p, bool wrap) {
  const std::size_t count = p.size();
  for (int pass = 0; pass < 8; ++pass) {
    bool moved = false;
    for (std::size_t i = 0; i < count; ++i) {
      const bool wrapping = i + 1 == count;
      if (wrapping && !(wrap && count >= 2)) break;
      const std::size_t k = wrapping ? 0 : i + 1;
      moved |= move_junction(c, p[i].prim, p[k].prim, wrapping ? c.n : 0);
    }
    if (!moved) break;
  }
}

// Root mean square residual of vertices j0..j1 from primitive p.
double rms_of(const Unrolled& u, const Primitive& p, long j0, long j1) {
  double sum = 0;
  for (long j = j0; j <= j1; ++j) sum += std::pow(residual(p, u.at(j)), 2);
  return std::sqrt(sum / double(j1 - j0 + 1));
}

// One primitive over both ranges: a line for two lines, else a circle; false when the circle fit fails or
// is no arc of this ring.
bool fit_union(const SmoothContext& c, const Primitive& pa, const Primitive& pb, Primitive& ab) {
  ab.first = pa.first, ab.last = pb.last;
  if (!pa.circle && !pb.circle) {
    const Line l = fit_line(c.u, pa.first, pb.last);
    ab.circle = false, ab.centre = l.centre, ab.dir = l.dir;
    return true;
  }
  return fit_circle(c.u, pa.first, pb.last, ab) && ab.radius > 2 * c.unit;
}

// Half the pixel staircase's sawtooth about a straight edge of direction t (0 without a known lattice). The
// outermost pixel centres of a straight edge at angle a to the nearest grid axis lie 0 .. pitch x cos(a)
// inside it, a sawtooth of period pitch / sin(a). The tolerance counts on a window averaging it out; within
// a few degrees of an axis the period is longer than a window, and window means about the edge's line reach
// half the sawtooth (the edge compensation's figure). The greedy fit then splits such a straight into flat
// runs a pixel apart, which meet nowhere, and the emitted chord between them is a notch the tool cannot
// enter (m130, 0.39 mm pixels, where the noise allowance is well under half a pixel). For an arc, whose
// direction turns, the bound over all directions.
double staircase(const SmoothContext& c, const Primitive& p) {
  return c.bias_scale * (p.circle ? 0.5 * c.pitch : edge_bias(p.dir, c.pitch));
}

// Neighbouring pieces of one kind that one primitive explains are one edge that a noise bump split:
// merged. Straights when one line explains both about as well (its rms residual within a quarter of the
// worse piece's): split, the short piece beside the bump tilts, and a real bend, however shallow, raises
// the merged residual far more than that. Arcs when one circle explains both as the greedy fit explains a
// piece (no window mean beyond the tolerance): a slot's end split where a dent stopped the greedy fit gets
// two radii that meet at a kink the tool cannot follow. Either kind also when no window mean of the union
// is beyond the tolerance plus the staircase's half sawtooth: a bend that stays within that of one
// primitive is finer than the pixel lattice resolves. On a loop without corners (`wrap`), a straight and an
// arc as well when one circle explains both so: a large ring's flattest stretch, where a pixel's sagitta is
// within the noise, fits a straight too (50 mm of a R250 ring at pm806), and the arc fitted to the rest is
// drawn off-centre by up to 0.5 mm. Not beside a corner: a fillet's arc would swallow a short straight.
bool explains_both(const SmoothContext& c, const Primitive& pa, const Primitive& pb, const Primitive& ab) {
  thread_local std::vector<double> scratch;
  const Unrolled& u = c.u;
  const double worst = worst_window_mean(u, ab, ab.first, ab.last, c.win, scratch);
  if (worst <= c.tolerance + staircase(c, ab)) return true;
  if (ab.circle) return false;
  return rms_of(u, ab, ab.first, ab.last) <=
         1.25 * std::max(rms_of(u, pa, pa.first, pa.last), rms_of(u, pb, pb.first, pb.last));
}

void merge_neighbours(const SmoothContext& c, Pieces& p, bool wrap) {
  for (std::size_t i = 0; i + 1 < p.size();) {
    Primitive& pa = p[i].prim;
    const Primitive& pb = p[i + 1].prim;
    Primitive ab;
    if ((pa.circle != pb.circle && !wrap) || !fit_union(c, pa, pb, ab) || !explains_both(c, pa, pb, ab)) {
      ++i;
      continue;
    }
    pa = ab;
    p.erase(p.begin() + long(i) + 1);
  }
}

}  // namespace

Pieces segment_run(const SmoothContext& c, long j0, long j1, int run, bool wrap) {
  Pieces pieces = greedy_pieces(c, j0, j1, run);
  refine_junctions(c, pieces, wrap);
  merge_neighbours(c, pieces, wrap);
  return pieces;
}

// The pieces a noisy fillet is split into are shorter than four minimum pieces.
bool long_line(const SmoothContext& c, const Primitive& p) {
  return !p.circle && p.last - p.first + 1 >= 4 * c.min_piece;
}

}  // namespace hg::path_planner::smooth
