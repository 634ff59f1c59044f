// Exact fallbacks of the predicates: floating-point expansions (a value is the exact sum of doubles of
// increasing magnitude that do not overlap). Implemented from Shewchuk, "Adaptive Precision
// Floating-Point Arithmetic and Fast Robust Geometric Predicates" (1997), section 2.
#include "predicates.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace hg::outline::pred {
namespace {

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

using Expansion = std::vector<double>;  // components by increasing magnitude, no zeros

// h = e + f. Merge by magnitude, then a chain of two-sums (the "linear expansion sum"), zeros dropped.
void sum(const Expansion& e, const Expansion& f, Expansion& h) {
  h.clear();
  if (e.empty()) {
    h = f;
    return;
  }
  if (f.empty()) {
    h = e;
    return;
  }
  Expansion g;
  g.reserve(e.size() + f.size());
  std::size_t i = 0, j = 0;
  while (i < e.size() && j < f.size()) {
    if (std::fabs(e[i]) < std::fabs(f[j])) g.push_back(e[i++]);
    else
      g.push_back(f[j++]);
  }
  while (i < e.size()) g.push_back(e[i++]);
  while (j < f.size()) g.push_back(f[j++]);
  double q = g[0];
  for (std::size_t k = 1; k < g.size(); ++k) {
    double s, t;
    two_sum(q, g[k], s, t);
    if (t != 0) h.push_back(t);
    q = s;
  }
  if (q != 0 || h.empty()) h.push_back(q);
  if (h.size() == 1 && h[0] == 0) h.clear();
}

// h = e * b.
void scale(const Expansion& e, double b, Expansion& h) {
  h.clear();
  if (e.empty() || b == 0) return;
  double q, t;
  two_product(e[0], b, q, t);
  if (t != 0) h.push_back(t);
  for (std::size_t i = 1; i < e.size(); ++i) {
    double p1, p0, s;
    two_product(e[i], b, p1, p0);
    two_sum(q, p0, s, t);
    if (t != 0) h.push_back(t);
    two_sum(p1, s, q, t);
    if (t != 0) h.push_back(t);
  }
  if (q != 0) h.push_back(q);
}

// h = e * f, as the sum over f's components of e scaled by each.
void mul(const Expansion& e, const Expansion& f, Expansion& h) {
  h.clear();
  Expansion part, acc;
  for (double c : f) {
    scale(e, c, part);
    sum(h, part, acc);
    h.swap(acc);
  }
}

void negate(Expansion& e) {
  for (double& c : e) c = -c;
}

Expansion diff(double a, double b) {
  double x, y;
  two_diff(a, b, x, y);
  Expansion e;
  if (y != 0) e.push_back(y);
  if (x != 0) e.push_back(x);
  return e;
}

// The most significant component carries the sign.
double sign_of(const Expansion& e) { return e.empty() ? 0.0 : e.back(); }

// ax*by - ay*bx exactly, for expansions.
Expansion cross(const Expansion& ax, const Expansion& ay, const Expansion& bx, const Expansion& by) {
  Expansion l, r, h;
  mul(ax, by, l);
  mul(ay, bx, r);
  negate(r);
  sum(l, r, h);
  return h;
}

Expansion square_norm(const Expansion& x, const Expansion& y) {
  Expansion xx, yy, h;
  mul(x, x, xx);
  mul(y, y, yy);
  sum(xx, yy, h);
  return h;
}

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

// Fixed-capacity expansions on the stack for orient2d and incircle: the exact path runs often on
// camera grids (near-cocircular cells everywhere) and must not allocate. Same algorithms as above.
template <int N>
struct Fixed {
  double c[N];
  int n = 0;
};

// h = e + f (h must hold e.n + f.n components and not alias e or f).
inline int sum_raw(const double* e, int en, const double* f, int fn, double* h) {
  if (en == 0) {
    for (int k = 0; k < fn; ++k) h[k] = f[k];
    return fn;
  }
  if (fn == 0) {
    for (int k = 0; k < en; ++k) h[k] = e[k];
    return en;
  }
  // Merge by magnitude on the fly, then the chain of two-sums.
  int i = 0, j = 0, hn = 0;
  double q = (std::fabs(e[0]) < std::fabs(f[0])) ? e[i++] : f[j++];
  while (i < en || j < fn) {
    const double g = (j >= fn || (i < en && std::fabs(e[i]) < std::fabs(f[j]))) ? e[i++] : f[j++];
    double s, t;
    two_sum(q, g, s, t);
    if (t != 0) h[hn++] = t;
    q = s;
  }
  if (q != 0 || hn == 0) h[hn++] = q;
  if (hn == 1 && h[0] == 0) hn = 0;
  return hn;
}

inline int scale_raw(const double* e, int en, double b, double* h) {
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

template <int A, int B, int H>
void fsum(const Fixed<A>& e, const Fixed<B>& f, Fixed<H>& h) {
  static_assert(H >= A + B);
  h.n = sum_raw(e.c, e.n, f.c, f.n, h.c);
}

// h = e * f: sum over f's components of e scaled by each.
template <int A, int B, int H>
void fmul(const Fixed<A>& e, const Fixed<B>& f, Fixed<H>& h) {
  static_assert(H >= 2 * A * B);
  double part[2 * A];
  double acc[H];
  h.n = 0;
  for (int k = 0; k < f.n; ++k) {
    const int pn = scale_raw(e.c, e.n, f.c[k], part);
    const int an = sum_raw(h.c, h.n, part, pn, acc);
    for (int i = 0; i < an; ++i) h.c[i] = acc[i];
    h.n = an;
  }
}

inline Fixed<2> fdiff(double a, double b) {
  Fixed<2> e;
  double x, y;
  two_diff(a, b, x, y);
  if (y != 0) e.c[e.n++] = y;
  if (x != 0) e.c[e.n++] = x;
  return e;
}

template <int N>
double fsign(const Fixed<N>& e) {
  return e.n == 0 ? 0.0 : e.c[e.n - 1];
}

// ax*by - ay*bx for 2-component inputs: at most 16 components.
Fixed<16> fcross(const Fixed<2>& ax, const Fixed<2>& ay, const Fixed<2>& bx, const Fixed<2>& by) {
  Fixed<8> l, r;
  fmul(ax, by, l);
  fmul(ay, bx, r);
  for (int k = 0; k < r.n; ++k) r.c[k] = -r.c[k];
  Fixed<16> h;
  fsum(l, r, h);
  return h;
}

Fixed<16> fsquare_norm(const Fixed<2>& x, const Fixed<2>& y) {
  Fixed<8> xx, yy;
  fmul(x, x, xx);
  fmul(y, y, yy);
  Fixed<16> h;
  fsum(xx, yy, h);
  return h;
}

}  // namespace

double orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  const Fixed<2> acx = fdiff(ax, cx), acy = fdiff(ay, cy), bcx = fdiff(bx, cx), bcy = fdiff(by, cy);
  if (acx.n <= 1 && acy.n <= 1 && bcx.n <= 1 && bcy.n <= 1) {
    const double d[4] = {ax - cx, ay - cy, bx - cx, by - cy};  // exact
    int lo;
    if (few_bits(d, 4, lo)) return d[0] * d[3] - d[1] * d[2];  // exact (collinear rows of a grid: 0)
  }
  return fsign(fcross(fdiff(ax, cx), fdiff(ay, cy), fdiff(bx, cx), fdiff(by, cy)));
}

namespace {

[[gnu::noinline]] double incircle_general(double ax, double ay, double bx, double by, double cx, double cy, double dx,
                                          double dy) {
  const Fixed<2> adx = fdiff(ax, dx), ady = fdiff(ay, dy);
  const Fixed<2> bdx = fdiff(bx, dx), bdy = fdiff(by, dy);
  const Fixed<2> cdx = fdiff(cx, dx), cdy = fdiff(cy, dy);
  if (adx.n <= 1 && ady.n <= 1 && bdx.n <= 1 && bdy.n <= 1 && cdx.n <= 1 && cdy.n <= 1) {
    // Every difference is a single double (the usual case: nearby points). Then
    // det = sum over cyclic (a, b, c) of (adx^2 + ady^2) (bdx cdy - cdx bdy), each cross product an exact
    // 4-component expansion, scaled twice by adx and twice by ady: at most 32 components per term.
    const double ax1 = adx.n ? adx.c[0] : 0.0, ay1 = ady.n ? ady.c[0] : 0.0;
    const double bx1 = bdx.n ? bdx.c[0] : 0.0, by1 = bdy.n ? bdy.c[0] : 0.0;
    const double cx1 = cdx.n ? cdx.c[0] : 0.0, cy1 = cdy.n ? cdy.c[0] : 0.0;
    auto cross4 = [](double px, double py, double qx, double qy, double* out) {
      double l1, l0, r1, r0;
      two_product(px, qy, l1, l0);
      two_product(-qx, py, r1, r0);  // negation is exact
      const double l[2] = {l0, l1}, r[2] = {r0, r1};
      double lz[2], rz[2];
      int ln = 0, rn = 0;
      for (double v : l)
        if (v != 0) lz[ln++] = v;
      for (double v : r)
        if (v != 0) rz[rn++] = v;
      return sum_raw(lz, ln, rz, rn, out);
    };
    // (ux^2 + uy^2) * cross: the lift is an exact expansion of at most 4 components; with coordinates of
    // few significant bits (float input, rounded origin) it is one component and this is one two-product.
    auto term = [](double ux, double uy, const double* cr, int crn, double* out) {
      double x1, x0, y1, y0;
      two_product(ux, ux, x1, x0);
      two_product(uy, uy, y1, y0);
      double xs[2], ys[2], lift[4], part[8], acc[32];
      int xn = 0, yn = 0;
      if (x0 != 0) xs[xn++] = x0;
      if (x1 != 0) xs[xn++] = x1;
      if (y0 != 0) ys[yn++] = y0;
      if (y1 != 0) ys[yn++] = y1;
      const int ln = sum_raw(xs, xn, ys, yn, lift);
      int on = 0;
      for (int k = 0; k < ln; ++k) {
        const int pn = scale_raw(cr, crn, lift[k], part);
        on = sum_raw(out, on, part, pn, acc);
        for (int i = 0; i < on; ++i) out[i] = acc[i];
      }
      return on;
    };
    double bc[4], ca[4], ab[4], ta[32], tb[32], tc[32], s1[64], s2[96];
    const int bcn = cross4(bx1, by1, cx1, cy1, bc);
    const int can = cross4(cx1, cy1, ax1, ay1, ca);
    const int abn = cross4(ax1, ay1, bx1, by1, ab);
    const int tan_ = term(ax1, ay1, bc, bcn, ta);
    const int tbn = term(bx1, by1, ca, can, tb);
    const int tcn = term(cx1, cy1, ab, abn, tc);
    const int s1n = sum_raw(ta, tan_, tb, tbn, s1);
    const int s2n = sum_raw(s1, s1n, tc, tcn, s2);
    return s2n == 0 ? 0.0 : s2[s2n - 1];
  }
  Fixed<512> ta, tb, tc;
  fmul(fsquare_norm(adx, ady), fcross(bdx, bdy, cdx, cdy), ta);
  fmul(fsquare_norm(bdx, bdy), fcross(cdx, cdy, adx, ady), tb);
  fmul(fsquare_norm(cdx, cdy), fcross(adx, ady, bdx, bdy), tc);
  Fixed<1024> s1;
  fsum(ta, tb, s1);
  Fixed<1536> s2;
  fsum(s1, tc, s2);
  return fsign(s2);
}

}  // namespace

namespace {

// incircle when every coordinate difference is exact and they have few bits (see few_bits); `done`
// tells whether it applied. Apart from the general path, whose expansions need a large stack frame.
double incircle_few_bits(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy,
                         bool& done) {
  done = false;
  const double d[6] = {ax - dx, ay - dy, bx - dx, by - dy, cx - dx, cy - dy};
  const double minuend[6] = {ax, ay, bx, by, cx, cy}, subtrahend[6] = {dx, dy, dx, dy, dx, dy};
  for (int k = 0; k < 6; ++k) {  // exact difference: its two-diff tail is zero
    const double bv = minuend[k] - d[k], av = d[k] + bv;
    if ((minuend[k] - av) + (bv - subtrahend[k]) != 0) return 0;
  }
  int lo;
  if (!few_bits(d, 6, lo)) return 0;
  done = true;
  if (lo > 240) return 0;  // every difference is zero (few_bits leaves lo unset): a, b, c, d coincide
  // In units of 2^lo the differences are integers below 2^26 (scaling by a power of two is exact): the
  // lifts and cross products are integers below 2^53, their products below 2^106, the sum of three
  // below 2^108: exact in 128-bit integers.
  std::uint64_t scale_bits = static_cast<std::uint64_t>(1023 - lo) << 52;  // 2^-lo, lo in [-240, 240]
  double scale;
  std::memcpy(&scale, &scale_bits, 8);
  std::int64_t q[6];
  for (int k = 0; k < 6; ++k) q[k] = static_cast<std::int64_t>(d[k] * scale);
  const std::int64_t L[3] = {q[0] * q[0] + q[1] * q[1], q[2] * q[2] + q[3] * q[3], q[4] * q[4] + q[5] * q[5]};
  const std::int64_t C[3] = {q[2] * q[5] - q[4] * q[3], q[4] * q[1] - q[0] * q[5], q[0] * q[3] - q[2] * q[1]};
  const __int128 det =
      static_cast<__int128>(L[0]) * C[0] + static_cast<__int128>(L[1]) * C[1] + static_cast<__int128>(L[2]) * C[2];
  return det > 0 ? 1.0 : (det < 0 ? -1.0 : 0.0);
}

}  // namespace

double incircle_exact(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy) {
  bool done;
  const double s = incircle_few_bits(ax, ay, bx, by, cx, cy, dx, dy, done);
  if (done) return s;
  return incircle_general(ax, ay, bx, by, cx, cy, dx, dy);
}

namespace {
Expansion orient_expansion(double ax, double ay, double bx, double by, double cx, double cy) {
  return cross(diff(ax, cx), diff(ay, cy), diff(bx, cx), diff(by, cy));
}
}  // namespace

int circumradius_vs_exact(double ax, double ay, double bx, double by, double cx, double cy, double R) {
  // Exact: sign(|ab|^2 |bc|^2 |ca|^2 - 4 R^2 D^2).
  const Expansion eab = square_norm(diff(ax, bx), diff(ay, by));
  const Expansion ebc = square_norm(diff(bx, cx), diff(by, cy));
  const Expansion eca = square_norm(diff(cx, ax), diff(cy, ay));
  Expansion n1, n, d2, r2, m;
  mul(eab, ebc, n1);
  mul(n1, eca, n);
  const Expansion d = orient_expansion(ax, ay, bx, by, cx, cy);
  mul(d, d, d2);
  double rh, rl;
  two_product(R, R, rh, rl);
  Expansion er;
  if (rl != 0) er.push_back(4 * rl);  // times 4 is exact
  if (rh != 0) er.push_back(4 * rh);
  mul(d2, er, m);
  negate(m);
  Expansion s;
  sum(n, m, s);
  const double v = sign_of(s);
  return v > 0 ? 1 : (v < 0 ? -1 : 0);
}

}  // namespace hg::outline::pred
