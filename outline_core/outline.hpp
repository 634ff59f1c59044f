// hullgrind outline core: the plate's outline (outer edges and cut-outs) from its 2-D points.
// DSHI Delaunay triangulation (paper section 3.1) + alpha shape by circumradius (section 3.2) + loops.
// No LCM dependency: used by hg-outline-service and by the command-line tool hg-outline.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "types.hpp"

namespace hg::outline {

// Automatic radius: one R for the whole cloud (global), or one per triangle following the local point
// spacing (local: for clouds whose spacing varies, e.g. seen by a tilted camera). docs/outline-auto-radius.md.
enum class AlphaMode { Global, Local };

// Option names. Inline, so that readers and writers (hg_outline_io) use them without linking the core.
inline const char* to_string(Mode m) {
  switch (m) {
    case Mode::Ordinary: return "ordinary";
    case Mode::DS: return "ds";
    case Mode::DSHI: return "dshi";
  }
  return "?";
}
inline const char* to_string(Order o) {
  switch (o) {
    case Order::AsIs: return "as-is";
    case Order::Hilbert: return "hilbert";
    case Order::Brio: return "brio";
  }
  return "?";
}
inline const char* to_string(AlphaMode a) { return a == AlphaMode::Local ? "local" : "global"; }
Mode parse_mode(const std::string&);             // "ordinary" | "ds" | "dshi"; throws OutlineError
Order parse_order(const std::string&);           // "as-is" | "hilbert" | "brio"; throws OutlineError
AlphaMode parse_alpha_mode(const std::string&);  // "global" | "local"; throws OutlineError

// Default of Options::min_hole_spacings: holes under (4.5 spacings)^2 = 20.25 s^2 are dropped. Measured
// (docs/outline-auto-radius.md): a 3x3 dropout gap gives at most 17.5 s^2 even at +-0.5 spacing noise;
// holes 6 spacings wide and more always pass; 4-5 spacings is the boundary (a 3x3 gap is a 4-spacing
// hole centred on a grid point).
inline constexpr double kDefaultMinHoleSpacings = 4.5;

struct Options {
  double alpha_radius = 0;  // R in input units; <= 0: automatic, auto_factor x the point spacing
  double auto_factor = 0;   // <= 0: automatic_factor (alpha.hpp): 1.7 regular .. ~2.1-2.8 random cloud
  // Global: R = k x spacing of the whole cloud; Local: each triangle's R = k x the spacing around its
  // vertices (automatic radius only: an explicit alpha_radius with Local is refused).
  AlphaMode alpha_mode = AlphaMode::Global;
  // Holes with area < (min_hole_spacings x spacing)^2 are dropped as dropout, not cut-outs; the spacing
  // is Result::spacing (Local: the median spacing at the hole's vertices). 0 keeps every hole.
  double min_hole_spacings = kDefaultMinHoleSpacings;
  Mode mode = Mode::DSHI;
  Order order = Order::Brio;    // docs/outline-core-performance.md: scan order makes long thin fans
  bool outer_only = false;      // paper's BFS from outside only: big triangles inside are kept (no holes)
  bool keep_triangles = false;  // fill Result::triangles
  // Threads: 0 = all hardware cores, 1 = one thread, N = at most N. The cloud is split into vertical
  // strips, one per thread (docs/outline-core-threads.md); the loops and R are identical to one
  // thread's. One thread is used below min_points_per_thread points per strip, for outer_only, local
  // alpha mode and modes other than DSHI, and when the split's checks fail for the cloud (a margin too
  // narrow for R, a median the strips cannot pin down; with keep_triangles, any triangle not proven).
  int threads = 0;
  std::size_t min_points_per_thread = 100'000;  // below this per strip a second thread does not pay
};

// The triangulation's counters: exact, the same on every run of the same points and options.
struct TriangulationStats {
  std::size_t triangles = 0;             // finite Delaunay triangles
  std::uint64_t search_cost = 0;         // triangles visited: point location + cavity search (the paper's measure)
  std::uint64_t search_cost_locate = 0;  // part of search_cost: point location (walk, or Ordinary's full scan)
  std::uint64_t search_cost_cavity = 0;  // part of search_cost: neighbours tested by the cavity search
  std::uint64_t cavity_triangles = 0;    // triangles deleted over all insertions (mean cavity size x points)
  std::uint64_t incircle_tests = 0;
  std::uint64_t orient_tests = 0;
};

struct Triangulation;
// The counters of T (its finite triangles counted around the vertex at infinity: no pass over them all).
TriangulationStats triangulation_stats(const Triangulation& T);

struct Timings {
  double triangulate_ms = 0, alpha_ms = 0, loops_ms = 0, total_ms = 0;
};

struct Result {
  std::size_t points_read = 0;     // as given
  std::size_t points_skipped = 0;  // with a NaN or infinite coordinate: left out
  std::size_t points_used = 0;     // distinct (finite) points triangulated
  std::size_t duplicates_merged = 0;
  double alpha_radius = 0;  // R actually used
  bool alpha_automatic = false;
  double nn_spacing_median = 0;  // median nearest-neighbour distance (input units; shrinks with noise)
  double spacing = 0;            // point spacing sqrt(2 x median Delaunay triangle area): the unit of R
  AlphaMode alpha_mode = AlphaMode::Global;
  std::size_t holes_dropped = 0;  // holes below Options::min_hole_spacings, not in `loops`
  Mode mode = Mode::DSHI;
  Order order = Order::AsIs;
  TriangulationStats stats;
  std::vector<Loop> loops;  // outer loops first, then holes
  // Final Delaunay triangles (only with Options::keep_triangles), counter-clockwise, indices into the
  // input as given; a merged duplicate is referred to by its first occurrence.
  std::vector<std::array<uint32_t, 3>> delaunay_triangles;
  // Strips computed in parallel (Options::threads); with more than one, the search and test counts are
  // the sums over the strips (their margin bands are triangulated twice).
  int threads_used = 1;
  Timings time;
};

Result compute_outline(std::span<const Vec2> points, const Options& options = {});
// The same result, consuming the points: their memory is returned as soon as the triangulation holds its
// (exact) copy, which lowers the peak by one copy of the cloud (16 bytes per point). For callers that no
// longer need the points.
Result compute_outline(std::vector<Vec2>&& points, const Options& options = {});

}  // namespace hg::outline
