// Bowyer-Watson insertion with ghost triangles; see delaunay.hpp for the conventions.
#include "delaunay.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <string>

#include "order.hpp"
#include "predicates.hpp"

namespace hg::outline {
namespace {

constexpr std::uint32_t kNone = 0xffffffffu;
// The half-edges after and before half-edge i of a triangle (by table: i is as good as random, and
// branches on it would mispredict a third of the time).
constexpr std::uint32_t kAfter[3] = {1, 2, 0}, kBefore[3] = {2, 0, 1};

std::string fmt(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

class Builder {
 public:
  Builder(Triangulation& T, Mode mode) : T_(T), mode_(mode), xy_(T.xy.data()), ghost_(T.ghost) {}

  void run(std::size_t n);  // inserts vertices 0 .. n-1 in this order

 private:
  Triangulation& T_;
  Mode mode_;
  const Vec2* xy_;
  std::uint32_t ghost_;
  std::uint32_t slots_ = 0;  // triangles in use (tri/twin are sized for all of them up front)
  // The cavity, and its boundary in counter-clockwise order: half-edge j runs from boundary_[j].from to
  // boundary_[j + 1].from, boundary_[j].twin is its twin outside the cavity (one array: one pointer less
  // to keep in a register in the cavity search).
  // Scratch arrays, grown on demand (never shrunk): cavity_ gets two more entries for the new slots.
  struct BoundaryEdge {
    std::uint32_t from, twin;
  };
  std::vector<std::uint32_t> cavity_, stack_;
  std::vector<BoundaryEdge> boundary_;
  [[gnu::noinline]] void grow_scratch(std::size_t need) {  // rare: kept out of the cavity search's registers
    if (need <= cavity_.size()) return;
    const std::size_t size = std::max(need, 2 * cavity_.size());
    cavity_.resize(size), boundary_.resize(size), stack_.resize(size);
  }
  std::size_t cavity_size_ = 0, boundary_size_ = 0;
  std::uint32_t last_ = 0;                    // DSHI: a triangle made by the previous insertion
  std::uint32_t ds_vertex_ = 0, ds_tri_ = 0;  // DS: fixed start, a triangle incident to the first vertex
  std::uint32_t dup_ = kNone;

  double orient_xy(double ax, double ay, double bx, double by, double cx, double cy) const {
    return pred::orient2d(ax, ay, bx, by, cx, cy);
  }
  double incircle(std::uint32_t a, std::uint32_t b, std::uint32_t c, const Vec2& p) const {
    static_assert(sizeof(Vec2) == 2 * sizeof(double));  // x and y consecutive: loaded as one pair
    return pred::incircle_at(&xy_[a].x, &xy_[b].x, &xy_[c].x, &p.x);
  }
  // Edge i of the finite triangle v: sets bit i of `beyond` when p is strictly on its far side, of `on`
  // when p is on its line (without a branch on the sign: the walk's next step depends on it).
  // `orients` counts the test (the walk counts in a local, added to the stats once it ends).
  void edge_side(const std::uint32_t* v, std::uint32_t i, const Vec2& p, unsigned& beyond, unsigned& on,
                 std::uint64_t& orients) const {
    ++orients;
    const std::uint32_t u = v[i], w = v[kAfter[i]];
    const double o = orient_xy(xy_[u].x, xy_[u].y, xy_[w].x, xy_[w].y, p.x, p.y);
    beyond |= static_cast<unsigned>(o < 0) << i;
    on |= static_cast<unsigned>(o == 0) << i;
  }
  // p strictly between u and v, given that the three are collinear.
  bool strictly_between(std::uint32_t u, std::uint32_t v, const Vec2& p) const {
    const Vec2 &a = xy_[u], &b = xy_[v];
    if (a.x != b.x) return (a.x < p.x && p.x < b.x) || (b.x < p.x && p.x < a.x);
    return (a.y < p.y && p.y < b.y) || (b.y < p.y && p.y < a.y);
  }
  // Ghost triangle with finite half-edge u -> v (outside on its left): in conflict when p is strictly
  // outside that hull edge, or on the edge's open segment (CGAL's rule; keeps the cavity star-shaped).
  bool ghost_conflict(std::uint32_t u, std::uint32_t v, const Vec2& p, std::uint64_t& orients) const {
    ++orients;
    const double o = orient_xy(xy_[u].x, xy_[u].y, xy_[v].x, xy_[v].y, p.x, p.y);
    return o > 0 || (o == 0 && strictly_between(u, v, p));
  }
  // Index (0..2) of the finite half-edge of a ghost triangle, kNone for a finite triangle.
  std::uint32_t ghost_edge(std::uint32_t t) const {
    const std::uint32_t* v = &T_.tri[3 * t];
    if (std::max(std::max(v[0], v[1]), v[2]) != ghost_) [[likely]]  // ghost_ is the largest vertex id
      return kNone;
    if (v[0] == ghost_) return 1;
    if (v[1] == ghost_) return 2;
    if (v[2] == ghost_) return 0;
    return kNone;
  }
  bool conflict(std::uint32_t t, const Vec2& p) {
    const std::uint32_t* v = &T_.tri[3 * t];
    const std::uint32_t ge = ghost_edge(t);
    if (ge != kNone) return ghost_conflict(v[ge], v[(ge + 1) % 3], p, T_.stats.orient_tests);
    ++T_.stats.incircle_tests;
    return incircle(v[0], v[1], v[2], p) > 0;
  }
  // Conflict test of the triangle (b, a, c) across a cavity edge, entered by its half-edge b -> a.
  // Needs no ghost search: only these three are compared. Counts the orientation tests (ghosts) only: the
  // incircle tests are the rest of the visits.
  bool conflict_across(std::uint32_t b, std::uint32_t a, std::uint32_t c, const Vec2& p, std::uint64_t& orients) const {
    if (std::max(std::max(a, b), c) == ghost_) [[unlikely]] {  // ghost_ is the largest vertex id
      const std::uint32_t u = c == ghost_ ? b : (a == ghost_ ? c : a),
                          v = c == ghost_ ? a : (a == ghost_ ? b : c);  // finite edge u -> v
      ++orients;
      const double o = pred::orient2d(xy_[u].x, xy_[u].y, xy_[v].x, xy_[v].y, p.x, p.y);
      return o > 0 || (o == 0 && strictly_between(u, v, p));
    }
    return incircle(b, a, c, p) > 0;
  }

  std::uint32_t walk(std::uint32_t start, const Vec2& p);
  std::uint32_t scan_for_conflict(const Vec2& p);
  void find_duplicate_by_scan(const Vec2& p);
  void dig_cavity(std::uint32_t t0, const Vec2& p, bool count);
  void star_cavity(std::uint32_t v, const Vec2& p);
  void insert(std::uint32_t v);
};

// Directive search: from the current triangle, cross the edge through which the ray from its centroid
// to p leaves. Every crossed edge has p strictly on its far side, so this is a visibility walk, which
// terminates in a Delaunay triangulation; the step cap is a guard only. Returns a triangle in conflict
// with p (the finite triangle containing p, or a ghost triangle whose hull edge sees p); dup_ is set
// when p equals a vertex.
std::uint32_t Builder::walk(std::uint32_t t, const Vec2& p) {
  std::uint32_t from = kNone;  // half-edge of t we entered through (p strictly on its inner side)
  const std::uint64_t cap = std::uint64_t{slots_} + 16;
  const std::uint32_t* tri = T_.tri.data();
  const std::uint32_t* twin = T_.twin.data();
  // The counters in locals (memory increments on every step would chain through the store buffer).
  std::uint64_t steps = 0, orients = 0;
  auto found = [&](std::uint32_t at) {
    T_.stats.locate_visits += steps + 1;
    T_.stats.orient_tests += orients;
    return at;
  };
  for (; steps < cap; ++steps) {
    const std::uint32_t* v = tri + 3 * t;
    const std::uint32_t ge = ghost_edge(t);
    if (ge != kNone) {
      if (ghost_conflict(v[ge], v[(ge + 1) % 3], p, orients)) return found(t);
      from = kNone;  // p may be collinear with that hull edge: test all three edges of the next one
      t = twin[3 * t + ge] / 3;
      continue;
    }
    unsigned neg = 0, zero = 0;                  // bit i: p beyond edge i / on its line
    const std::uint32_t entered = from - 3 * t;  // 0..2: the edge we came through; otherwise none
    if (entered < 3) {                           // p is strictly inside that one: the other two
      edge_side(v, kAfter[entered], p, neg, zero, orients);
      edge_side(v, kBefore[entered], p, neg, zero, orients);
    } else {
      for (std::uint32_t i = 0; i < 3; ++i) edge_side(v, i, p, neg, zero, orients);
    }
    if (neg == 0) {
      if (zero) {
        for (int i = 0; i < 3; ++i)
          if (xy_[v[i]].x == p.x && xy_[v[i]].y == p.y) dup_ = v[i];
      }
      return found(t);
    }
    const int first_neg = __builtin_ctz(neg);
    int cross = first_neg;
    if (neg & (neg - 1)) {
      // Both edges around their shared vertex s see p: the centroid ray decides.
      const int second_neg = 31 - __builtin_clz(neg);
      int incoming = first_neg, outgoing = second_neg;  // edge ending at s, edge starting at s
      if ((first_neg + 1) % 3 != second_neg) std::swap(incoming, outgoing);
      const std::uint32_t s = v[outgoing];
      const double cx = (xy_[v[0]].x + xy_[v[1]].x + xy_[v[2]].x) / 3.0;
      const double cy = (xy_[v[0]].y + xy_[v[1]].y + xy_[v[2]].y) / 3.0;
      ++orients;
      cross = pred::orient2d(cx, cy, xy_[s].x, xy_[s].y, p.x, p.y) < 0 ? incoming : outgoing;
    }
    from = twin[3 * t + cross];
    t = from / 3;
  }
  T_.stats.locate_visits += steps;
  T_.stats.orient_tests += orients;
  ++T_.stats.walk_fallbacks;
  return scan_for_conflict(p);
}

std::uint32_t Builder::scan_for_conflict(const Vec2& p) {
  for (std::uint32_t t = 0; t < slots_; ++t) {
    ++T_.stats.locate_visits;
    if (conflict(t, p)) return t;
  }
  find_duplicate_by_scan(p);
  return kNone;
}

void Builder::find_duplicate_by_scan(const Vec2& p) {
  const std::uint32_t* tri = T_.tri.data();
  for (std::uint32_t k = 0; k < 3 * slots_; ++k)
    if (tri[k] != ghost_ && xy_[tri[k]].x == p.x && xy_[tri[k]].y == p.y) {
      dup_ = tri[k];
      return;
    }
}

// The conflict region, by depth-first search from t0 (in conflict), taking each triangle's edges in
// counter-clockwise order: the boundary edges then come out in counter-clockwise order around the cavity.
// The cavity is a disk whose vertices all lie on its boundary (each becomes a neighbour of p), so its
// triangles form a tree across their shared edges: each is reached once, no marks are needed. A
// triangle outside touching the cavity along two edges is tested twice (rare; counted twice).
void Builder::dig_cavity(std::uint32_t t0, const Vec2& p, bool count) {
  const std::uint32_t* tri = T_.tri.data();
  const std::uint32_t* twin = T_.twin.data();
  std::uint64_t orients = 0;
  // Sizes: the stack holds at most cavity + 3 half-edges, the boundary cavity + 2; checked per triangle
  // (run() sized the arrays for 64 first, and they never shrink).
  std::uint32_t* cav = cavity_.data();
  BoundaryEdge* bd = boundary_.data();
  std::uint32_t* st = stack_.data();
  std::size_t nc = 0, nb = 0, ns = 0, room = cavity_.size();
  cav[nc++] = t0;
  st[ns++] = 3 * t0 + 2;
  st[ns++] = 3 * t0 + 1;
  st[ns++] = 3 * t0;
  while (ns > 0) {
    const std::uint32_t h = st[--ns];
    const std::uint32_t g = twin[h];
    const std::uint32_t t = g / 3, t3 = 3 * t, i = g - t3;
    const std::uint32_t g_after = t3 + kAfter[i], g_before = t3 + kBefore[i];
    if (conflict_across(tri[g], tri[g_after], tri[g_before], p, orients)) {
      if (nc + 8 > room) [[unlikely]] {
        grow_scratch(nc + 8);
        cav = cavity_.data(), bd = boundary_.data(), st = stack_.data();
        room = cavity_.size();
      }
      cav[nc++] = t;
      st[ns++] = g_before;  // then the edge after it
      st[ns++] = g_after;   // the edge after g first
    } else {
      bd[nb++] = {tri[h], g};
    }
  }
  cavity_size_ = nc;
  boundary_size_ = nb;
  if (count) {
    // Every triangle pushed two edges, t0 three: 2 nc + 1 visits, each an orientation or an incircle test.
    const std::uint64_t visits = 2 * nc + 1;
    T_.stats.cavity_visits += visits;
    T_.stats.orient_tests += orients;
    T_.stats.incircle_tests += visits - orients;
  }
}

void Builder::insert(std::uint32_t v) {
  const Vec2 p = xy_[v];
  dup_ = kNone;
  std::uint32_t t0 = kNone;
  if (mode_ == Mode::Ordinary) {
    // The paper's ordinary scheme: every live triangle is tested (and counted); the cavity is then
    // collected from the first one found, its tests not counted again.
    for (std::uint32_t t = 0; t < slots_; ++t) {
      ++T_.stats.locate_visits;
      if (conflict(t, p) && t0 == kNone) t0 = t;
    }
    if (t0 == kNone) find_duplicate_by_scan(p);
  } else {
    t0 = walk(mode_ == Mode::DS ? ds_tri_ : last_, p);
  }
  if (dup_ == kNone && t0 == kNone)
    throw OutlineError("internal error: no triangle in conflict with point " + std::to_string(v));
  if (dup_ != kNone) {
    T_.vrep[v] = dup_;
    ++T_.duplicates;
    return;
  }
  dig_cavity(t0, p, mode_ != Mode::Ordinary);
  const std::size_t m = boundary_size_;  // a disk of m - 2 triangles has m boundary edges
  T_.stats.cavity_triangles += cavity_size_;

  star_cavity(v, p);
  if (mode_ == Mode::DS) {
    // The fixed start may have been in the cavity: keep a finite triangle incident to ds_vertex_.
    const std::uint32_t* w = T_.tri.data() + 3 * ds_tri_;
    const bool ok = (w[0] == ds_vertex_ || w[1] == ds_vertex_ || w[2] == ds_vertex_) && ghost_edge(ds_tri_) == kNone;
    if (!ok)
      for (std::size_t j = 0; j < m; ++j) {
        const std::uint32_t a = boundary_[j].from, b = boundary_[j + 1 == m ? 0 : j + 1].from;
        if ((a == ds_vertex_ || b == ds_vertex_) && a != ghost_ && b != ghost_) ds_tri_ = cavity_[j];
      }
  }
  ++T_.inserted;
}

// Replaces the cavity by the fan of new triangles around v (the boundary edges to v) and picks DSHI's next
// start among them.
void Builder::star_cavity(std::uint32_t v, const Vec2& p) {
  const std::size_t m = boundary_size_;  // a disk of m - 2 triangles has m boundary edges
  // Star the cavity from p: new triangle j = (boundary_[j].from, boundary_[j + 1].from, v), in the cavity's slots and
  // two appended. Its edge 0 faces the outside, edge 1 (b -> v) is edge 2 of triangle j + 1.
  // Room is kept: the cavity holds m - 2 entries, the arrays at least m + 5 (dig_cavity): the two new slots
  // and a copy of entry 0 after the last (no wrap-around test in the loop) fit.
  std::uint32_t* cav = cavity_.data();
  BoundaryEdge* bd = boundary_.data();
  cav[cavity_size_] = slots_;
  cav[cavity_size_ + 1] = slots_ + 1;
  cav[m] = cav[0];
  bd[m] = bd[0];
  slots_ += 2;
  std::uint32_t* tri = T_.tri.data();
  std::uint32_t* twin = T_.twin.data();
  float* nn2 = T_.nn2.data();
  float nn2_v = nn2[v];
  std::uint32_t finite_new = kNone;
  // DSHI's start for the next insertion: of the new triangles around v, the one whose angle at v holds the
  // direction to the next point (vertex v + 1: ids are the insertion order), so the walk starts next to
  // it. A plain floating-point choice: any start is correct, this one only shortens the walk.
  const Vec2 q = xy_[v + 1 < T_.ghost ? v + 1 : v];
  const double qx = q.x - p.x, qy = q.y - p.y;
  std::uint32_t toward = kNone;
  bool left_of_prev = false;  // the direction to the next point is left of v -> a for the previous a (finite)
  std::uint32_t t_prev = cav[m - 1];
  for (std::size_t j = 0; j < m; ++j) {
    const std::uint32_t t = cav[j], a = bd[j].from, b = bd[j + 1].from, o = bd[j].twin;
    tri[3 * t] = a;
    tri[3 * t + 1] = b;
    tri[3 * t + 2] = v;
    twin[3 * t] = o;
    twin[o] = 3 * t;
    twin[3 * t + 1] = 3 * cav[j + 1] + 2;
    twin[3 * t + 2] = 3 * t_prev + 1;
    if (a != ghost_) {
      // v's new Delaunay neighbours: the nearest neighbour of either end is found when the later of the
      // two is inserted (a final Delaunay edge is an edge of every intermediate triangulation).
      const double dx = xy_[a].x - p.x, dy = xy_[a].y - p.y;
      const float d2 = static_cast<float>(dx * dx + dy * dy);
      nn2_v = std::min(nn2_v, d2);
      nn2[a] = std::min(nn2[a], d2);
      if (finite_new == kNone && b != ghost_) finite_new = t;
      const bool left = dx * qy - dy * qx >= 0;
      // Triangle j - 1 = (a_{j-1}, a_j, v) holds the direction when it turns here; chosen by a mask, as the
      // turn's position around v is random (a branch on it mispredicted 2.4 times a point).
      const std::uint32_t turn = 0u - static_cast<std::uint32_t>(left_of_prev & !left);
      toward = (t_prev & turn) | (toward & ~turn);
      left_of_prev = left;
    } else {
      left_of_prev = false;
    }
    t_prev = t;
  }
  if (toward != kNone) finite_new = toward;
  nn2[v] = nn2_v;
  last_ = finite_new;
}

void Builder::run(std::size_t n) {
  auto order = [](std::size_t k) { return static_cast<std::uint32_t>(k); };
  // Initial triangle: the first point, the first point different from it, the first point not collinear
  // with both. Points skipped on the way are inserted right after, in their order.
  const std::uint32_t p0 = order(0);
  std::size_t k1 = 1;
  while (k1 < n && xy_[order(k1)].x == xy_[p0].x && xy_[order(k1)].y == xy_[p0].y) ++k1;
  std::size_t k2 = k1 + 1;
  if (k1 < n) {
    const std::uint32_t p1 = order(k1);
    while (k2 < n &&
           pred::orient2d(xy_[p0].x, xy_[p0].y, xy_[p1].x, xy_[p1].y, xy_[order(k2)].x, xy_[order(k2)].y) == 0)
      ++k2;
  }
  if (k1 >= n || k2 >= n) {
    std::vector<Vec2> distinct(xy_, xy_ + n);
    std::sort(distinct.begin(), distinct.end(),
              [](const Vec2& a, const Vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    const auto e = std::unique(distinct.begin(), distinct.end(),
                               [](const Vec2& a, const Vec2& b) { return a.x == b.x && a.y == b.y; });
    const std::size_t count = static_cast<std::size_t>(e - distinct.begin());
    if (count < 3) throw OutlineError("need at least 3 distinct points, got " + std::to_string(count));
    throw OutlineError("all " + std::to_string(count) + " distinct points are collinear");
  }
  std::uint32_t a = p0, b = order(k1), c = order(k2);
  if (pred::orient2d(xy_[a].x, xy_[a].y, xy_[b].x, xy_[b].y, xy_[c].x, xy_[c].y) < 0) std::swap(b, c);

  // A triangulation of n + 1 vertices (the ghost included) on the sphere has 2 (n + 1) - 4 triangles:
  // every slot is allocated once, no growth during the insertion.
  const std::size_t max_slots = 2 * n + 2;
  T_.tri.resize(3 * max_slots);  // uninitialised (SlotArray): a slot is written when first used
  T_.twin.resize(3 * max_slots);
  const std::uint32_t init_tri[12] = {a, b, c, b, a, ghost_, c, b, ghost_, a, c, ghost_};
  const std::uint32_t init_twin[12] = {3, 6, 9, 0, 11, 7, 1, 5, 10, 2, 8, 4};
  std::copy(init_tri, init_tri + 12, T_.tri.begin());
  std::copy(init_twin, init_twin + 12, T_.twin.begin());
  slots_ = 4;
  T_.inserted = 3;
  T_.nn2.assign(n, std::numeric_limits<float>::infinity());
  for (std::uint32_t u : {a, b, c})
    for (std::uint32_t w : {a, b, c})
      if (u != w) {
        const double dx = xy_[u].x - xy_[w].x, dy = xy_[u].y - xy_[w].y;
        T_.nn2[u] = std::min(T_.nn2[u], static_cast<float>(dx * dx + dy * dy));
      }
  last_ = 0;
  ds_vertex_ = a;
  ds_tri_ = 0;
  grow_scratch(64);

  for (std::size_t k = 1; k < k2; ++k)
    if (k != k1) insert(order(k));
  for (std::size_t k = k2 + 1; k < n; ++k) insert(order(k));
  T_.tri.resize(3 * std::size_t{slots_});
  T_.twin.resize(3 * std::size_t{slots_});
}

}  // namespace

std::size_t Triangulation::finite_count() const {
  std::size_t c = 0;
  for (std::size_t t = 0; t < slots(); ++t) c += !is_ghost(t);
  return c;
}

Triangulation triangulate(std::span<const Vec2> points, Mode mode, Order order) {
  return triangulate(points, mode, order, {});
}

namespace {

bool is_finite(const Vec2& p) { return std::isfinite(p.x) && std::isfinite(p.y); }

// What the triangulation needs to know of the input before ordering it, from one pass: the finite
// points' count, box and coordinate sum, and whether any finite coordinate is so small (nonzero, below
// 2^-118) that it may have set bits below the exact resolution 2^-170 (every larger double is a multiple
// of 2^-170: its last mantissa bit is worth at least 2^-118-52).
struct InputSummary {
  std::size_t finite = 0;
  Box box{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  double sx = 0, sy = 0;
  bool tiny = false;
};

// A point as an (x, y) pair of a two-lane vector.
pred::v2 pair_of(const Vec2& p) { return *reinterpret_cast<const pred::v2_unaligned*>(&p.x); }

InputSummary summarize(std::span<const Vec2> points) {
  using pred::v2, pred::v2i;
  InputSummary s;
  // x and y in the two lanes of the same operations: std::min's and std::max's choices, the sums in the
  // same order, so the same box and sums as lane by lane.
  v2 lo = {s.box.minx, s.box.miny}, hi = {s.box.maxx, s.box.maxy}, sum = {0, 0};
  v2i tiny = {0, 0};
  const v2 top = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  for (const Vec2& p : points) {
    const v2 q = pair_of(p), m = pred::magnitude(q);
    const v2i finite = m <= top;  // false for infinities and NaN
    if ((finite[0] & finite[1]) == 0) [[unlikely]]
      continue;
    ++s.finite;
    lo = pred::vmin(lo, q), hi = pred::vmax(hi, q);
    sum += q;
    tiny |= (m < 0x1p-118) & (q != 0);
  }
  s.box = {lo[0], hi[0], lo[1], hi[1]};
  s.sx = sum[0], s.sy = sum[1];
  s.tiny = (tiny[0] | tiny[1]) != 0;
  return s;
}

std::vector<std::uint32_t> finite_indices(std::span<const Vec2> points) {
  std::vector<std::uint32_t> finite;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (is_finite(points[i])) finite.push_back(static_cast<std::uint32_t>(i));
  return finite;
}

// The predicates are exact while their products neither overflow nor underflow (predicates.hpp): a
// cloud spanning more than 1e60, or a coordinate with a set bit below 2^-170, is refused (naming the
// point) rather than triangulated wrongly.
void check_range(std::span<const Vec2> points, const InputSummary& s) {
  const Box& b = s.box;
  if (!(b.maxx - b.minx <= 1e60 && b.maxy - b.miny <= 1e60)) {
    // The point farthest from the mean (the box's centre if the sum overflows) is the odd one out.
    const std::vector<std::uint32_t> finite = finite_indices(points);
    Vec2 c{s.sx / static_cast<double>(s.finite), s.sy / static_cast<double>(s.finite)};
    if (!std::isfinite(c.x) || !std::isfinite(c.y)) c = {b.minx / 2 + b.maxx / 2, b.miny / 2 + b.maxy / 2};
    auto dist = [&](std::uint32_t i) { return std::max(std::fabs(points[i].x - c.x), std::fabs(points[i].y - c.y)); };
    const std::uint32_t extreme = *std::max_element(
        finite.begin(), finite.end(), [&](std::uint32_t i, std::uint32_t j) { return dist(i) < dist(j); });
    throw OutlineError("point " + std::to_string(extreme) + " (x=" + fmt(points[extreme].x) +
                       ", y=" + fmt(points[extreme].y) +
                       ") is too far from the others: the cloud must span less than 1e60 for exact predicates");
  }
  if (!s.tiny) return;  // every finite coordinate is 0 or at least 2^-118: within the resolution
  for (std::size_t i = 0; i < points.size(); ++i)
    if (is_finite(points[i]) &&
        (!pred::within_exact_resolution(points[i].x) || !pred::within_exact_resolution(points[i].y)))
      throw OutlineError(
          "point " + std::to_string(i) + " (x=" + fmt(points[i].x) + ", y=" + fmt(points[i].y) +
          ") has a coordinate too finely resolved for exact predicates (a set bit below 2^-170, about 7e-52)");
}

// The candidate translation: the centroid rounded to a multiple of a power of two about 2^-20 of the
// extent (a negligible shift). It then has few significant bits, so for coordinates with few bits
// themselves (float32 camera data) the translated coordinates keep few bits; products of their
// differences are then exact doubles and the exact fallback of the predicates (frequent on noise-free
// grids, where every cell is nearly cocircular) works on one-component expansions. It is used only if
// every translated coordinate turns out exact (translate_exactly), so that the triangulation is that of
// the input as given; otherwise the origin is 0 and the points are triangulated as they are.
Vec2 rounded_centroid(const InputSummary& s) {
  const Box& b = s.box;
  const double n = static_cast<double>(s.finite);
  Vec2 o{s.sx / n, s.sy / n};
  if (!std::isfinite(o.x) || !std::isfinite(o.y))
    o = {b.minx / 2 + b.maxx / 2, b.miny / 2 + b.maxy / 2};  // the sum overflowed
  const double extent = std::max(b.maxx - b.minx, b.maxy - b.miny);
  if (!(std::isfinite(extent) && extent > 0)) return {0, 0};
  const double unit = std::ldexp(1.0, std::ilogb(extent) - 20);
  o = {std::round(o.x / unit) * unit, std::round(o.y / unit) * unit};
  if (!std::isfinite(o.x) || !std::isfinite(o.y)) return {0, 0};
  return o;
}

// xy[v] = points[ids[v]] - origin; false, as soon as one is found, if any of these subtractions rounded
// (checked on the way, by the error term of each: one pass for the copy and the check).
bool translate_exactly(std::span<const Vec2> points, Triangulation& T) {
  using pred::v2, pred::v2i;
  const std::size_t n = T.ids.size();
  const v2 o = pair_of(T.origin);
  T.xy.resize(n);
  for (std::size_t v = 0; v < n; ++v) {
    // pred::difference_is_exact on x and y at once (the same operations in two lanes).
    const v2 p = pair_of(points[T.ids[v]]);
    const v2 d = p - o, bv = p - d, av = d + bv;
    T.xy[v] = {d[0], d[1]};
    const v2i inexact = (p - av) + (bv - o) != 0;
    if ((inexact[0] | inexact[1]) != 0) return false;
  }
  return true;
}

// The same for the given (finite) points, in the two lanes as summarize: the same figures as lane by lane.
InputSummary summarize_subset(std::span<const Vec2> points, std::span<const std::uint32_t> subset) {
  using pred::v2, pred::v2i;
  InputSummary s;
  v2 lo = {s.box.minx, s.box.miny}, hi = {s.box.maxx, s.box.maxy}, sum = {0, 0};
  v2i tiny = {0, 0};
  for (std::uint32_t i : subset) {
    const v2 q = pair_of(points[i]);
    lo = pred::vmin(lo, q), hi = pred::vmax(hi, q);
    sum += q;
    tiny |= (pred::magnitude(q) < 0x1p-118) & (q != 0);
  }
  s.finite = subset.size();
  s.box = {lo[0], hi[0], lo[1], hi[1]};
  s.sx = sum[0], s.sy = sum[1];
  s.tiny = (tiny[0] | tiny[1]) != 0;
  return s;
}

// The triangulation of the finite points (of points[subset[k]] when a subset is given) into T; `translated`,
// when given, runs once the translated copy exists (every point is xy + origin exactly, and `points` is
// not read again: the caller may release it there). T keeps what was built if a later step throws.
void triangulate_impl(Triangulation& T, std::span<const Vec2> points, Mode mode, Order order,
                      std::vector<std::uint32_t> custom, std::vector<std::uint32_t> subset,
                      const std::function<void()>& translated) {
  const std::size_t n_in = points.size();
  if (n_in > 500'000'000) throw OutlineError("too many points: " + std::to_string(n_in));
  if (!custom.empty() && custom.size() != n_in) throw OutlineError("custom insertion order has the wrong size");
  const bool given_subset = !subset.empty();
  const InputSummary s = given_subset ? summarize_subset(points, subset) : summarize(points);
  T.skipped = given_subset ? 0 : n_in - s.finite;
  const std::size_t n = s.finite;
  if (n < 3)
    throw OutlineError("need at least 3 distinct points, got " + std::to_string(n) + " finite points" +
                       (T.skipped ? " (" + std::to_string(T.skipped) + " non-finite skipped)" : std::string()));
  check_range(points, s);
  // Positions of the finite points in the input; none needed when all are finite (the usual case).
  std::vector<std::uint32_t> finite =
      given_subset ? std::move(subset) : (T.skipped ? finite_indices(points) : std::vector<std::uint32_t>{});
  const bool given_order = !custom.empty();
  if (given_order) {
    std::erase_if(custom, [&](std::uint32_t i) { return i >= n_in || !is_finite(points[i]); });
    if (custom.size() != n) throw OutlineError("custom insertion order is not a permutation");
    T.ids = std::move(custom);
  }
  // The candidate origin first; if a translated coordinate would round, once more with origin 0 (full-
  // precision input: exact as given). The insertion order is computed once, from the candidate: the
  // order decides the speed only (the triangulation is the Delaunay one of the points as given, up to
  // cocircular ties, which the alpha boundary does not depend on), and sorting again costs more than
  // the whole copy.
  T.origin = rounded_centroid(s);
  if (!given_order) {
    const Vec2 o = T.origin;
    const Box tb{s.box.minx - o.x, s.box.maxx - o.x, s.box.miny - o.y, s.box.maxy - o.y};
    T.ids = order_translated(points, finite, o, tb, order);
  }
  std::vector<std::uint32_t>().swap(finite);  // T.ids has them all now (a subset's 4 bytes a point)
  for (Vec2 origin : {T.origin, Vec2{0, 0}}) {
    T.origin = origin;
    if (translate_exactly(points, T)) {
      T.xy_min = {s.box.minx - origin.x, s.box.miny - origin.y};  // exact, as every translated coordinate
      T.xy_max = {s.box.maxx - origin.x, s.box.maxy - origin.y};
      break;
    }
  }
  if (translated) translated();
  T.ghost = static_cast<std::uint32_t>(n);
  T.vrep.resize(n);
  for (std::size_t v = 0; v < n; ++v) T.vrep[v] = static_cast<std::uint32_t>(v);
  Builder(T, mode).run(n);
}

}  // namespace

Triangulation triangulate(std::span<const Vec2> points, Mode mode, Order order, std::vector<std::uint32_t> custom) {
  Triangulation T;
  triangulate_impl(T, points, mode, order, std::move(custom), {}, {});
  return T;
}

Triangulation triangulate_releasing(std::vector<Vec2>& points, Mode mode, Order order) {
  Triangulation T;
  triangulate_impl(T, points, mode, order, {}, {}, [&] { std::vector<Vec2>().swap(points); });
  return T;
}

void triangulate_subset(Triangulation& T, std::span<const Vec2> points, std::vector<std::uint32_t> subset, Mode mode,
                        Order order, const std::function<void()>& translated) {
  if (subset.empty()) throw OutlineError("need at least 3 distinct points, got 0 finite points");
  triangulate_impl(T, points, mode, order, {}, std::move(subset), translated);
}

}  // namespace hg::outline
