// compute_outline: triangulate, classify by circumradius, chain loops; plus the option names.
#include "outline.hpp"

#include <chrono>
#include <cmath>

#include "alpha.hpp"
#include "delaunay.hpp"

namespace hg::outline {

Mode parse_mode(const std::string& s) {
  if (s == "ordinary") return Mode::Ordinary;
  if (s == "ds") return Mode::DS;
  if (s == "dshi") return Mode::DSHI;
  throw OutlineError("unknown mode '" + s + "' (expected ordinary, ds or dshi)");
}

Order parse_order(const std::string& s) {
  if (s == "as-is") return Order::AsIs;
  if (s == "hilbert") return Order::Hilbert;
  if (s == "brio") return Order::Brio;
  throw OutlineError("unknown order '" + s + "' (expected as-is, hilbert or brio)");
}

namespace {

// The pipeline; `owned`, when given, is the vector `points` views and may be released by the
// triangulation (then the loops take their coordinates from it).
Result run_outline(std::span<const Vec2> points, std::vector<Vec2>* owned, const Options& options) {
  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
  if (!std::isfinite(options.alpha_radius))
    throw OutlineError("alpha radius must be a finite number");
  if (std::isnan(options.auto_factor) || std::isinf(options.auto_factor))
    throw OutlineError("auto factor must be a finite number");

  const auto t0 = Clock::now();
  Result res;
  res.points_read = points.size();
  res.mode = options.mode;
  res.order = options.order;
  const Triangulation T =
      owned ? triangulate_releasing(*owned, options.mode, options.order) : triangulate(points, options.mode, options.order);
  if (owned) points = *owned;  // empty if released
  const auto t1 = Clock::now();

  res.points_skipped = T.skipped;
  res.points_used = T.inserted;
  res.duplicates_merged = T.duplicates;
  res.search_cost = T.stats.search_cost();
  res.search_cost_locate = T.stats.locate_visits;
  res.search_cost_cavity = T.stats.cavity_visits;
  res.cavity_triangles = T.stats.cavity_triangles;
  res.incircle_tests = T.stats.incircle_tests;
  res.orient_tests = T.stats.orient_tests;
  res.nn_spacing_median = median_nn_spacing(T);
  if (options.alpha_radius > 0) {
    res.alpha_radius = options.alpha_radius;
  } else {
    const double k = options.auto_factor > 0 ? options.auto_factor : kDefaultAutoFactor;
    res.alpha_radius = k * res.nn_spacing_median;
    res.alpha_automatic = true;
  }
  const std::vector<std::uint8_t> inside = classify_alpha(T, res.alpha_radius, options.outer_only);
  const auto t2 = Clock::now();

  res.loops = extract_loops(T, inside, points);
  if (options.keep_triangles) {
    const std::size_t slots = T.slots();
    for (std::size_t t = 0; t < slots; ++t) {
      if (T.is_ghost(t)) continue;
      ++res.triangles;
      res.delaunay_triangles.push_back({T.ids[T.tri[3 * t]], T.ids[T.tri[3 * t + 1]], T.ids[T.tri[3 * t + 2]]});
    }
  } else {
    // Finite triangles = all slots minus the ghost ones, one per hull edge: counted by turning around the
    // vertex at infinity (no pass over the 3 M triangles). Its half-edges are g -> x; the next one
    // around it is the twin of the half-edge ending at the ghost in the same triangle.
    std::uint32_t h0 = 0;
    while (T.tri[h0] != T.ghost) ++h0;  // a half-edge leaving the ghost (usually within the first slots)
    std::size_t hull = 0;
    std::uint32_t h = h0;
    do {
      ++hull;
      h = T.twin[Triangulation::prev(h)];
    } while (h != h0);
    res.triangles = T.slots() - hull;
  }
  const auto t3 = Clock::now();
  res.time.triangulate_ms = ms(t0, t1);
  res.time.alpha_ms = ms(t1, t2);
  res.time.loops_ms = ms(t2, t3);
  res.time.total_ms = ms(t0, t3);
  return res;
}

}  // namespace

Result compute_outline(std::span<const Vec2> points, const Options& options) { return run_outline(points, nullptr, options); }

Result compute_outline(std::vector<Vec2>&& points, const Options& options) {
  std::vector<Vec2> owned = std::move(points);  // consumed: released during the triangulation when possible
  return run_outline(owned, &owned, options);
}

}  // namespace hg::outline
