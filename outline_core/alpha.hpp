// Alpha shape by circumradius (paper section 3.2) and the chaining of its free edges into loops.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <vector>

#include "delaunay.hpp"
#include "predicates.hpp"
#include "types.hpp"

namespace hg::outline {

// Default k of the automatic radius R = k x point spacing h for a regular (grid-like) cloud
// (docs/outline-auto-radius.md).
inline constexpr double kDefaultAutoFactor = 1.7;

// The automatic k follows how random the cloud is, measured by q = median nearest-neighbour distance / h
// (1 on a grid, 0.66 at +-0.5 spacing uniform or sigma 0.3 noise, 0.542 for a Poisson set). A random
// cloud has empty circles larger than 1.7 h: its k is random_cloud_factor. In between, k is linear in q.
inline constexpr double kRegularNnRatio = 0.65;  // q >= this: k = kDefaultAutoFactor
inline constexpr double kRandomNnRatio = 0.55;   // q <= this: k = random_cloud_factor
// h x sqrt(point density) of a Poisson set (measured: 0.864 at 20 k points, 0.867 at 400 k).
inline constexpr double kPoissonSpacing = 0.866;

// The k at which a Poisson set of n points expects one Delaunay triangle with circumradius > k x h:
// among its ~2n triangles t = pi x density x r^2 is Gamma(2)-distributed, P(t > T) = (1 + T) e^-T, so
// (1 + T) e^-T = 1 / (2n) and k = sqrt(T / pi) / kPoissonSpacing; never below kDefaultAutoFactor.
// 2.14 at 2 k points, 2.66 at 500 k, 2.76 at 1.6 M.
double random_cloud_factor(std::size_t points);

// The automatic k for a cloud of `points` points with regularity q (see above).
double automatic_factor(double q, std::size_t points);

// Median over the triangulated points of the distance to the nearest other point (Triangulation::nn2,
// read off the Delaunay edges during insertion: the nearest neighbour is always a Delaunay neighbour).
// Not the unit of R (in-plane noise shrinks it: ~0.65 of the grid spacing at +-0.5 spacing noise); its
// ratio to the triangle spacing is the regularity q of automatic_factor.
double median_nn_spacing(const Triangulation& T);
// The same median over given squared distances (non-finite ones ignored): sqrt of the element of rank
// count / 2. The threaded outline merges the strips' vertices with it.
double median_distance(std::span<const float> squared);

// Histogram of triangle areas behind median_triangle_spacing: the top 20 bits of each float area
// (exponent and 11 mantissa bits, 2 MB); the median is read off as its bucket's lower edge, within 2^-11
// of the true median, exact for areas with few mantissa bits (the 0.5 of a unit grid's triangles).
class AreaHistogram {
 public:
  AreaHistogram();
  // The bucket of an area (its float's top 20 bits); false for a non-finite area.
  // Inline: a pass over millions of triangles adds each one's area.
  static bool bucket_of(double area, std::uint32_t& bucket) {
    const float f = static_cast<float>(area);
    if (!std::isfinite(f)) return false;
    std::memcpy(&bucket, &f, 4);
    bucket = (bucket & 0x7fffffffu) >> 12;  // -0.0f as +0.0f
    return true;
  }
  void add(double area) {  // non-finite areas are not counted
    std::uint32_t b;
    if (!bucket_of(area, b)) return;
    if (hist_.empty()) [[unlikely]]
      hist_.assign(kBuckets, 0);
    ++hist_[b];
    ++used_;
  }
  void merge(const AreaHistogram& other);
  std::size_t count() const { return used_; }
  std::size_t bucket_at(std::size_t rank) const;  // the bucket holding the element of this rank (< count)
  static double spacing_of(std::size_t bucket);   // sqrt(2 x the bucket's lower edge)
  double spacing() const { return used_ ? spacing_of(bucket_at(used_ / 2)) : 0; }

 private:
  static constexpr std::size_t kBuckets = std::size_t{1} << 19;
  std::vector<std::uint32_t> hist_;  // allocated by the first add or merge (none at the threads' peak)
  std::size_t used_ = 0;
};
// The area of a finite triangle as the spacing counts it: the same value for every rotation and
// orientation of the vertices, and for any exact translation of them.
double triangle_area(const Vec2& a, const Vec2& b, const Vec2& c);

// The point spacing of the automatic radius: sqrt(2 x median area of the finite Delaunay triangles)
// (= the pitch on a square grid, whose cells split into two triangles). Noise does not shrink it (the
// triangles still tile the same area with about 2 per point), and dropout, edges and cut-outs only add
// a minority of larger triangles, which the median ignores. One pass, a 2 MB histogram; the median
// area to 2^-11 relative (its bucket's lower edge; exact for a grid's 0.5).
double median_triangle_spacing(const Triangulation& T);

// The same pass, also giving each triangle a coarse class of its circumradius (16 per octave of r^2, from
// a floating-point estimate, 255 where the estimate is not accurate to 1e-5): classify_alpha then
// decides by the classes alone where they are 3 or more apart from R's and calls the exact predicate
// only near R, so the extra pass costs the classification almost nothing. One byte per triangle.
struct TriangleScan {
  double spacing = 0;                // median_triangle_spacing
  double scale2 = 0;                 // the classes are of r^2 / scale2 (bounding-box area per point)
  std::vector<std::uint8_t> rclass;  // per triangle slot; 0 for the ghost triangles
};
TriangleScan scan_triangles(const Triangulation& T);
// One triangle's figures of that pass, for callers that make their own TriangleScan in a pass of theirs
// (the threaded outline's strips): the area (triangle_area) and the class of r^2 / scale2, scale2 being
// class_scale(T) (the bounding-box area per point), for a finite counter-clockwise triangle; and r^2 as
// N / (4 D^2) (N the product of the squared edge lengths, D twice the signed area), accurate to about
// 2e-6 relative where the class is decided (not kUndecidedClass).
struct TriangleMeasure {
  double area;
  std::uint8_t rclass;
  double N, D;
};
inline constexpr std::uint8_t kUndecidedClass = 255;
// Class of q = r^2 / scale2 > 0 from its bits: 16 per octave (exponent and top 4 mantissa bits), 1 at
// q < 2^-8 ... 254 at q >= 2^7.9. Monotone in q; a class spans 3-6 % of q.
inline std::uint8_t r2_class(double q) {
  if (!(q > 0)) return 1;
  std::uint64_t bits;
  std::memcpy(&bits, &q, 8);
  const long c = static_cast<long>(bits >> 48) - 1023L * 16 + 128;
  return static_cast<std::uint8_t>(std::clamp(c, 1L, 254L));
}
// The area is the middle of the three pivots' values, a function of the vertex set (the same for every
// insertion order, whatever rotation the triangle is stored in), without data-dependent branches. The
// class is kUndecidedClass unless r^2 is accurate to about 2e-6 relative (|D| far above its rounding
// bound, no overflow or underflow); it needs no such symmetry (it only skips the exact predicate where the
// decision is certain). Only coordinate differences enter: the same figures for any exact translation.
// Inline: the passes over millions of triangles call it once each.
[[gnu::always_inline]] inline TriangleMeasure measure_triangle(const Vec2& a, const Vec2& b, const Vec2& c,
                                                               double scale2) {
  const double abx = a.x - b.x, aby = a.y - b.y, bcx = b.x - c.x, bcy = b.y - c.y, cax = c.x - a.x, cay = c.y - a.y;
  // Twice the signed area with each vertex as the pivot, as orient2d computes it: for pivot c,
  // (a.x - c.x)(b.y - c.y) - (a.y - c.y)(b.x - c.x). Written with the edge differences above, whose
  // negatives those are exactly (rounding is symmetric), so the same values and signs of zero come out of
  // six differences instead of twelve.
  const double pa = aby * cax, qa = abx * cay, pb = bcy * abx, qb = bcx * aby, pc = cay * bcx, qc = cax * bcy;
  const double da = pa - qa, db = pb - qb, dc = pc - qc;
  const double mid = std::max(std::min(da, db), std::min(std::max(da, db), dc));
  const double N = (abx * abx + aby * aby) * (bcx * bcx + bcy * bcy) * (cax * cax + cay * cay);
  TriangleMeasure m{std::fabs(mid) / 2, kUndecidedClass, N, dc};
  const double errD = pred::kOrientBound * (std::fabs(qc) + std::fabs(pc));
  const double den = 4 * (dc * dc) * scale2;
  if (std::fabs(dc) > 1e6 * errD && std::isnormal(N) && std::isnormal(den)) {
    const double q = N / den;
    if (std::isnormal(q)) m.rclass = r2_class(q);
  }
  return m;
}
// measure_triangle of two triangles, (p0[0], p0[1], p0[2]) and (p1[0], p1[1], p1[2]), one in each lane of
// the same two-lane vector operations (SSE2, the x86-64 baseline): measure_triangle's operations in its
// order on the same operands, so the same figures bit for bit at about half the instructions. The
// triangle scan's step (scan_triangles).
[[gnu::always_inline]] inline void measure_pair(const Vec2* const p0[3], const Vec2* const p1[3], double scale2,
                                                TriangleMeasure& m0, TriangleMeasure& m1) {
  using pred::v2, pred::vmin, pred::vmax, pred::normal;
  auto load = [](const Vec2* p) -> v2 { return *reinterpret_cast<const pred::v2_unaligned*>(&p->x); };
  v2 x[3], y[3];
  for (int i = 0; i < 3; ++i) {
    const v2 u = load(p0[i]), w = load(p1[i]);
    x[i] = pred::lanes_lo(u, w), y[i] = pred::lanes_hi(u, w);
  }
  const v2 abx = x[0] - x[1], aby = y[0] - y[1], bcx = x[1] - x[2], bcy = y[1] - y[2], cax = x[2] - x[0],
           cay = y[2] - y[0];
  const v2 pa = aby * cax, qa = abx * cay, pb = bcy * abx, qb = bcx * aby, pc = cay * bcx, qc = cax * bcy;
  const v2 da = pa - qa, db = pb - qb, dc = pc - qc;
  const v2 area = pred::magnitude(vmax(vmin(da, db), vmin(vmax(da, db), dc))) / 2;
  const v2 N = (abx * abx + aby * aby) * (bcx * bcx + bcy * bcy) * (cax * cax + cay * cay);
  const v2 errD = pred::kOrientBound * (pred::magnitude(qc) + pred::magnitude(pc));
  const v2 den = 4 * (dc * dc) * scale2;
  const v2 q = N / den;
  const pred::v2i decided = (pred::magnitude(dc) > 1e6 * errD) & normal(N) & normal(den) & normal(q);
  m0 = {area[0], decided[0] != 0 ? r2_class(q[0]) : kUndecidedClass, N[0], dc[0]};
  m1 = {area[1], decided[1] != 0 ? r2_class(q[1]) : kUndecidedClass, N[1], dc[1]};
}
double class_scale(const Triangulation& T);
// The same; the median is read off an AreaHistogram from `histogram_from` triangle slots on, below
// that by selecting among the areas' buckets (select_rank): the same bucket either way (for tests).
TriangleScan scan_triangles(const Triangulation& T, std::size_t histogram_from);

// The element of rank `rank` (< keys.size()) of `keys` sorted increasingly, as std::nth_element would
// place it; reorders `keys`. Radix selection, 8 bits per pass: a 2 KB histogram on the stack, no
// allocation, so a small cloud's median costs microseconds.
std::uint32_t select_rank(std::span<std::uint32_t> keys, std::size_t rank);

// Per vertex (by vertex id) the local spacing sqrt(2 x A_v): A_v is the median, over v and its Delaunay
// neighbours, of each one's median incident triangle area (a median of medians, so a vertex on the rim
// of a cut-out, whose own fan half spans the hole, still gets the spacing of the surface around it).
// Merged duplicates get 0. Depends only on the triangulation, not on the insertion order.
std::vector<float> local_spacing(const Triangulation& T);

// inside[t] = 1 for a finite triangle kept in the shape. A finite triangle is "big" when its circumradius
// r > R, decided exactly (r == R is kept, as CGAL's Alpha_shape_2 does with alpha = R^2: a face is
// interior when its squared radius <= alpha). Default: every big triangle is outside (cut-outs become
// holes; equals CGAL's REGULARIZED alpha shape). outer_only: the paper's BFS from the ghost triangles
// through big triangles only, so big triangles not connected to the outside stay inside.
std::vector<std::uint8_t> classify_alpha(const Triangulation& T, double R, bool outer_only);
// The same decisions (exact), faster with the classes of scan_triangles.
std::vector<std::uint8_t> classify_alpha(const Triangulation& T, double R, bool outer_only, const TriangleScan& scan);
// The same with a radius per triangle: R_t = k x (middle of the three vertex spacings), a symmetric
// function of the triangle's vertex set, compared exactly with the circumradius as above.
std::vector<std::uint8_t> classify_alpha_local(const Triangulation& T, std::span<const float> vertex_spacing, double k,
                                               bool outer_only);
// R_t of classify_alpha_local for the vertices u, v, w.
double local_radius(std::span<const float> vertex_spacing, double k, std::uint32_t u, std::uint32_t v, std::uint32_t w);

// Chains the free half-edges (inside triangle on the left, outside or ghost on the right) into closed
// loops. At a pinch vertex the outgoing edge paired with an incoming one is the next free edge of the
// same fan of inside triangles; a closed chain that still visits a vertex twice is split there, so every
// loop is a simple polygon with >= 3 vertices. `input` (the points as given) may be empty when the
// triangulation came from triangulate_releasing and released them: coordinates are then xy + origin. Outer loops
// (counter-clockwise) first, then holes (clockwise), each group by decreasing area; each loop starts at its smallest
// point index.
std::vector<Loop> extract_loops(const Triangulation& T, const std::vector<std::uint8_t>& inside,
                                std::span<const Vec2> input);

// extract_loops in two steps, so that strips of a split cloud can each contribute their free edges:
// a free half-edge from -> to (input indices), the head of the free edge after it (the pinch rule
// above) and the coordinates of `from`.
struct FreeEdge {
  std::uint32_t from = 0, to = 0, next = 0;
  Vec2 from_xy;
};
// The free edges of T whose tail vertex v passes keep_tail(v) (by vertex id). `input` as above.
template <class KeepTail>
std::vector<FreeEdge> free_edges(const Triangulation& T, const std::vector<std::uint8_t>& inside,
                                 std::span<const Vec2> input, KeepTail keep_tail);
// The loops through a complete set of free edges (each edge's successor present), in extract_loops'
// canonical order; the same loops whatever order the edges come in. Throws OutlineError if an edge's
// successor is missing.
std::vector<Loop> chain_loops(std::vector<FreeEdge> edges);

template <class KeepTail>
std::vector<FreeEdge> free_edges(const Triangulation& T, const std::vector<std::uint8_t>& inside,
                                 std::span<const Vec2> input, KeepTail keep_tail) {
  std::vector<FreeEdge> edges;
  // Found from the outside: a free half-edge is the twin of a half-edge of a triangle not inside (a ghost
  // or a big one: a few percent of the slots), so only those slots' three twins are looked at. The edges
  // come out in another order than a pass over all half-edges would give; chain_loops sorts them.
  const std::size_t slots = T.slots();
  for (std::size_t t = 0; t < slots; ++t) {
    if (inside[t]) continue;
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t h = T.twin[3 * t + k];
      if (!inside[h / 3] || !keep_tail(T.tri[h])) continue;
      // The next free half-edge after h = a -> b: turn around b through the inside triangles of its fan.
      std::uint32_t g = Triangulation::next(h);
      while (inside[T.twin[g] / 3]) g = Triangulation::next(T.twin[g]);
      const std::uint32_t a = T.tri[h], b = T.tri[g], c = T.tri[Triangulation::next(g)];
      const Vec2 xy = input.empty() ? Vec2{T.xy[a].x + T.origin.x, T.xy[a].y + T.origin.y} : input[T.ids[a]];
      edges.push_back({T.ids[a], T.ids[b], T.ids[c], xy});
    }
  }
  return edges;
}

}  // namespace hg::outline
