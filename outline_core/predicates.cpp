// Exact fallbacks of the predicates: floating-point expansions (a value is the exact sum of doubles of
// increasing magnitude that do not overlap). Implemented from Shewchuk, "Adaptive Precision
// Floating-Point Arithmetic and Fast Robust Geometric Predicates" (1997), section 2.
// One kernel for all three predicates: expansions in fixed-capacity buffers, each capacity the worst case
// of the operations that fill it (checked at compile time), so the exact path never overflows and, on the
// stack, never allocates (it runs often on camera grids: near-cocircular cells everywhere).
#include "predicates.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>

namespace hg::outline::pred {
namespace {

// ---- error-free transforms ----

// a + b = x + y exactly.
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}

inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double bv = a - x;
  const double av = x + bv;
  y = (a - av) + (bv - b);
}

// a = hi + lo with both halves of at most 26 significant bits (Dekker / Veltkamp).
inline void split(double a, double& hi, double& lo) {
  constexpr double kSplitter = 134217729.0;  // 2^27 + 1
  const double c = kSplitter * a;
  const double big = c - a;
  hi = c - big;
  lo = a - hi;
}

// a * b = x + y exactly.
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  const double err = x - ah * bh - al * bh - ah * bl;
  y = al * bl - err;
}

// ---- expansions ----

// Room for N components: c[0..n) by increasing magnitude, non-overlapping, no zeros; the value is their
// exact sum (0 when n == 0).
template <int N>
struct Expansion {
  double c[N];
  int n = 0;
  void push(double v) {
    if (v != 0) c[n++] = v;
  }
  double sign() const { return n == 0 ? 0.0 : c[n - 1]; }  // the largest component carries the sign
};

// h = e + f: merge by magnitude, then a chain of two-sums (the "linear expansion sum"), zeros dropped;
// returns h's length (<= en + fn). h may start below e in the same buffer when the write position never
// passes the next unread component of e (add_in_place); f never overlaps h.
int merge_sum(const double* e, int en, const double* f, int fn, double* h) {
  if (en == 0 || fn == 0) {
    const double* only = en ? e : f;
    const int n = en ? en : fn;
    for (int k = 0; k < n; ++k) h[k] = only[k];  // forward: h never starts above `only`
    return n;
  }
  int i = 0, j = 0, hn = 0;
  double q = std::fabs(e[0]) < std::fabs(f[0]) ? e[i++] : f[j++];
  while (i < en || j < fn) {
    const double g = (j >= fn || (i < en && std::fabs(e[i]) < std::fabs(f[j]))) ? e[i++] : f[j++];
    double s, t;
    two_sum(q, g, s, t);
    if (t != 0) h[hn++] = t;
    q = s;
  }
  if (q != 0) h[hn++] = q;
  return hn;
}

// h = e * b (at most 2 en components).
int scale(const double* e, int en, double b, double* h) {
  if (en == 0 || b == 0) return 0;
  int hn = 0;
  double q, t;
  two_product(e[0], b, q, t);
  if (t != 0) h[hn++] = t;
  for (int i = 1; i < en; ++i) {
    double p1, p0, s;
    two_product(e[i], b, p1, p0);
    two_sum(q, p0, s, t);
    if (t != 0) h[hn++] = t;
    two_sum(p1, s, q, t);
    if (t != 0) h[hn++] = t;
  }
  if (q != 0) h[hn++] = q;
  return hn;
}

// h += f in h's own buffer (the caller guarantees h.n + fn <= N): h's components move to the top of the
// buffer and are merged down from the bottom. The write position stays below the next unread component
// (it trails the components read by at most the fn of f), so nothing unread is overwritten.
template <int N>
void add_in_place(Expansion<N>& h, const double* f, int fn) {
  double* top = h.c + (N - h.n);
  for (int k = h.n - 1; k >= 0; --k) top[k] = h.c[k];  // backward: the ranges may overlap
  h.n = merge_sum(top, h.n, f, fn, h.c);
}

template <int A, int B, int H>
void sum(const Expansion<A>& e, const Expansion<B>& f, Expansion<H>& h) {
  static_assert(H >= A + B);
  h.n = merge_sum(e.c, e.n, f.c, f.n, h.c);
}

// h = e * f: the sum over f's components of e scaled by each.
template <int A, int B, int H>
void mul(const Expansion<A>& e, const Expansion<B>& f, Expansion<H>& h) {
  static_assert(H >= 2 * A * B);
  h.n = 0;
  if (f.n == 0) return;
  h.n = scale(e.c, e.n, f.c[0], h.c);
  double part[2 * A];
  for (int k = 1; k < f.n; ++k) {
    const int pn = scale(e.c, e.n, f.c[k], part);
    add_in_place(h, part, pn);  // h.n + pn <= 2 A (k + 1) <= H
  }
}

template <int N>
void negate(Expansion<N>& e) {
  for (int k = 0; k < e.n; ++k) e.c[k] = -e.c[k];
}

// a - b in K components: K = 2 always; K = 1 only when the difference is exact (difference_is_exact).
template <int K>
Expansion<K> diff(double a, double b) {
  static_assert(K == 1 || K == 2);
  double x, y;
  two_diff(a, b, x, y);
  Expansion<K> e;
  if constexpr (K == 2) e.push(y);
  e.push(x);
  return e;
}

// ux * vy - uy * vx.
template <int K>
Expansion<4 * K * K> cross(const Expansion<K>& ux, const Expansion<K>& uy, const Expansion<K>& vx,
                           const Expansion<K>& vy) {
  Expansion<2 * K * K> l, r;
  mul(ux, vy, l);
  mul(uy, vx, r);
  negate(r);
  Expansion<4 * K * K> h;
  sum(l, r, h);
  return h;
}

// ux^2 + uy^2.
template <int K>
Expansion<4 * K * K> square_norm(const Expansion<K>& ux, const Expansion<K>& uy) {
  Expansion<2 * K * K> xx, yy;
  mul(ux, ux, xx);
  mul(uy, uy, yy);
  Expansion<4 * K * K> h;
  sum(xx, yy, h);
  return h;
}

// ---- few-bit integer path ----

// "Few bits": nonzero doubles d_k that are all integer multiples of 2^s and below 2^B in magnitude with
// B - s <= 26. Then a product of two is an integer below 2^52 units of 2^2s and the sum or difference of
// two products is below 2^53 units: all exact doubles. Coordinate differences of nearby camera points
// (float32 data, translated to a rounded origin) are like this, and those are the near-degenerate tests
// that reach the exact path (a noise-free grid makes every cell nearly cocircular), so this cheap check
// settles most of them. Limits on s and B keep every product of four far from under/overflow.
inline bool few_bits(const double* d, int count, int& lo) {
  lo = 4096;
  int hi = -4096;
  for (int k = 0; k < count; ++k) {
    std::uint64_t bits;
    std::memcpy(&bits, &d[k], 8);
    const int e = static_cast<int>((bits >> 52) & 0x7ff);
    if (e == 0) {
      if ((bits << 1) == 0) continue;  // zero
      return false;                    // subnormal
    }
    const std::uint64_t mant = (bits & ((std::uint64_t{1} << 52) - 1)) | (std::uint64_t{1} << 52);
    lo = std::min(lo, e - 1075 + __builtin_ctzll(mant));  // value = mant 2^(e - 1075)
    hi = std::max(hi, e - 1022);                          // |value| < 2^(e - 1022)
  }
  return hi - lo <= 26 && lo >= -240 && hi <= 240;
}

// The incircle determinant of exact few-bit differences d = (adx, ady, bdx, bdy, cdx, cdy), lo their
// lowest set bit (few_bits). In units of 2^lo the differences are integers below 2^26 (scaling by a power
// of two is exact): the lifts and cross products are integers below 2^53, their products below 2^106, the
// sum of three below 2^108: exact in 128-bit integers.
double incircle_integer(const double (&d)[6], int lo) {
  if (lo > 240) return 0;  // every difference is zero (few_bits leaves lo unset): a, b, c, d coincide
  std::uint64_t scale_bits = static_cast<std::uint64_t>(1023 - lo) << 52;  // 2^-lo, lo in [-240, 240]
  double unit;
  std::memcpy(&unit, &scale_bits, 8);
  std::int64_t q[6];
  for (int k = 0; k < 6; ++k) q[k] = static_cast<std::int64_t>(d[k] * unit);
  const std::int64_t L[3] = {q[0] * q[0] + q[1] * q[1], q[2] * q[2] + q[3] * q[3], q[4] * q[4] + q[5] * q[5]};
  const std::int64_t C[3] = {q[2] * q[5] - q[4] * q[3], q[4] * q[1] - q[0] * q[5], q[0] * q[3] - q[2] * q[1]};
  const __int128 det =
      static_cast<__int128>(L[0]) * C[0] + static_cast<__int128>(L[1]) * C[1] + static_cast<__int128>(L[2]) * C[2];
  return det > 0 ? 1.0 : (det < 0 ? -1.0 : 0.0);
}

// ---- the determinants as expansions (K components per coordinate difference) ----

// det = sum over cyclic (a, b, c) of (adx^2 + ady^2) (bdx cdy - cdx bdy). Apart (noinline) from
// incircle_exact: the K = 2 frame is large (36 kB).
template <int K>
[[gnu::noinline]] double incircle_expansion(double ax, double ay, double bx, double by, double cx, double cy, double dx,
                                            double dy) {
  const Expansion<K> adx = diff<K>(ax, dx), ady = diff<K>(ay, dy);
  const Expansion<K> bdx = diff<K>(bx, dx), bdy = diff<K>(by, dy);
  const Expansion<K> cdx = diff<K>(cx, dx), cdy = diff<K>(cy, dy);
  constexpr int T = 2 * (4 * K * K) * (4 * K * K);  // one term: a cross product times a lift
  Expansion<T> ta, tb, tc;
  mul(cross(bdx, bdy, cdx, cdy), square_norm(adx, ady), ta);
  mul(cross(cdx, cdy, adx, ady), square_norm(bdx, bdy), tb);
  mul(cross(adx, ady, bdx, bdy), square_norm(cdx, cdy), tc);
  Expansion<2 * T> s1;
  sum(ta, tb, s1);
  Expansion<3 * T> s2;
  sum(s1, tc, s2);
  return s2.sign();
}

// The expansions of sign(|ab|^2 |bc|^2 |ca|^2 - 4 R^2 D^2), D the orient2d determinant of a, b, c.
template <int K>
struct CircumradiusWork {
  static constexpr int L = 4 * K * K;  // a squared length, and D
  static constexpr int N = 2 * (2 * L * L) * L;
  static constexpr int M = 2 * (2 * L * L) * 2;
  Expansion<2 * L * L> ab_bc, d2;
  Expansion<N> product;  // |ab|^2 |bc|^2 |ca|^2
  Expansion<M> m;        // 4 R^2 D^2
  Expansion<N + M> s;
};

template <int K>
int circumradius_expansion(double ax, double ay, double bx, double by, double cx, double cy, double R,
                           CircumradiusWork<K>& w) {
  const Expansion<4 * K* K> ab = square_norm(diff<K>(ax, bx), diff<K>(ay, by));
  const Expansion<4 * K* K> bc = square_norm(diff<K>(bx, cx), diff<K>(by, cy));
  const Expansion<4 * K* K> ca = square_norm(diff<K>(cx, ax), diff<K>(cy, ay));
  mul(ab, bc, w.ab_bc);
  mul(w.ab_bc, ca, w.product);
  const Expansion<4 * K* K> d = cross(diff<K>(ax, cx), diff<K>(ay, cy), diff<K>(bx, cx), diff<K>(by, cy));
  mul(d, d, w.d2);
  double rh, rl;
  two_product(R, R, rh, rl);
  Expansion<2> four_r2;
  four_r2.push(4 * rl);  // times 4 is exact
  four_r2.push(4 * rh);
  mul(w.d2, four_r2, w.m);
  negate(w.m);
  sum(w.product, w.m, w.s);
  const double v = w.s.sign();
  return v > 0 ? 1 : (v < 0 ? -1 : 0);
}

}  // namespace

double orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  if (difference_is_exact(ax, cx) && difference_is_exact(ay, cy) && difference_is_exact(bx, cx) &&
      difference_is_exact(by, cy)) {
    const double d[4] = {ax - cx, ay - cy, bx - cx, by - cy};
    int lo;
    if (few_bits(d, 4, lo)) return d[0] * d[3] - d[1] * d[2];  // exact (collinear rows of a grid: 0)
    return cross(diff<1>(ax, cx), diff<1>(ay, cy), diff<1>(bx, cx), diff<1>(by, cy)).sign();
  }
  return cross(diff<2>(ax, cx), diff<2>(ay, cy), diff<2>(bx, cx), diff<2>(by, cy)).sign();
}

double incircle_exact(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy) {
  if (difference_is_exact(ax, dx) && difference_is_exact(ay, dy) && difference_is_exact(bx, dx) &&
      difference_is_exact(by, dy) && difference_is_exact(cx, dx) && difference_is_exact(cy, dy)) {
    const double d[6] = {ax - dx, ay - dy, bx - dx, by - dy, cx - dx, cy - dy};
    int lo;
    if (few_bits(d, 6, lo)) return incircle_integer(d, lo);
    return incircle_expansion<1>(ax, ay, bx, by, cx, cy, dx, dy);
  }
  return incircle_expansion<2>(ax, ay, bx, by, cx, cy, dx, dy);
}

int circumradius_vs_exact(double ax, double ay, double bx, double by, double cx, double cy, double R) {
  if (difference_is_exact(ax, bx) && difference_is_exact(ay, by) && difference_is_exact(bx, cx) &&
      difference_is_exact(by, cy) && difference_is_exact(cx, ax) && difference_is_exact(cy, ay)) {
    CircumradiusWork<1> w;  // 6.6 kB: on the stack
    return circumradius_expansion(ax, ay, bx, by, cx, cy, R, w);
  }
  // Inexact differences: the worst-case buffers total 300 kB, on the heap (rare: the filter decides
  // almost every triangle, and camera points have exact differences).
  const auto w = std::make_unique_for_overwrite<CircumradiusWork<2>>();
  return circumradius_expansion(ax, ay, bx, by, cx, cy, R, *w);
}

}  // namespace hg::outline::pred
