// Alpha shape classification and loop extraction; see alpha.hpp.
#include "alpha.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>

#include "predicates.hpp"

namespace hg::outline {

namespace {

// Median of the non-negative floats key(i), i < count, for which key returns true: selection by radix on
// the float bit patterns (for non-negative floats their order is that of the unsigned integers): a
// histogram of the top 16 bits finds the bucket of the median, a second one of the low 16 bits within
// that bucket finds it exactly. Two passes, no copy of the millions of values. 0 if there are none.
template <class Key>
float radix_median(std::size_t count, Key key) {
  auto bits_of = [&](std::size_t i, std::uint32_t& k) {
    float f;
    if (!key(i, f) || !std::isfinite(f)) return false;
    std::memcpy(&k, &f, 4);
    k &= 0x7fffffffu;  // -0.0f as +0.0f
    return true;
  };
  std::vector<std::uint32_t> hist(1u << 16, 0);
  std::size_t used = 0;
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t k;
    if (bits_of(i, k)) ++hist[k >> 16], ++used;
  }
  if (used == 0) return 0;
  std::size_t rank = used / 2;  // the element nth_element would put at used / 2
  std::uint32_t top = 0;
  while (rank >= hist[top]) rank -= hist[top++];
  std::fill(hist.begin(), hist.end(), 0);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t k;
    if (bits_of(i, k) && (k >> 16) == top) ++hist[k & 0xffffu];
  }
  std::uint32_t low = 0;
  while (rank >= hist[low]) rank -= hist[low++];
  const std::uint32_t bits = (top << 16) | low;
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

// A float's bits as an unsigned integer of the same order (for non-negative floats; -0.0f as +0.0f);
// false for a non-finite value (not counted by the medians).
inline bool float_key(float f, std::uint32_t& k) {
  if (!std::isfinite(f)) return false;
  std::memcpy(&k, &f, 4);
  k &= 0x7fffffffu;
  return true;
}

// Below this many values a median copies their keys and selects (select_rank: a 2 KB histogram on the stack); from
// it on, the fixed-size histograms (256 KB radix_median, 2 MB AreaHistogram) cost less than the copy.
// A fresh histogram's pages are faulted in on first touch, which is what a small cloud cannot afford.
constexpr std::size_t kCopyMedianBelow = 1u << 16;

// Median of a small buffer (the upper middle for an even count, as radix_median).
float small_median(std::vector<float>& v) {
  if (v.empty()) return std::numeric_limits<float>::infinity();
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

double median_nn_spacing(const Triangulation& T) {
  float d2 = 0;
  if (T.nn2.size() < kCopyMedianBelow) {
    SlotArray keys(T.nn2.size());  // uninitialised: the first `used` are written
    std::size_t used = 0;
    for (std::size_t v = 0; v < T.nn2.size(); ++v) {
      std::uint32_t k = 0;
      const bool counted = float_key(T.nn2[v], k) & (T.vrep[v] == v);
      keys[used] = k;
      used += counted;
    }
    if (used > 0) {
      const std::uint32_t bits = select_rank(std::span(keys.data(), used), used / 2);
      std::memcpy(&d2, &bits, 4);
    }
  } else {
    d2 = radix_median(T.nn2.size(), [&](std::size_t v, float& f) {
      f = T.nn2[v];
      return T.vrep[v] == v;
    });
  }
  return std::sqrt(static_cast<double>(d2));
}

std::uint32_t select_rank(std::span<std::uint32_t> keys, std::size_t rank) {
  std::size_t n = keys.size();
  if (n <= 64) {
    std::nth_element(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(rank), keys.end());
    return keys[rank];
  }
  // Bits above the highest one in which two keys differ are common to all (areas of one cloud share their
  // exponent): the digits start there, 8 bits each, most significant first; the keys sharing the element's
  // digits so far are compacted to the front.
  const std::uint32_t first = keys[0];
  std::uint32_t differ = 0;
  for (std::size_t i = 0; i < n; ++i) differ |= keys[i] ^ first;
  if (differ == 0) return first;
  const int top = 31 - __builtin_clz(differ);
  std::uint32_t result = top == 31 ? 0 : first & ~((std::uint32_t{2} << top) - 1);
  for (int hi = top; hi >= 0;) {
    const int shift = std::max(hi - 7, 0);
    const std::uint32_t mask = (std::uint32_t{2} << (hi - shift)) - 1;
    // Four counter sets, summed after: keys in a row often share a digit (neighbouring triangles' areas),
    // and one set would chain each increment on the previous one's store.
    std::uint32_t part[4][256] = {};
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4)
      for (std::size_t j = 0; j < 4; ++j) ++part[j][(keys[i + j] >> shift) & mask];
    for (; i < n; ++i) ++part[0][(keys[i] >> shift) & mask];
    std::size_t hist[256];
    for (std::size_t b = 0; b < 256; ++b)
      hist[b] = std::size_t{part[0][b]} + part[1][b] + part[2][b] + part[3][b];  // each part < 2^32 keys
    std::uint32_t d = 0;
    while (rank >= hist[d]) rank -= hist[d++];
    result |= d << shift;
    hi = shift - 1;
    if (hist[d] == n || hi < 0) continue;  // all keys share this digit (or the last digit): nothing to drop
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {  // without a branch: which keys match is as good as random
      const std::uint32_t k = keys[i];
      keys[m] = k;
      m += ((k >> shift) & mask) == d;
    }
    n = m;
  }
  return result;
}

double median_distance(std::span<const float> squared) {
  const float d2 = radix_median(squared.size(), [&](std::size_t i, float& f) {
    f = squared[i];
    return true;
  });
  return std::sqrt(static_cast<double>(d2));
}

AreaHistogram::AreaHistogram() = default;

void AreaHistogram::merge(const AreaHistogram& other) {
  if (other.hist_.empty()) return;
  if (hist_.empty()) hist_.assign(kBuckets, 0);
  for (std::size_t b = 0; b < hist_.size(); ++b) hist_[b] += other.hist_[b];
  used_ += other.used_;
}

std::size_t AreaHistogram::bucket_at(std::size_t rank) const {
  std::size_t b = 0;
  while (rank >= hist_[b]) rank -= hist_[b++];
  return b;
}

double AreaHistogram::spacing_of(std::size_t bucket) {
  const std::uint32_t bits = static_cast<std::uint32_t>(bucket) << 12;
  float area;
  std::memcpy(&area, &bits, 4);
  return std::sqrt(2.0 * static_cast<double>(area));
}

namespace {

constexpr std::uint8_t kGhostClass = 0;  // rclass of a ghost triangle slot
constexpr std::uint8_t kUndecided = kUndecidedClass;

}  // namespace

double triangle_area(const Vec2& a, const Vec2& b, const Vec2& c) { return measure_triangle(a, b, c, 0).area; }

double class_scale(const Triangulation& T) {
  // The box of the inserted vertices is that of all (a merged duplicate has its representative's coordinates).
  const double scale2 =
      (T.xy_max.x - T.xy_min.x) * (T.xy_max.y - T.xy_min.y) / static_cast<double>(std::max<std::size_t>(T.inserted, 1));
  return std::isnormal(scale2) ? scale2 : 0;  // 0: no classes, every decision exact
}

double random_cloud_factor(std::size_t points) {
  const double target = std::log(2.0 * std::max<std::size_t>(points, 1));  // T - ln(1 + T) = ln(2n)
  double t = target + 1;
  for (int i = 0; i < 50; ++i) t = target + std::log1p(t);  // a contraction (derivative 1/(1+T) < 1)
  return std::max(kDefaultAutoFactor, std::sqrt(t / std::numbers::pi) / kPoissonSpacing);
}

double automatic_factor(double q, std::size_t points) {
  if (!(q < kRegularNnRatio)) return kDefaultAutoFactor;  // also NaN (no nearest neighbours measured)
  const double w = std::min(1.0, (kRegularNnRatio - q) / (kRegularNnRatio - kRandomNnRatio));
  return kDefaultAutoFactor + w * (random_cloud_factor(points) - kDefaultAutoFactor);
}

double median_triangle_spacing(const Triangulation& T) { return scan_triangles(T).spacing; }

TriangleScan scan_triangles(const Triangulation& T) { return scan_triangles(T, kCopyMedianBelow); }

namespace {

// emit(t, measure) for each finite triangle slot t of T, in slot order, two triangles at a time
// (measure_pair). kPrefetch: the three vertices of a triangle are scattered over the coordinate array;
// fetching those of a few triangles ahead overlaps the cache misses that otherwise dominate this pass (a
// small cloud's coordinates stay in the cache).
template <bool kPrefetch, class Emit>
void measure_finite(const Triangulation& T, double scale2, Emit emit) {
  constexpr std::size_t kAhead = 8, kNoSlot = ~std::size_t{0};
  const std::size_t slots = T.slots();
  const std::uint32_t* tri = T.tri.data();
  const Vec2* xy = T.xy.data();
  const std::uint32_t ghost = T.ghost;
  std::size_t held = kNoSlot;  // a finite triangle waiting for a second one
  for (std::size_t t = 0; t < slots; ++t) {
    if constexpr (kPrefetch) {
      if (t + kAhead < slots)
        for (int i = 0; i < 3; ++i)
          if (const std::uint32_t w = tri[3 * (t + kAhead) + i]; w != ghost) __builtin_prefetch(&xy[w]);
    }
    const std::uint32_t* v = tri + 3 * t;
    if (std::max(std::max(v[0], v[1]), v[2]) == ghost) continue;  // the ghost is the largest vertex id
    if (held == kNoSlot) {
      held = t;
      continue;
    }
    const std::uint32_t* u = tri + 3 * held;
    const Vec2* p0[3] = {&xy[u[0]], &xy[u[1]], &xy[u[2]]};
    const Vec2* p1[3] = {&xy[v[0]], &xy[v[1]], &xy[v[2]]};
    TriangleMeasure m0, m1;
    measure_pair(p0, p1, scale2, m0, m1);
    emit(held, m0);
    emit(t, m1);
    held = kNoSlot;
  }
  if (held != kNoSlot) {
    const std::uint32_t* u = tri + 3 * held;
    emit(held, measure_triangle(xy[u[0]], xy[u[1]], xy[u[2]], scale2));
  }
}

}  // namespace

TriangleScan scan_triangles(const Triangulation& T, std::size_t histogram_from) {
  TriangleScan scan;
  scan.scale2 = class_scale(T);
  const std::size_t slots = T.slots();
  scan.rclass.assign(slots, kGhostClass);
  std::uint8_t* rclass = scan.rclass.data();
  // The median area's bucket: from the 2 MB histogram, or (small clouds) by selection among the buckets
  // of all areas. Prefetching pays from kPrefetchFrom triangles (512 KB of points) on.
  constexpr std::size_t kPrefetchFrom = 65536;
  if (slots >= histogram_from) {
    AreaHistogram median;
    auto emit = [&](std::size_t t, const TriangleMeasure& m) {
      median.add(m.area);
      rclass[t] = m.rclass;
    };
    if (slots >= kPrefetchFrom) measure_finite<true>(T, scan.scale2, emit);
    else
      measure_finite<false>(T, scan.scale2, emit);
    scan.spacing = median.spacing();
    return scan;
  }
  SlotArray buckets(slots);  // uninitialised: the first `used` are written
  std::size_t used = 0;
  measure_finite<false>(T, scan.scale2, [&](std::size_t t, const TriangleMeasure& m) {
    std::uint32_t b = 0;
    const bool finite = AreaHistogram::bucket_of(m.area, b);
    buckets[used] = b;
    used += finite;
    rclass[t] = m.rclass;
  });
  if (used > 0) scan.spacing = AreaHistogram::spacing_of(select_rank(std::span(buckets.data(), used), used / 2));
  return scan;
}

std::vector<float> local_spacing(const Triangulation& T) {
  const std::size_t n = T.xy.size(), slots = T.slots();
  constexpr std::uint32_t kNone = 0xffffffffu;
  // The areas once, in slot order (the fan walks below then read 4 bytes per triangle, not 3 points).
  std::vector<float> area(slots, std::numeric_limits<float>::infinity());
  for (std::size_t t = 0; t < slots; ++t)
    if (!T.is_ghost(t)) {
      area[t] = static_cast<float>(
          measure_triangle(T.xy[T.tri[3 * t]], T.xy[T.tri[3 * t + 1]], T.xy[T.tri[3 * t + 2]], 0).area);
    }
  std::vector<std::uint32_t> out(n, kNone);  // one half-edge leaving each vertex
  for (std::uint32_t h = 0; h < T.tri.size(); ++h)
    if (T.tri[h] != T.ghost) out[T.tri[h]] = h;
  // Visits the half-edges leaving v, once around its fan.
  auto around = [&](std::uint32_t v, auto&& visit) {
    const std::uint32_t h0 = out[v];
    std::uint32_t h = h0;
    do {
      visit(h);
      h = T.twin[Triangulation::prev(h)];
    } while (h != h0);
  };
  std::vector<float> fan_median(n, std::numeric_limits<float>::infinity()), buf;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (out[v] == kNone) continue;
    buf.clear();
    around(v, [&](std::uint32_t h) {
      if (std::isfinite(area[h / 3])) buf.push_back(area[h / 3]);
    });
    fan_median[v] = small_median(buf);
  }
  std::vector<float>().swap(area);
  std::vector<float> spacing(n, 0);
  for (std::uint32_t v = 0; v < n; ++v) {
    if (out[v] == kNone) continue;
    buf.assign(1, fan_median[v]);
    around(v, [&](std::uint32_t h) {
      const std::uint32_t u = T.tri[Triangulation::next(h)];
      if (u != T.ghost) buf.push_back(fan_median[u]);
    });
    spacing[v] = static_cast<float>(std::sqrt(2.0 * static_cast<double>(small_median(buf))));
  }
  return spacing;
}

double local_radius(std::span<const float> s, double k, std::uint32_t u, std::uint32_t v, std::uint32_t w) {
  const float a = s[u], b = s[v], c = s[w];
  const float mid = std::max(std::min(a, b), std::min(std::max(a, b), c));
  return k * static_cast<double>(mid);
}

namespace {

// What the classification knows of a triangle slot.
enum class Triangle : std::uint8_t {
  Ghost,       // a ghost triangle (outside by definition)
  Small,       // finite, circumradius r <= R_t: in the shape
  Big,         // finite, r > R_t (decided exactly)
  BigOutside,  // big and reached from a ghost through big triangles (outer_only's BFS)
};

// inside[] as documented at classify_alpha, from state(t) (Ghost, Small or Big).
template <class State>
std::vector<std::uint8_t> classify_with(const Triangulation& T, bool outer_only, State state) {
  const std::size_t slots = T.slots();
  std::vector<std::uint8_t> inside(slots);
  if (!outer_only) {
    for (std::size_t t = 0; t < slots; ++t) inside[t] = state(t) == Triangle::Small;
    return inside;
  }
  std::vector<Triangle> st(slots);
  for (std::size_t t = 0; t < slots; ++t) st[t] = state(t);
  // The paper's BFS: from every ghost triangle, through big triangles only; those reached are outside.
  std::vector<std::uint32_t> stack;
  for (std::size_t t = 0; t < slots; ++t)
    if (st[t] == Triangle::Ghost) stack.push_back(static_cast<std::uint32_t>(t));
  while (!stack.empty()) {
    const std::uint32_t t = stack.back();
    stack.pop_back();
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t nb = T.twin[3 * t + i] / 3;
      if (st[nb] == Triangle::Big) {
        st[nb] = Triangle::BigOutside;
        stack.push_back(nb);
      }
    }
  }
  for (std::size_t t = 0; t < slots; ++t) inside[t] = st[t] == Triangle::Small || st[t] == Triangle::Big;
  return inside;
}

bool bigger_than(const Triangulation& T, std::size_t t, double R) {
  const Vec2 &a = T.xy[T.tri[3 * t]], &b = T.xy[T.tri[3 * t + 1]], &c = T.xy[T.tri[3 * t + 2]];
  return pred::circumradius_vs(a.x, a.y, b.x, b.y, c.x, c.y, R) > 0;
}

}  // namespace

std::vector<std::uint8_t> classify_alpha(const Triangulation& T, double R, bool outer_only) {
  return classify_with(T, outer_only, [&](std::size_t t) {
    if (T.is_ghost(t)) return Triangle::Ghost;
    return bigger_than(T, t, R) ? Triangle::Big : Triangle::Small;
  });
}

std::vector<std::uint8_t> classify_alpha(const Triangulation& T, double R, bool outer_only, const TriangleScan& scan) {
  // A triangle's estimated class is within 1 of its true class (estimate accurate to 2e-6, classes of
  // 3 % or more), and so is R's: 3 classes apart decide. Near the clamped ends, all exact.
  const int cR = std::isnormal(scan.scale2) ? r2_class(R * R / scan.scale2) : 0;
  const bool usable = cR >= 4 && cR <= 250;
  if (usable && !outer_only) {
    // The classes decide nearly every triangle: a pass without branches (vectorised), then the exact
    // predicate for those within 2 classes of R's or undecided (a few percent). Ghosts (class 0) are out.
    const std::size_t slots = T.slots();
    const std::uint8_t* rc = scan.rclass.data();
    std::vector<std::uint8_t> inside(slots);
    for (std::size_t t = 0; t < slots; ++t) inside[t] = (rc[t] != kGhostClass) & (rc[t] + 3 <= cR);
    // Near R: classes cR - 2 .. cR + 2 (c - (cR - 2) < 5 as a byte; ghosts' 0 wraps far above), 16 at a time.
    using bytes16 = std::uint8_t __attribute__((vector_size(16)));
    using chars16 = char __attribute__((vector_size(16)));
    const auto lo = static_cast<std::uint8_t>(cR - 2);
    auto near_r = [&](std::uint8_t c) { return static_cast<std::uint8_t>(c - lo) < 5 || c == kUndecided; };
    std::size_t t = 0;
    for (; t + 16 <= slots; t += 16) {
      bytes16 c;
      std::memcpy(&c, rc + t, 16);
      const bytes16 lo16 = bytes16{} + lo;
      const chars16 near = reinterpret_cast<chars16>(((c - lo16) < 5) | (c == kUndecided));
      for (unsigned m = static_cast<unsigned>(__builtin_ia32_pmovmskb128(near)); m != 0; m &= m - 1) {
        const std::size_t u = t + static_cast<std::size_t>(__builtin_ctz(m));
        inside[u] = !bigger_than(T, u, R);
      }
    }
    for (; t < slots; ++t)
      if (near_r(rc[t])) inside[t] = !bigger_than(T, t, R);
    return inside;
  }
  // The ghost triangles are those of kGhostClass: this pass reads the classes only, not the triangles.
  return classify_with(T, outer_only, [&](std::size_t t) {
    const int c = scan.rclass[t];
    if (c == kGhostClass) return Triangle::Ghost;
    if (usable && c != kUndecided) {
      if (c + 3 <= cR) return Triangle::Small;
      if (c >= cR + 3) return Triangle::Big;
    }
    return bigger_than(T, t, R) ? Triangle::Big : Triangle::Small;
  });
}

std::vector<std::uint8_t> classify_alpha_local(const Triangulation& T, std::span<const float> vertex_spacing, double k,
                                               bool outer_only) {
  return classify_with(T, outer_only, [&](std::size_t t) {
    if (T.is_ghost(t)) return Triangle::Ghost;
    const double R = local_radius(vertex_spacing, k, T.tri[3 * t], T.tri[3 * t + 1], T.tri[3 * t + 2]);
    return bigger_than(T, t, R) ? Triangle::Big : Triangle::Small;
  });
}

namespace {

// The loop through the free edges e[0..m) (a chain: each one's head is the next one's tail), starting at
// its smallest input index.
Loop make_loop(const std::vector<FreeEdge>& edges, const std::uint32_t* e, std::size_t m) {
  Loop L;
  std::size_t start = 0;
  for (std::size_t k = 1; k < m; ++k)
    if (edges[e[k]].from < edges[e[start]].from) start = k;
  // Area and length in input coordinates relative to the loop's first point: exact for integer-valued
  // inputs, and no cancellation against a far origin.
  const Vec2 o = edges[e[start]].from_xy;
  double twice_area = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const FreeEdge &ei = edges[e[(start + k) % m]], &ej = edges[e[(start + k + 1) % m]];
    const Vec2 pi = ei.from_xy, pj = ej.from_xy;
    L.point_index.push_back(ei.from);
    L.points.push_back(pi);
    const double xi = pi.x - o.x, yi = pi.y - o.y, xj = pj.x - o.x, yj = pj.y - o.y;
    twice_area += xi * yj - xj * yi;
    L.perimeter += std::hypot(xj - xi, yj - yi);
  }
  L.hole = twice_area < 0;
  L.area = std::fabs(twice_area) / 2;
  return L;
}

// std::lower_bound's position among `count` sorted elements, below(k) telling whether element k is below
// the key, with no branch on the comparisons: they are as good as random (two searches an edge).
template <class Below>
std::size_t lower_index(std::size_t count, Below below) {
  if (count == 0) return 0;
  std::size_t base = 0;
  for (std::size_t len = count; len > 1;) {  // the answer stays within [base, base + len]
    const std::size_t half = len / 2;
    base += below(base + half) ? half : 0;
    len -= half;
  }
  return base + below(base);
}

// Outer loops first, then holes, each group by decreasing area, ties by the point indices (a total
// order: the result does not depend on the order the loops were traced in).
void sort_loops(std::vector<Loop>& loops) {
  std::sort(loops.begin(), loops.end(), [](const Loop& a, const Loop& b) {
    if (a.hole != b.hole) return !a.hole;
    if (a.area != b.area) return a.area > b.area;
    return a.point_index < b.point_index;
  });
}

}  // namespace

std::vector<Loop> extract_loops(const Triangulation& T, const std::vector<std::uint8_t>& inside,
                                std::span<const Vec2> input) {
  return chain_loops(free_edges(T, inside, input, [](std::uint32_t) { return true; }));
}

std::vector<Loop> chain_loops(std::vector<FreeEdge> edges) {
  auto key_less = [](const FreeEdge& a, const FreeEdge& b) {
    return a.from < b.from || (a.from == b.from && a.to < b.to);
  };
  std::sort(edges.begin(), edges.end(), key_less);
  // The edge a -> b, by binary search in the sorted list (its length is the outline's, not the cloud's).
  auto find = [&](std::uint32_t a, std::uint32_t b) {
    auto key = [](std::uint32_t from, std::uint32_t to) { return (std::uint64_t{from} << 32) | to; };
    const std::size_t i =
        lower_index(edges.size(), [&](std::size_t k) { return key(edges[k].from, edges[k].to) < key(a, b); });
    if (i == edges.size() || edges[i].from != a || edges[i].to != b)
      throw OutlineError("internal error: free edge " + std::to_string(a) + " -> " + std::to_string(b) + " missing");
    return i;
  };
  std::vector<std::uint32_t> bverts;  // the boundary vertices, for the chain position of each
  for (const FreeEdge& e : edges) bverts.push_back(e.from);
  bverts.erase(std::unique(bverts.begin(), bverts.end()), bverts.end());  // sorted already
  auto vert_slot = [&](std::uint32_t v) {
    return lower_index(bverts.size(), [&](std::size_t k) { return bverts[k] < v; });
  };
  std::vector<Loop> loops;
  std::vector<std::uint8_t> used(edges.size(), 0);
  std::vector<std::int32_t> pos(bverts.size(), -1);  // position of a vertex in the chain being traced
  std::vector<std::uint32_t> path;                   // edges of the chain
  for (std::size_t e0 = 0; e0 < edges.size(); ++e0) {
    if (used[e0]) continue;
    path.clear();
    std::size_t e = e0;
    do {
      used[e] = 1;
      const std::size_t vs = vert_slot(edges[e].from);
      if (pos[vs] >= 0) {  // the chain came back to this vertex: what lies between is a closed loop on its own
        const std::size_t p = static_cast<std::size_t>(pos[vs]);
        loops.push_back(make_loop(edges, path.data() + p, path.size() - p));
        for (std::size_t k = p; k < path.size(); ++k) pos[vert_slot(edges[path[k]].from)] = -1;
        path.resize(p);
      }
      pos[vs] = static_cast<std::int32_t>(path.size());
      path.push_back(static_cast<std::uint32_t>(e));
      e = find(edges[e].to, edges[e].next);
    } while (e != e0);
    loops.push_back(make_loop(edges, path.data(), path.size()));
    for (std::uint32_t k : path) pos[vert_slot(edges[k].from)] = -1;
  }
  sort_loops(loops);
  return loops;
}

}  // namespace hg::outline
