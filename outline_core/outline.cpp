// compute_outline: triangulate, classify by circumradius, chain loops; plus the option names.
#include "outline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "alpha.hpp"
#include "delaunay.hpp"
#include "threads.hpp"

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

AlphaMode parse_alpha_mode(const std::string& s) {
  if (s == "global") return AlphaMode::Global;
  if (s == "local") return AlphaMode::Local;
  throw OutlineError("unknown alpha mode '" + s + "' (expected global or local)");
}

TriangulationStats triangulation_stats(const Triangulation& T) {
  TriangulationStats s;
  s.search_cost = T.stats.search_cost();
  s.search_cost_locate = T.stats.locate_visits;
  s.search_cost_cavity = T.stats.cavity_visits;
  s.cavity_triangles = T.stats.cavity_triangles;
  s.incircle_tests = T.stats.incircle_tests;
  s.orient_tests = T.stats.orient_tests;
  // Finite triangles = all slots minus the ghost ones, one per hull edge: counted by turning around the
  // vertex at infinity. Its half-edges are g -> x; the next one around it is the twin of the half-edge
  // ending at the ghost in the same triangle.
  std::uint32_t h0 = 0;
  while (T.tri[h0] != T.ghost) ++h0;  // a half-edge leaving the ghost (usually within the first slots)
  std::size_t hull = 0;
  std::uint32_t h = h0;
  do {
    ++hull;
    h = T.twin[Triangulation::prev(h)];
  } while (h != h0);
  s.triangles = T.slots() - hull;
  return s;
}

namespace {

void check_options(const Options& options) {
  if (!std::isfinite(options.alpha_radius)) throw OutlineError("alpha radius must be a finite number");
  if (std::isnan(options.auto_factor) || std::isinf(options.auto_factor))
    throw OutlineError("auto factor must be a finite number");
  if (!(options.min_hole_spacings >= 0) || std::isinf(options.min_hole_spacings))
    throw OutlineError("min hole spacings must be a finite number >= 0");
  if (options.alpha_mode == AlphaMode::Local && options.alpha_radius > 0)
    throw OutlineError("alpha mode local sets the radius per triangle: give no alpha radius");
  if (options.threads < 0) throw OutlineError("threads must be >= 0 (0: all cores)");
}

// Removes the holes smaller than (min_spacings x spacing)^2, the spacing being the global one or, in
// local mode, the median local spacing at the hole's vertices; returns how many were removed.
// T is read only in local mode (local not empty).
std::size_t drop_small_holes(std::vector<Loop>& loops, const Triangulation* T, std::span<const float> local,
                             double spacing, double min_spacings) {
  if (min_spacings <= 0) return 0;
  // Local mode: the spacing of each hole vertex (input index -> vertex is found by one pass over the
  // vertices, for the hole vertices only).
  std::vector<std::pair<std::uint32_t, float>> at;  // (input index, local spacing)
  if (!local.empty()) {
    for (const Loop& L : loops)
      if (L.hole)
        for (std::uint32_t i : L.point_index) at.push_back({i, 0.0f});
    std::sort(at.begin(), at.end());
    for (std::uint32_t v = 0; v < T->xy.size(); ++v) {
      if (T->vrep[v] != v) continue;
      auto it = std::lower_bound(at.begin(), at.end(), std::pair<std::uint32_t, float>{T->ids[v], 0.0f});
      for (; it != at.end() && it->first == T->ids[v]; ++it) it->second = local[v];
    }
  }
  std::vector<float> buf;
  auto hole_spacing = [&](const Loop& L) {
    if (local.empty()) return spacing;
    buf.clear();
    for (std::uint32_t i : L.point_index)
      buf.push_back(std::lower_bound(at.begin(), at.end(), std::pair<std::uint32_t, float>{i, 0.0f})->second);
    std::nth_element(buf.begin(), buf.begin() + buf.size() / 2, buf.end());
    return static_cast<double>(buf[buf.size() / 2]);
  };
  const std::size_t before = loops.size();
  std::erase_if(loops, [&](const Loop& L) {
    if (!L.hole) return false;
    const double m = min_spacings * hole_spacing(L);
    return L.area < m * m;
  });
  return before - loops.size();
}

// The spacings and the radius (global or per triangle) into res; the inside flags of the triangles.
std::vector<std::uint8_t> classify_by_options(const Triangulation& T, const Options& options, Result& res,
                                              std::vector<float>& local) {
  res.nn_spacing_median = median_nn_spacing(T);
  const TriangleScan scan = scan_triangles(T);
  res.spacing = scan.spacing;
  res.alpha_mode = options.alpha_mode;
  const double k =
      options.auto_factor > 0 ? options.auto_factor : automatic_factor(res.nn_spacing_median / res.spacing, T.inserted);
  if (options.alpha_mode == AlphaMode::Local) {
    // Result::alpha_radius then reports k x the global spacing, for scale; each triangle has its own.
    local = local_spacing(T);
    res.alpha_radius = k * res.spacing;
    res.alpha_automatic = true;
    return classify_alpha_local(T, local, k, options.outer_only);
  }
  res.alpha_automatic = !(options.alpha_radius > 0);
  res.alpha_radius = res.alpha_automatic ? k * res.spacing : options.alpha_radius;
  return classify_alpha(T, res.alpha_radius, options.outer_only, scan);
}

// The pipeline on several strips when the options and the size call for it and the split's checks
// pass (threads.hpp); false (res untouched, `owned` as it was) when the one-thread path is to run.
bool run_on_strips(std::span<const Vec2> points, std::vector<Vec2>* owned, const Options& options, Result& res) {
  const int strips = strips_for(options, points.size());
  if (strips < 2) return false;
  Result r;
  if (!run_threaded(points, owned, options, strips, r)) return false;
  r.holes_dropped = drop_small_holes(r.loops, nullptr, {}, r.spacing, options.min_hole_spacings);
  res = std::move(r);
  return true;
}

// The pipeline; `owned`, when given, is the vector `points` views and may be released by the
// triangulation (then the loops take their coordinates from it).
Result run_outline(std::span<const Vec2> points, std::vector<Vec2>* owned, const Options& options) {
  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  check_options(options);

  const auto t0 = Clock::now();
  Result res;
  if (run_on_strips(points, owned, options, res)) {
    res.time.total_ms = ms(t0, Clock::now());
    res.time.loops_ms = res.time.total_ms - res.time.triangulate_ms - res.time.alpha_ms;
    return res;
  }
  if (owned) points = *owned;  // the strips may have released it and put it back (same points, new memory)
  res.points_read = points.size();
  res.mode = options.mode;
  res.order = options.order;
  const Triangulation T = owned ? triangulate_releasing(*owned, options.mode, options.order)
                                : triangulate(points, options.mode, options.order);
  if (owned) points = *owned;  // empty if released
  const auto t1 = Clock::now();

  res.points_skipped = T.skipped;
  res.points_used = T.inserted;
  res.duplicates_merged = T.duplicates;
  res.stats = triangulation_stats(T);
  std::vector<float> local;  // per-vertex spacing, local mode only
  const std::vector<std::uint8_t> inside = classify_by_options(T, options, res, local);
  const auto t2 = Clock::now();

  res.loops = extract_loops(T, inside, points);
  res.holes_dropped = drop_small_holes(res.loops, &T, local, res.spacing, options.min_hole_spacings);
  if (options.keep_triangles) {
    const std::size_t slots = T.slots();
    for (std::size_t t = 0; t < slots; ++t)
      if (!T.is_ghost(t))
        res.delaunay_triangles.push_back({T.ids[T.tri[3 * t]], T.ids[T.tri[3 * t + 1]], T.ids[T.tri[3 * t + 2]]});
  }
  const auto t3 = Clock::now();
  res.time.triangulate_ms = ms(t0, t1);
  res.time.alpha_ms = ms(t1, t2);
  res.time.loops_ms = ms(t2, t3);
  res.time.total_ms = ms(t0, t3);
  return res;
}

}  // namespace

Result compute_outline(std::span<const Vec2> points, const Options& options) {
  return run_outline(points, nullptr, options);
}

Result compute_outline(std::vector<Vec2>&& points, const Options& options) {
  std::vector<Vec2> owned = std::move(points);  // consumed: released during the triangulation when possible
  return run_outline(owned, &owned, options);
}

}  // namespace hg::outline
