// Exact fallbacks of the predicates: floating-point expansions (a value is the exact sum of doubles of
// increasing magnitude that do not overlap). Implemented from Shewchuk, "Adaptive Precision
// Floating-Point Arithmetic and Fast Robust Geometric Predicates" (1997), section 2.
#include "predicates.hpp"

#include <cmath>
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
  if (e.empty()) { h = f; return; }
  if (f.empty()) { h = e; return; }
  Expansion g;
  g.reserve(e.size() + f.size());
  std::size_t i = 0, j = 0;
  while (i < e.size() && j < f.size()) {
    if (std::fabs(e[i]) < std::fabs(f[j])) g.push_back(e[i++]);
    else g.push_back(f[j++]);
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

Expansion orient_expansion(double ax, double ay, double bx, double by, double cx, double cy) {
  return cross(diff(ax, cx), diff(ay, cy), diff(bx, cx), diff(by, cy));
}

}  // namespace

double orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  return sign_of(orient_expansion(ax, ay, bx, by, cx, cy));
}

double incircle_exact(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy) {
  const Expansion adx = diff(ax, dx), ady = diff(ay, dy);
  const Expansion bdx = diff(bx, dx), bdy = diff(by, dy);
  const Expansion cdx = diff(cx, dx), cdy = diff(cy, dy);
  Expansion ta, tb, tc, s1, s2;
  mul(square_norm(adx, ady), cross(bdx, bdy, cdx, cdy), ta);
  mul(square_norm(bdx, bdy), cross(cdx, cdy, adx, ady), tb);
  mul(square_norm(cdx, cdy), cross(adx, ady, bdx, bdy), tc);
  sum(ta, tb, s1);
  sum(s1, tc, s2);
  return sign_of(s2);
}

int circumradius_vs(double ax, double ay, double bx, double by, double cx, double cy, double R) {
  // Filter. Relative rounding errors: each squared length <= 4.01 eps, the product N of three <= 14.1 eps.
  const double abx = ax - bx, aby = ay - by, bcx = bx - cx, bcy = by - cy, cax = cx - ax, cay = cy - ay;
  const double ab2 = abx * abx + aby * aby, bc2 = bcx * bcx + bcy * bcy, ca2 = cax * cax + cay * cay;
  const double N = ab2 * bc2 * ca2;
  const double l = (ax - cx) * (by - cy), r = (ay - cy) * (bx - cx);
  const double D = l - r;
  const double errD = kOrientBound * (std::fabs(l) + std::fabs(r));
  const double absD = std::fabs(D);
  if (absD > 4 * errD && std::isnormal(N)) {
    // |D - fl(D)| <= errD < |D| / 4, so the relative error of D is relD < (4/3) errD / |D| < 1/3 and that
    // of D^2 below 2.34 relD; M = 4 R^2 D^2 then errs by at most 2.5 relD M + 8 eps M, and
    // relD M < (4/3) errD |D| 4 R^2 (no division needed).
    const double R4 = 4.0 * (R * R);
    const double M = R4 * (D * D);
    const double margin = 1.01 * (16 * kEps * N + 2.5 * (4.0 / 3.0) * errD * absD * R4 + 8 * kEps * M);
    if (std::isnormal(M)) {
      if (N - M > margin) return 1;
      if (M - N > margin) return -1;
    }
  }
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
