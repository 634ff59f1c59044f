// The outline on several threads; see threads.hpp and docs/outline-core-threads.md.
//
// Strip i owns the x range [lo, hi) and triangulates the finite points with x in [lo - M, hi + M). A
// triangle of a strip's triangulation whose closed circumdisk lies inside that zone is Delaunay for the
// whole cloud (no point outside the zone can be in its disk), and so is its whole cocircular cell. Each
// triangle is owned by the strip holding its circumcentre (decided exactly: the triangles of a
// cocircular cell share it, so a cell is never split between two strips' different diagonals).
#include "threads.hpp"

#include <algorithm>
#include <barrier>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <sys/resource.h>

#include <thread>
#include <unordered_set>

#include "alpha.hpp"
#include "delaunay.hpp"
#include "predicates.hpp"

namespace hg::outline {

namespace {

// The margin band's width in units of sqrt(box area / points): >= 4 R with room (R is k <= 2.8 point
// spacings, and the spacing of a cloud not filling its box is below this unit).
constexpr double kMarginUnits = 16;

constexpr double kEps = pred::kEps;
constexpr std::size_t kAhead = 8;  // triangles ahead whose vertices a pass over the triangles prefetches

// A vertex as input index and coordinates; a directed edge between two.
struct VertexRef {
  std::uint32_t id;
  Vec2 p;
};
struct EdgeRef {
  VertexRef a, b;
};
std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) { return std::uint64_t{a} << 32 | b; }

// The calling thread's costs from one lap to the next (StageCost: a syscall and a clock read a lap).
class Lap {
 public:
  Lap() { now(r_, w_); }
  // Adds what this thread spent since the last lap to `c`.
  void to(StageCost& c) {
    rusage r;
    std::chrono::steady_clock::time_point w;
    now(r, w);
    auto ms = [](const timeval& a, const timeval& b) {
      return static_cast<double>(b.tv_sec - a.tv_sec) * 1e3 + static_cast<double>(b.tv_usec - a.tv_usec) * 1e-3;
    };
    c.user_ms += ms(r_.ru_utime, r.ru_utime);
    c.sys_ms += ms(r_.ru_stime, r.ru_stime);
    c.faults += r.ru_minflt - r_.ru_minflt;
    c.blocked += r.ru_nvcsw - r_.ru_nvcsw;
    c.wall_ms += std::chrono::duration<double, std::milli>(w - w_).count();
    r_ = r, w_ = w;
  }

 private:
  static void now(rusage& r, std::chrono::steady_clock::time_point& w) {
    if (getrusage(RUSAGE_THREAD, &r) != 0) r = rusage{};
    w = std::chrono::steady_clock::now();
  }
  rusage r_;
  std::chrono::steady_clock::time_point w_;
};

struct Strip {
  std::size_t index = 0;
  double lo = 0, hi = 0;  // owned x range [lo, hi)
  // The zone's points, triangulated straight from the input: T.ids are input indices (no copy of the
  // zone's points or of their indices is kept next to T).
  Triangulation T;
  bool translated = false;  // T holds the zone's points (xy, ids), even if its triangulation failed
  bool ok = true;
  StripProfile cost;  // what its stages cost its threads
  // What the survey found (before the radius is known).
  AreaHistogram areas;       // owned trusted triangles
  TriangleScan scan;         // circumradius classes of T's triangles (its spacing unused)
  std::size_t distinct = 0;  // owned distinct vertices
  // Their squared nearest-neighbour distances (T.nn2) by the top 16 bits of the float (the first pass
  // of the merged radix median; the vertices are read again for the second).
  std::vector<std::uint32_t> nn_top;
  std::vector<std::uint32_t> nn_low;  // the second pass: low 16 bits, within the median's top bucket
  std::vector<VertexRef> hull;        // convex hull vertices of the zone's points
  // Edges of counted triangles with no counted triangle of this strip across (seams, hull, gaps).
  std::vector<EdgeRef> frontier;
  std::vector<std::array<std::uint32_t, 3>> kept;  // owned trusted triangles (keep_triangles)
  std::vector<FreeEdge> edges;                     // free edges with an owned tail (input indices)
  // Owned triangles whose disk leaves the zone (hull slivers, huge cut-outs): checked against the
  // other strips' points (check_untrusted) before they count.
  struct Untrusted {
    Vec2 a, b, c;
    std::array<std::uint32_t, 3> ids;
  };
  std::vector<Untrusted> untrusted;
  // The owned vertices in square cells (counting sort), for those checks.
  double cx0 = 0, cy0 = 0, cell = 1;
  std::size_t nx = 0, ny = 0;
  std::vector<std::uint32_t> cell_start;
  std::vector<std::uint32_t> cell_vertex;  // vertex ids of T

  bool owns_x(double x) const { return lo <= x && x < hi; }
  Vec2 at(std::uint32_t v) const { return {T.xy[v].x + T.origin.x, T.xy[v].y + T.origin.y}; }  // exact
  // Calls f(v) for each owned distinct vertex v.
  template <class F>
  void for_owned(F f) const {
    for (std::uint32_t v = 0; v < T.xy.size(); ++v)
      if (T.vrep[v] == v && owns_x(at(v).x)) f(v);
  }
};

// A finite triangle's circumcentre and radius in floating point, with whether they are accurate to
// about 1e-7 of the radius (the triangle is not a sliver: |D| >= 1e-6 (|ab|^2 + |ac|^2)).
struct Circle {
  double ox, oy, r;
  bool accurate;
};

Circle circle_of(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
  const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  const double D = 2 * (bx * cy - by * cx);
  const double ux = (cy * b2 - by * c2) / D, uy = (bx * c2 - cx * b2) / D;
  Circle k{a.x + ux, a.y + uy, std::sqrt(ux * ux + uy * uy), false};
  k.accurate = std::fabs(D) >= 2e-6 * (b2 + c2) && std::isfinite(k.ox) && std::isfinite(k.oy) && std::isfinite(k.r);
  return k;
}

// Sign of (circumcentre x - xb) for the counter-clockwise triangle a, b, c: exact. The float circle
// decides when it is far enough; otherwise the mirror image p' = (2 xb - p.x, p.y) of a vertex p off the
// line x = xb: |O - p'|^2 - |O - p|^2 = 4 (p.x - xb)(O.x - xb), and its sign is that of -incircle(a, b, c,
// p'). 2 (no exact mirror image of any vertex: not decidable here).
int circumcentre_side(const Vec2& a, const Vec2& b, const Vec2& c, const Circle& k, double xb) {
  if (k.accurate) {
    const double d = k.ox - xb, slack = 1e-6 * k.r + 8 * kEps * (std::fabs(k.ox) + std::fabs(xb));
    if (d > slack) return 1;
    if (d < -slack) return -1;
  }
  for (const Vec2* p : {&a, &b, &c}) {
    if (p->x == xb || !pred::difference_is_exact(2 * xb, p->x) || !std::isfinite(2 * xb)) continue;
    const double s = pred::incircle(a.x, a.y, b.x, b.y, c.x, c.y, 2 * xb - p->x, p->y);
    if (s == 0) return 0;
    return (s < 0) == (p->x > xb) ? 1 : -1;
  }
  return 2;
}

// The triangle's closed circumdisk lies in the open x range (zlo, zhi) (decided conservatively).
bool disk_inside(const Circle& k, double zlo, double zhi) {
  if (!k.accurate) return false;
  const double r = k.r * (1 + 1e-6), slack = 8 * kEps * (std::fabs(k.ox) + r);
  return k.ox - r - slack > zlo && k.ox + r + slack < zhi;
}

// The split: inner boundaries b[0] < b[1] < ...; strip i owns [b[i-1], b[i]) and sees the zone
// [b[i-1] - margin, b[i] + margin).
struct Split {
  std::vector<double> bounds;
  double margin = 0;
  double zone_lo(std::size_t i) const {
    return i == 0 ? -std::numeric_limits<double>::infinity() : bounds[i - 1] - margin;
  }
  double zone_hi(std::size_t i) const {
    return i == bounds.size() ? std::numeric_limits<double>::infinity() : bounds[i] + margin;
  }
};

// The strip holding the circumcentre (exact), or -1 when not decidable.
long owner_of(const Vec2& a, const Vec2& b, const Vec2& c, const Circle& k, const Split& split) {
  for (std::size_t i = 0; i < split.bounds.size(); ++i) {
    const int side = circumcentre_side(a, b, c, k, split.bounds[i]);
    if (side == 2) return -1;
    if (side < 0) return static_cast<long>(i);
  }
  return static_cast<long>(split.bounds.size());
}

// Which strip counts the triangle: the one holding its circumcentre (all of a cocircular cell's
// triangles share it), unless the triangle's vertices leave that strip's zone (a long hull sliver: that
// strip cannot have it); then the first strip whose zone holds them. -1: none, or not decidable.
long reporter_of(const Vec2& a, const Vec2& b, const Vec2& c, const Circle& k, const Split& split) {
  const long owner = owner_of(a, b, c, k, split);
  if (owner < 0) return -1;
  const double x0 = std::min({a.x, b.x, c.x}), x1 = std::max({a.x, b.x, c.x});
  auto fits = [&](std::size_t i) { return x0 >= split.zone_lo(i) && x1 < split.zone_hi(i); };
  if (fits(static_cast<std::size_t>(owner))) return owner;
  for (std::size_t i = 0; i <= split.bounds.size(); ++i)
    if (fits(i)) return static_cast<long>(i);
  return -1;
}

// A triangle with its vertices at least x from the strip's ends and circumradius below x: its
// circumcentre is here and its disk inside the zone (the common case, decided without the circle). The
// radius from the triangle's measure, where that is accurate (its class decided).
bool deep_inside(const Vec2& a, const Vec2& b, const Vec2& c, const TriangleMeasure& m, double lo, double hi,
                 double x) {
  const double x0 = std::min({a.x, b.x, c.x}), x1 = std::max({a.x, b.x, c.x});
  if (!(x0 - x >= lo && x1 + x < hi) || m.rclass == kUndecidedClass) return false;
  return m.N < 0.99 * 4 * (x * x) * (m.D * m.D);  // r^2 = N / (4 D^2), accurate to 2e-6: far below 1 %
}

// The strip's counted triangles: the trusted ones' areas (and ids), the untrusted ones for
// check_untrusted, and the frontier edges; and every triangle's circumradius class for the alpha pass
// (the strip's TriangleScan, made here so that the triangles are measured once).
void count_triangles(Strip& s, const Split& split, bool keep) {
  const Triangulation& T = s.T;
  auto at = [&](std::uint32_t v) { return Vec2{T.xy[v].x + T.origin.x, T.xy[v].y + T.origin.y}; };  // exact
  const double zlo = split.zone_lo(s.index), zhi = split.zone_hi(s.index), deep = split.margin / 2;
  const bool left_open = std::isinf(s.lo), right_open = std::isinf(s.hi);
  s.scan.scale2 = class_scale(T);
  s.scan.rclass.assign(T.slots(), 0);  // 0: a ghost triangle's class
  // Counted here and proven (untrusted ones are checked later). Bytes, not bits: the frontier pass below
  // reads them at random, and nn2 and vrep are gone by now, so the bytes fit under the strips' peak.
  std::vector<std::uint8_t> trusted(T.slots(), 0);
  const std::size_t slots = T.slots();
  // The measure and the deep test read the translated coordinates: the measure takes differences only
  // (the same values as from the input's), and the strip's ends translated round far below the deep
  // test's slack (0.25 % of M; coordinates are below 1e9 M).
  const double lo_t = s.lo - T.origin.x, hi_t = s.hi - T.origin.x;
  for (std::size_t t = 0; t < slots; ++t) {
    // The vertices are scattered over xy: fetching a few triangles ahead overlaps the cache misses, as
    // scan_triangles does (the same pass on one thread).
    if (t + kAhead < slots)
      for (int i = 0; i < 3; ++i)
        if (const std::uint32_t w = T.tri[3 * (t + kAhead) + i]; w != T.ghost) __builtin_prefetch(&T.xy[w]);
    if (T.is_ghost(t)) continue;
    const std::uint32_t* v = &T.tri[3 * t];
    const Vec2 &pa = T.xy[v[0]], &pb = T.xy[v[1]], &pc = T.xy[v[2]];
    const TriangleMeasure m = measure_triangle(pa, pb, pc, s.scan.scale2);
    s.scan.rclass[t] = m.rclass;
    if (deep_inside(pa, pb, pc, m, lo_t, hi_t, deep)) {
      trusted[t] = 1;
      s.areas.add(m.area);
      if (keep) s.kept.push_back({T.ids[v[0]], T.ids[v[1]], T.ids[v[2]]});
      continue;
    }
    const Vec2 a = at(v[0]), b = at(v[1]), c = at(v[2]);
    const Circle k = circle_of(a, b, c);
    const int sl = left_open ? 1 : circumcentre_side(a, b, c, k, s.lo);
    const int sh = right_open ? -1 : circumcentre_side(a, b, c, k, s.hi);
    if (sl == 2 || sh == 2) s.ok = false;
    // Circumcentre here: this strip's (its vertices are in this zone). Elsewhere: maybe, see reporter_of.
    if ((sl < 0 || sh >= 0) && reporter_of(a, b, c, k, split) != static_cast<long>(s.index)) continue;
    if (!disk_inside(k, zlo, zhi)) {
      s.untrusted.push_back({a, b, c, {T.ids[v[0]], T.ids[v[1]], T.ids[v[2]]}});
      continue;
    }
    trusted[t] = 1;
    s.areas.add(m.area);
    if (keep) s.kept.push_back({T.ids[v[0]], T.ids[v[1]], T.ids[v[2]]});
  }
  // The frontier, found from the other side: the triangles not trusted here (ghosts, the other strips',
  // the untrusted) are a few percent of the slots.
  for (std::uint32_t t = 0; t < slots; ++t) {
    if (trusted[t]) continue;
    for (std::uint32_t g = 3 * t; g < 3 * t + 3; ++g)
      if (const std::uint32_t h = T.twin[g]; trusted[h / 3]) {
        const std::uint32_t u = T.tri[h], w = T.tri[Triangulation::next(h)];
        s.frontier.push_back({{T.ids[u], at(u)}, {T.ids[w], at(w)}});
      }
  }
}

// The top 16 bits of a non-negative float (-0.0f as +0.0f): the first digit of the radix median.
std::uint32_t float_bits(float f) {
  std::uint32_t k;
  std::memcpy(&k, &f, 4);
  return k & 0x7fffffffu;
}

// The strips' two meeting points, the phases of one std::barrier: 0 when every strip's triangulation
// holds its points (the input may then be released), 1 when every strip has counted its vertices'
// nearest-neighbour distances by their top bits (the median's top bits are then known, in *nn_hi).
struct Meeting {
  std::function<void()> wait;   // arrive and wait for the others
  std::function<void()> leave;  // arrive, and drop out of the later phases (a strip that failed)
  const std::uint32_t* nn_hi;
};

// The top 16 bits of the median of the strips' owned nearest-neighbour distances (from their first
// radix histograms), and the median's rank among the distances with those bits. {0, 0} if there are none.
std::pair<std::uint32_t, std::size_t> nn_top_bucket(const std::vector<Strip>& strips) noexcept {
  auto count = [&](std::size_t b) {
    std::size_t c = 0;
    for (const Strip& s : strips) c += s.nn_top.empty() ? 0 : s.nn_top[b];
    return c;
  };
  std::size_t used = 0;
  for (std::size_t b = 0; b < (1u << 16); ++b) used += count(b);
  if (used == 0) return {0, 0};
  std::size_t rank = used / 2;
  std::uint32_t hi = 0;
  while (rank >= count(hi)) rank -= count(hi++);
  return {hi, rank};
}

// The strip's triangulation of its zone's points, and the survey of its owned triangles and vertices.
// Meets the other strips at both phases of `meet` (or leaves), whatever happens.
void survey_strip(std::span<const Vec2> points, const Options& options, const Split& split, Strip& s,
                  const Meeting& meet) {
  const double margin = split.margin;
  const double zlo = s.lo - margin, zhi = s.hi + margin;
  int phases = 0;  // of the meeting, passed
  auto pass = [&] { ++phases, meet.wait(); };
  auto leave = [&] {
    if (phases < 2) phases = 2, meet.leave();
  };
  Lap lap;
  try {
    std::vector<std::uint32_t> zone;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Vec2 p = points[i];
      if (std::isfinite(p.x) && std::isfinite(p.y) && p.x >= zlo && p.x < zhi)
        zone.push_back(static_cast<std::uint32_t>(i));
    }
    lap.to(s.cost.zone);
    triangulate_subset(s.T, points, std::move(zone), options.mode, options.order, [&] {
      s.translated = true;
      lap.to(s.cost.order);
      pass();
      lap.to(s.cost.wait_points);
    });
    lap.to(s.cost.insert);
    s.nn_top.assign(1u << 16, 0);
  } catch (const OutlineError&) {
    s.ok = false;  // too few or collinear points in this strip: the one-thread path decides
    leave();
    return;
  } catch (...) {
    leave();
    throw;
  }
  const Triangulation& T = s.T;
  const double m2 = 0.99 * margin * margin;
  s.for_owned([&](std::uint32_t v) {
    // The nearest neighbour is within M, hence in the zone: this strip measured it.
    if (!(static_cast<double>(T.nn2[v]) < m2)) s.ok = false;
    ++s.distinct;
    if (std::isfinite(T.nn2[v])) ++s.nn_top[float_bits(T.nn2[v]) >> 16];
  });
  lap.to(s.cost.nn);
  pass();
  lap.to(s.cost.wait_nn);
  // The second radix histogram (low 16 bits within the median's top bucket); then nn2 and vrep go, before
  // the classes and cells are allocated: the strips' peak is their triangulations, as one thread's.
  const std::uint32_t hi = *meet.nn_hi;
  s.nn_low.assign(1u << 16, 0);
  s.for_owned([&](std::uint32_t v) {
    const std::uint32_t k = float_bits(T.nn2[v]);
    if (std::isfinite(T.nn2[v]) && (k >> 16) == hi) ++s.nn_low[k & 0xffffu];
  });
  std::vector<float>().swap(s.T.nn2);
  std::vector<std::uint32_t>().swap(s.T.vrep);
  auto at = [&](std::uint32_t v) { return s.at(v); };
  std::uint32_t h0 = 0;  // the hull: the vertices around the ghost
  while (T.tri[h0] != T.ghost) ++h0;
  std::uint32_t h = h0;
  do {
    const std::uint32_t u = T.tri[Triangulation::next(h)];
    s.hull.push_back({T.ids[u], at(u)});
    h = T.twin[Triangulation::prev(h)];
  } while (h != h0);
  count_triangles(s, split, options.keep_triangles);
  lap.to(s.cost.survey);
}

// The strip's owned vertices in cells of size `cell` over the box (counting sort). Merged duplicates
// are indexed too (T.vrep is gone by now; a duplicate's circle test is its representative's).
void index_owned(Strip& s, double cell, const Box& box) {
  auto for_owned = [&](auto f) {
    for (std::uint32_t v = 0; v < s.T.xy.size(); ++v)
      if (s.owns_x(s.at(v).x)) f(v);
  };
  // The owned x range within the box (no pass to find the owned vertices' own range).
  const double x0 = std::max(s.lo, box.minx), x1 = std::min(s.hi, box.maxx), miny = box.miny, maxy = box.maxy;
  if (!(x1 >= x0)) return;
  s.cx0 = x0, s.cy0 = miny, s.cell = cell;
  s.nx = static_cast<std::size_t>((x1 - x0) / cell) + 1, s.ny = static_cast<std::size_t>((maxy - miny) / cell) + 1;
  // By the reciprocal: two divisions a vertex and pass made most of this stage's time. A vertex within a
  // rounding error of a cell's side may land in the cell next to it; empty_of's slack (1e-9 of a cell
  // beyond the disk) covers that, as it covers the rounding of a division.
  const double per_cell = 1 / cell;
  auto cell_of = [&](const Vec2& p) {
    const std::size_t i = std::min(s.nx - 1, static_cast<std::size_t>((p.x - x0) * per_cell));
    const std::size_t j = std::min(s.ny - 1, static_cast<std::size_t>((p.y - miny) * per_cell));
    return j * s.nx + i;
  };
  s.cell_start.assign(s.nx * s.ny + 1, 0);
  for_owned([&](std::uint32_t v) { ++s.cell_start[cell_of(s.at(v)) + 1]; });
  for (std::size_t c = 0; c + 1 < s.cell_start.size(); ++c) s.cell_start[c + 1] += s.cell_start[c];
  s.cell_vertex.resize(s.cell_start.back());
  std::vector<std::uint32_t> fill(s.cell_start.begin(), s.cell_start.end() - 1);
  for_owned([&](std::uint32_t v) { s.cell_vertex[fill[cell_of(s.at(v))]++] = v; });
}

// No point of strip j strictly inside the circle of the counter-clockwise triangle u (exact incircle;
// cells clearly outside the disk skipped).
bool empty_of(const Strip::Untrusted& u, const Strip& j) {
  if (j.cell_start.empty()) return true;
  const Circle k = circle_of(u.a, u.b, u.c);
  if (!std::isfinite(k.r)) return false;
  const double r = k.r * (1 + 1e-6) + 1e-9 * j.cell, r2 = r * r * (1 + 1e-9);
  const long i0 = std::max(0L, static_cast<long>(std::floor((k.ox - r - j.cx0) / j.cell)));
  const long i1 = std::min(static_cast<long>(j.nx) - 1, static_cast<long>(std::floor((k.ox + r - j.cx0) / j.cell)));
  const long j0 = std::max(0L, static_cast<long>(std::floor((k.oy - r - j.cy0) / j.cell)));
  const long j1 = std::min(static_cast<long>(j.ny) - 1, static_cast<long>(std::floor((k.oy + r - j.cy0) / j.cell)));
  for (long cj = j0; cj <= j1; ++cj)
    for (long ci = i0; ci <= i1; ++ci) {
      const double x0 = j.cx0 + static_cast<double>(ci) * j.cell, y0 = j.cy0 + static_cast<double>(cj) * j.cell;
      const double dx = std::max({0.0, x0 - k.ox, k.ox - (x0 + j.cell)});
      const double dy = std::max({0.0, y0 - k.oy, k.oy - (y0 + j.cell)});
      if (std::sqrt(dx * dx + dy * dy) > r) continue;  // the cell clearly misses the disk
      const std::size_t c = static_cast<std::size_t>(cj) * j.nx + static_cast<std::size_t>(ci);
      for (std::uint32_t q = j.cell_start[c]; q < j.cell_start[c + 1]; ++q) {
        const Vec2 p = j.at(j.cell_vertex[q]);
        // Clearly outside (an accurate circle is within 1e-7 of its radius, r 1e-6 beyond it): no exact test.
        if (k.accurate && (p.x - k.ox) * (p.x - k.ox) + (p.y - k.oy) * (p.y - k.oy) > r2) continue;
        if (pred::incircle(u.a.x, u.a.y, u.b.x, u.b.y, u.c.x, u.c.y, p.x, p.y) > 0) return false;
      }
    }
  return true;
}

// The untrusted triangles proven Delaunay against every other strip's points join the trusted ones.
// Strip i's: it writes only strip i and reads the others' cells, so the strips run it in parallel.
void check_untrusted(std::vector<Strip>& strips, std::size_t i, bool keep) {
  for (const Strip::Untrusted& u : strips[i].untrusted) {
    bool empty = true;
    for (std::size_t j = 0; j < strips.size() && empty; ++j)
      if (j != i) empty = empty_of(u, strips[j]);
    if (!empty) continue;
    strips[i].areas.add(triangle_area(u.a, u.b, u.c));
    if (keep) strips[i].kept.push_back(u.ids);
    const VertexRef r[3] = {{u.ids[0], u.a}, {u.ids[1], u.b}, {u.ids[2], u.c}};
    for (int e = 0; e < 3; ++e) strips[i].frontier.push_back({r[e], r[(e + 1) % 3]});
  }
}

// The convex hull of `pts` as directed edges (counter-clockwise), collinear boundary points included
// (each is a Delaunay vertex on a hull edge): the monotone chain with exact orientation.
std::vector<EdgeRef> hull_edges(std::vector<VertexRef> pts) {
  auto lex = [](const VertexRef& a, const VertexRef& b) { return a.p.x < b.p.x || (a.p.x == b.p.x && a.p.y < b.p.y); };
  std::sort(pts.begin(), pts.end(), lex);
  pts.erase(std::unique(pts.begin(), pts.end(), [](const VertexRef& a, const VertexRef& b) { return a.id == b.id; }),
            pts.end());
  std::vector<EdgeRef> edges;
  auto chain = [&](auto first, auto last) {
    std::vector<VertexRef> c;
    for (auto it = first; it != last; ++it) {
      while (c.size() >= 2 &&
             pred::orient2d(c[c.size() - 2].p.x, c[c.size() - 2].p.y, c.back().p.x, c.back().p.y, it->p.x, it->p.y) < 0)
        c.pop_back();
      c.push_back(*it);
    }
    for (std::size_t k = 0; k + 1 < c.size(); ++k) edges.push_back({c[k], c[k + 1]});
  };
  chain(pts.begin(), pts.end());
  chain(pts.rbegin(), pts.rend());
  return edges;
}

// The triangles no strip could count (their vertices leave every zone, or a point beyond the zone
// fell in their disk): the region they fill is bounded by the unmatched frontier edges; it is
// triangulated from those edges' vertices, and each triangle found must be empty of every point
// (exact). Their areas join strip 0's; false when the region cannot be recovered so.
bool recover_missing(std::vector<Strip>& strips, const std::vector<EdgeRef>& hull, bool keep) {
  std::unordered_set<std::uint64_t> known;
  for (const Strip& s : strips)
    for (const EdgeRef& e : s.frontier) known.insert(edge_key(e.a.id, e.b.id));
  for (const EdgeRef& e : hull) known.insert(edge_key(e.b.id, e.a.id));  // the outside across a hull edge
  std::unordered_set<std::uint64_t> open;  // the missing region's side of each unmatched edge, b -> a
  std::vector<VertexRef> verts;
  for (const Strip& s : strips)
    for (const EdgeRef& e : s.frontier)
      if (!known.count(edge_key(e.b.id, e.a.id))) {
        open.insert(edge_key(e.b.id, e.a.id));
        verts.push_back(e.a), verts.push_back(e.b);
      }
  if (open.empty()) return true;
  std::sort(verts.begin(), verts.end(), [](const VertexRef& a, const VertexRef& b) { return a.id < b.id; });
  verts.erase(
      std::unique(verts.begin(), verts.end(), [](const VertexRef& a, const VertexRef& b) { return a.id == b.id; }),
      verts.end());
  std::vector<Vec2> xy;
  for (const VertexRef& v : verts) xy.push_back(v.p);
  Triangulation D;
  try {
    D = triangulate(xy, Mode::DSHI, Order::Hilbert);
  } catch (const OutlineError&) {
    return false;
  }
  auto gid = [&](std::uint32_t v) { return verts[D.ids[v]].id; };
  // Flood from the open edges through D's triangles, never across a known edge.
  std::vector<std::uint8_t> seen(D.slots(), 0);
  std::vector<std::uint32_t> stack;
  for (std::uint32_t h = 0; h < D.tri.size(); ++h)
    if (D.tri[h] != D.ghost && D.tri[Triangulation::next(h)] != D.ghost &&
        open.count(edge_key(gid(D.tri[h]), gid(D.tri[Triangulation::next(h)]))))
      stack.push_back(h / 3);
  std::size_t found = 0;
  while (!stack.empty()) {
    const std::uint32_t t = stack.back();
    stack.pop_back();
    if (seen[t]) continue;
    seen[t] = 1;
    if (D.is_ghost(t)) return false;  // the region is not closed
    const std::uint32_t* v = &D.tri[3 * t];
    const Strip::Untrusted u{xy[D.ids[v[0]]], xy[D.ids[v[1]]], xy[D.ids[v[2]]], {gid(v[0]), gid(v[1]), gid(v[2])}};
    for (const Strip& s : strips)
      if (!empty_of(u, s)) return false;
    strips[0].areas.add(triangle_area(u.a, u.b, u.c));
    if (keep) strips[0].kept.push_back(u.ids);
    ++found;
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t h = 3 * t + static_cast<std::uint32_t>(i);
      if (!known.count(edge_key(gid(D.tri[Triangulation::next(h)]), gid(D.tri[h])))) stack.push_back(D.twin[h] / 3);
    }
  }
  return found > 0;
}

// The inner strip boundaries: x quantiles of a sample, rounded to a multiple of a power of two about
// 2^-20 of the extent (so that mirror images across them are exact for most inputs). Empty if the
// boundaries do not come out strictly increasing inside the box.
std::vector<double> strip_boundaries(std::span<const Vec2> points, int strips, double minx, double maxx) {
  std::vector<double> xs;
  const std::size_t step = std::max<std::size_t>(1, points.size() / 8192);
  for (std::size_t i = 0; i < points.size(); i += step)
    if (std::isfinite(points[i].x) && std::isfinite(points[i].y)) xs.push_back(points[i].x);
  std::sort(xs.begin(), xs.end());
  std::vector<double> b;
  if (xs.empty() || !(maxx > minx)) return b;
  const double unit = std::ldexp(1.0, std::ilogb(maxx - minx) - 20);
  for (int i = 1; i < strips; ++i) {
    const double q = xs[xs.size() * static_cast<std::size_t>(i) / static_cast<std::size_t>(strips)];
    const double x = std::round(q / unit) * unit;
    if (!(x > minx && x < maxx) || (!b.empty() && !(x > b.back()))) return {};
    b.push_back(x);
  }
  return b;
}

// Runs f(i) for every strip, strip 0 on the calling thread; false if any threw (an exception must not
// leave a thread: the caller then runs the one-thread path, which reports it where it can be caught).
template <class F>
bool for_each_strip(std::size_t n, F f) {
  std::vector<std::uint8_t> failed(n, 0);
  auto run = [&](std::size_t i) {
    try {
      f(i);
    } catch (...) {
      failed[i] = 1;
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t i = 1; i < n; ++i) pool.emplace_back(run, i);
  run(0);
  for (std::thread& t : pool) t.join();
  return std::find(failed.begin(), failed.end(), 1) == failed.end();
}

// The median spacing of the whole cloud from the strips' trusted triangles, or 0 when the unknown
// (untrusted) triangles could move it: the median bucket must be the same whether all of them lie
// below it or above. Merges the histograms into strip 0's (no third 2 MB one at the peak).
double merged_spacing(std::vector<Strip>& strips, std::size_t triangles) {
  AreaHistogram& all = strips[0].areas;
  for (std::size_t i = 1; i < strips.size(); ++i) all.merge(strips[i].areas);
  if (all.count() > triangles) return 0;
  const std::size_t unknown = triangles - all.count(), rank = triangles / 2;
  if (rank < unknown || rank >= all.count()) return 0;
  const std::size_t b = all.bucket_at(rank - unknown);
  if (all.bucket_at(rank) != b) return 0;
  return AreaHistogram::spacing_of(b);
}

// The median of the owned distinct vertices' nearest-neighbour distances over all strips, as
// median_distance gives it for them all: a radix median whose two histograms the strips made (the
// second within the top bucket found at their meeting).
double merged_nn_median(const std::vector<Strip>& strips) {
  auto [hi, rank] = nn_top_bucket(strips);
  auto count = [&](std::uint32_t b) {
    std::size_t c = 0;
    for (const Strip& s : strips) c += s.nn_low[b];
    return c;
  };
  std::size_t in_bucket = 0;
  for (std::uint32_t b = 0; b < (1u << 16); ++b) in_bucket += count(b);
  if (in_bucket == 0) return 0;
  std::uint32_t lo = 0;
  while (rank >= count(lo)) rank -= count(lo++);
  const std::uint32_t bits = hi << 16 | lo;
  float d2;
  std::memcpy(&d2, &bits, 4);
  return std::sqrt(static_cast<double>(d2));
}

// The global figures from the surveys into res and survey; false if the split is unsafe.
bool merge_surveys(std::vector<Strip>& strips, const Options& options, const Split& split, const Box& box, Result& res,
                   StripSurvey& survey) {
  const double margin = split.margin;
  std::vector<VertexRef> hull;
  for (const Strip& s : strips)
    if (!s.ok) return false;
  Lap lap;  // the serial parts, on this thread
  res.nn_spacing_median = merged_nn_median(strips);
  for (Strip& s : strips) std::vector<std::uint32_t>().swap(s.nn_top), std::vector<std::uint32_t>().swap(s.nn_low);
  lap.to(survey.profile.merge);
  auto cells = [&](std::size_t i) {
    Lap l;
    index_owned(strips[i], margin / 2, box);
    l.to(strips[i].cost.cells);
  };
  auto check = [&](std::size_t i) {
    Lap l;
    check_untrusted(strips, i, options.keep_triangles);
    l.to(strips[i].cost.check);
  };
  if (!for_each_strip(strips.size(), cells) || !for_each_strip(strips.size(), check)) return false;
  lap = Lap();  // strip 0's share above is its own
  for (const Strip& s : strips) hull.insert(hull.end(), s.hull.begin(), s.hull.end());
  const std::vector<EdgeRef> hull_ring = hull_edges(std::move(hull));
  if (!recover_missing(strips, hull_ring, options.keep_triangles)) return false;
  for (const Strip& s : strips) {
    survey.distinct += s.distinct;
    for (const auto& t : s.kept) survey.owned.push_back(t);
    survey.trusted += s.areas.count();
  }
  survey.hull = hull_ring.size();
  if (2 * survey.distinct < survey.hull + 2 + 1) return false;
  survey.triangles = 2 * survey.distinct - 2 - survey.hull;
  if (options.keep_triangles && survey.trusted != survey.triangles) return false;
  res.points_used = survey.distinct;
  res.stats.triangles = survey.triangles;
  res.spacing = merged_spacing(strips, survey.triangles);
  if (!(res.spacing > 0)) return false;
  const double k = options.auto_factor > 0 ? options.auto_factor
                                           : automatic_factor(res.nn_spacing_median / res.spacing, survey.distinct);
  res.alpha_mode = AlphaMode::Global;
  res.alpha_automatic = !(options.alpha_radius > 0);
  res.alpha_radius = res.alpha_automatic ? k * res.spacing : options.alpha_radius;
  lap.to(survey.profile.merge);
  // Every inside triangle at an owned vertex or at its neighbours has its disk within 4 R of the strip.
  return 4 * res.alpha_radius * (1 + 1e-6) < margin * (1 - 1e-6);
}

// The strip's inside triangles and its free edges with an owned tail, as input indices.
void strip_edges(Strip& s, double R) {
  const Triangulation& T = s.T;
  const std::vector<std::uint8_t> inside = classify_alpha(T, R, false, s.scan);
  std::vector<std::uint8_t>().swap(s.scan.rclass);
  s.edges = free_edges(T, inside, {}, [&](std::uint32_t v) { return s.owns_x(s.at(v).x); });
}

void add_stats(const Triangulation& T, Result& res) {
  res.stats.search_cost += T.stats.search_cost();
  res.stats.search_cost_locate += T.stats.locate_visits;
  res.stats.search_cost_cavity += T.stats.cavity_visits;
  res.stats.cavity_triangles += T.stats.cavity_triangles;
  res.stats.incircle_tests += T.stats.incircle_tests;
  res.stats.orient_tests += T.stats.orient_tests;
}

}  // namespace

int strips_for(const Options& options, std::size_t points) {
  if (options.threads == 1 || options.outer_only || options.alpha_mode == AlphaMode::Local ||
      options.mode != Mode::DSHI)
    return 1;
  const long hw = std::max(1L, static_cast<long>(std::thread::hardware_concurrency()));
  const long wanted = options.threads > 0 ? options.threads : hw;
  const long fit = static_cast<long>(points / std::max<std::size_t>(options.min_points_per_thread, 1));
  return static_cast<int>(std::clamp(std::min(wanted, fit), 1L, 64L));
}

// Gives the allocator's free pages back to the system. Called when every strip has made its insertion
// order and the consumed input is released (compute_outline(std::vector&&), the one-shot path whose peak
// is hg-outline's): the order's temporaries (17 bytes a point) were freed inside the allocator's heaps,
// one per thread, where the triangles' larger arrays do not fit; without this those pages stay resident
// at the peak (measured: +6 MB RSS on 1.59 M points with 2 threads, heap peak unchanged). A caller that
// keeps its points (a span: the outline service, hg-bench) holds more than that anyway, and its next
// outline's order reuses those pages: trimming there cost 2-3 ms of waiting at the first meeting and the
// page faults of taking them back (docs/BENCHMARKS-core.md, "A second core").
void return_free_memory() noexcept {
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

// The input as it was, from the strips' copies (every finite point is in some zone, exactly as
// xy + origin; the non-finite ones come back as NaN, which the one-thread path skips alike).
void restore_points(const std::vector<Strip>& strips, std::size_t count, std::vector<Vec2>& points) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  points.assign(count, Vec2{nan, nan});
  for (const Strip& s : strips)
    for (std::uint32_t v = 0; v < s.T.xy.size(); ++v) points[s.T.ids[v]] = s.at(v);
}

// The box of the finite points, and their count. x and y in the two lanes of the same operations (as
// the one-thread path's input summary): std::min's and std::max's choices, so the same box as lane by lane.
static Box finite_box(std::span<const Vec2> points, std::size_t& finite) {
  using pred::v2, pred::v2i;
  const double inf = std::numeric_limits<double>::infinity();
  const v2 top = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  v2 lo = {inf, inf}, hi = {-inf, -inf};
  std::size_t count = 0;
  for (const Vec2& p : points) {
    const v2 q = *reinterpret_cast<const pred::v2_unaligned*>(&p.x);
    const v2i ok = pred::magnitude(q) <= top;  // false for infinities and NaN
    if ((ok[0] & ok[1]) == 0) [[unlikely]]
      continue;
    ++count;
    lo = pred::vmin(lo, q), hi = pred::vmax(hi, q);
  }
  finite = count;
  return {lo[0], hi[0], lo[1], hi[1]};
}

bool run_threaded(std::span<const Vec2> points, const Options& options, int nstrips, Result& res,
                  StripSurvey* survey_out) {
  return run_threaded(points, nullptr, options, nstrips, res, survey_out);
}

// The strips of the split, with their owned x ranges.
std::vector<Strip> make_strips(const std::vector<double>& bounds) {
  std::vector<Strip> strips(bounds.size() + 1);
  for (std::size_t i = 0; i < strips.size(); ++i) {
    strips[i].index = i;
    strips[i].lo = i == 0 ? -std::numeric_limits<double>::infinity() : bounds[i - 1];
    strips[i].hi = i + 1 == strips.size() ? std::numeric_limits<double>::infinity() : bounds[i];
  }
  return strips;
}

// The free edges of every strip (in parallel), merged; false if a strip threw.
bool merged_free_edges(std::vector<Strip>& strips, double R, Result& res, std::vector<FreeEdge>& edges) {
  const bool ok = for_each_strip(strips.size(), [&](std::size_t i) {
    Lap l;
    strip_edges(strips[i], R);
    l.to(strips[i].cost.edges);
  });
  if (!ok) return false;
  for (Strip& s : strips) {
    edges.insert(edges.end(), s.edges.begin(), s.edges.end());
    add_stats(s.T, res);
  }
  return true;
}

bool run_threaded(std::span<const Vec2> points, std::vector<Vec2>* owned, const Options& options, int nstrips,
                  Result& res, StripSurvey* survey_out) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  Lap lap;
  std::size_t finite = 0;
  const Box box = finite_box(points, finite);
  const double margin =
      kMarginUnits * std::sqrt((box.maxx - box.minx) * (box.maxy - box.miny) / static_cast<double>(finite));
  const std::vector<double> bounds = strip_boundaries(points, nstrips, box.minx, box.maxx);
  if (bounds.empty() || !std::isfinite(margin) || !(margin > 0)) return false;
  // The float slacks of the checks (zone ends, deep_inside, the margin test) assume coordinates below
  // 1e9 margins: the rounding of x - M is then far below the 0.25 % of M they leave.
  if (std::max(std::fabs(box.minx), std::fabs(box.maxx)) > 1e9 * margin) return false;
  std::vector<Strip> strips = make_strips(bounds);
  const Split split{bounds, margin};
  StripSurvey survey;
  survey.margin = margin;
  survey.boundaries = bounds;
  lap.to(survey.profile.split);
  // Once every strip's triangulation holds its zone's points, the input (when the caller gave it away)
  // is released, before the triangles are allocated: the peak then holds one copy of the cloud, as on
  // one thread. If the split then fails, the points are restored from the strips for the one-thread path.
  const std::size_t n_in = points.size();
  bool released = false;
  std::uint32_t nn_hi = 0;
  int phase = 0;
  auto on_phase = [&]() noexcept {
    if (phase++ == 0) {
      if (owned && std::all_of(strips.begin(), strips.end(), [](const Strip& s) { return s.translated; })) {
        std::vector<Vec2>().swap(*owned);
        released = true;
        return_free_memory();
      }
    } else if (phase == 2) {
      nn_hi = nn_top_bucket(strips).first;
    }
  };
  std::barrier sync(static_cast<std::ptrdiff_t>(strips.size()), on_phase);
  const Meeting meet{[&] { sync.arrive_and_wait(); }, [&] { sync.arrive_and_drop(); }, &nn_hi};
  auto fail = [&] {
    if (released) restore_points(strips, n_in, *owned);
    return false;
  };
  const bool surveyed =
      for_each_strip(strips.size(), [&](std::size_t i) { survey_strip(points, options, split, strips[i], meet); });
  const auto t1 = Clock::now();
  std::vector<FreeEdge> edges;
  if (!surveyed || !merge_surveys(strips, options, split, box, res, survey) ||
      !merged_free_edges(strips, res.alpha_radius, res, edges))
    return fail();
  const auto t2 = Clock::now();
  lap = Lap();
  try {
    res.loops = chain_loops(std::move(edges));
  } catch (const OutlineError&) {
    return fail();  // a successor missing: the strips disagree (not expected once the checks passed)
  }
  lap.to(survey.profile.chain);
  res.points_read = points.size();
  res.points_skipped = points.size() - finite;
  res.duplicates_merged = finite - survey.distinct;
  res.mode = options.mode;
  res.order = options.order;
  res.threads_used = static_cast<int>(strips.size());
  if (options.keep_triangles) res.delaunay_triangles = survey.owned;
  auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  res.time.triangulate_ms = ms(t0, t1);
  res.time.alpha_ms = ms(t1, t2);
  for (const Strip& s : strips) survey.profile.strips.push_back(s.cost);
  if (survey_out) *survey_out = std::move(survey);
  return true;
}

}  // namespace hg::outline
