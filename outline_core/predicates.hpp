// Exact geometric predicates on doubles: orientation, incircle, circumradius-vs-R.
// Adaptive: a floating-point evaluation with a proven error bound decides almost always; when the bound
// cannot decide, the sign is computed exactly with floating-point expansions (Shewchuk's method:
// error-free two-sum / two-product, sums of non-overlapping components). Written from the published
// method. The library is compiled with -ffp-contract=off: a fused multiply-add would break the
// error-free transforms.
// Limits (exact as long as no intermediate overflows or underflows; only coordinate differences enter):
// with every coordinate a multiple of 2^-170 (no set bit below 2^-170, about 7e-52: true of any double of
// magnitude >= 1e-35 and of 0), every expansion component of a product of up to six differences is zero
// or at least 2^-1020, so nothing underflows. orient2d and incircle (degree 2 and 4) are then exact for
// differences up to 2^250 (1.8e75); circumradius_vs (degree 6, and R^2 D^2) for differences and R up to
// 2^165 (4.7e49), R also a multiple of 2^-170 (any R >= 1e-35). triangulate() enforces the resolution and a
// span below 1e60 (within the first bound); a larger span than 4.7e49 with the alpha test is not checked.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

namespace hg::outline::pred {

// a - b is a double exactly: the error term of the rounded subtraction (two-diff tail) is zero.
inline bool difference_is_exact(double a, double b) {
  const double x = a - b, bv = a - x, av = x + bv;
  return (a - av) + (bv - b) == 0;
}

// v is 0 or a multiple of 2^-170 (no set bit below 2^-170; subnormals never are): see the limits above.
inline bool within_exact_resolution(double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, 8);
  const int e = static_cast<int>((bits >> 52) & 0x7ff);
  const std::uint64_t mant = bits & ((std::uint64_t{1} << 52) - 1);
  if (e == 0) return mant == 0;                                                // zero, or subnormal
  return e - 1075 + __builtin_ctzll(mant | (std::uint64_t{1} << 52)) >= -170;  // v = mant' 2^(e - 1075)
}

inline constexpr double kEps = 1.1102230246251565e-16;  // 2^-53, half an ulp of 1
inline constexpr double kOrientBound = (3.0 + 16.0 * kEps) * kEps;
inline constexpr double kIncircleBound = (10.0 + 96.0 * kEps) * kEps;

// Exact signs, called only when the filter cannot decide.
double orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy);
double incircle_exact(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy);

// > 0: a, b, c counter-clockwise; < 0 clockwise; 0 collinear. Only the sign is meaningful.
inline double orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const double l = (ax - cx) * (by - cy);
  const double r = (ay - cy) * (bx - cx);
  const double det = l - r;
  const double bound = kOrientBound * (std::fabs(l) + std::fabs(r));
  // One test of the magnitude: a branch on det's sign here would be as unpredictable as the caller's.
  if (std::fabs(det) > bound) return det;
  return orient2d_exact(ax, ay, bx, by, cx, cy);
}

using v2 = double __attribute__((vector_size(16)));  // an (x, y) pair: SSE2 on x86-64 (baseline)
using v2i = long long __attribute__((vector_size(16)));

inline v2 lanes_lo(v2 u, v2 w) { return __builtin_shufflevector(u, w, 0, 2); }  // (u0, w0)
inline v2 lanes_hi(v2 u, v2 w) { return __builtin_shufflevector(u, w, 1, 3); }  // (u1, w1)
inline v2 swapped(v2 u) { return __builtin_shufflevector(u, u, 1, 0); }
inline v2 magnitude(v2 u) {  // |u| per lane: the sign bits cleared
  const v2i keep = {0x7fffffffffffffffLL, 0x7fffffffffffffffLL};
  return reinterpret_cast<v2>(reinterpret_cast<v2i>(u) & keep);
}
inline v2 vmin(v2 x, v2 y) { return y < x ? y : x; }  // std::min's choice, lane by lane
inline v2 vmax(v2 x, v2 y) { return x < y ? y : x; }  // std::max's
inline v2i normal(v2 x) {                             // all ones in a lane where x is normal (std::isnormal)
  const v2 m = magnitude(x);
  return (m >= std::numeric_limits<double>::min()) & (m <= std::numeric_limits<double>::max());
}

// > 0: d strictly inside the circle through a, b, c (a, b, c counter-clockwise); < 0 outside; 0 on it.
// The filter works on (x, y) pairs, arranged so that the a and b terms share one vector operation: the same
// operations on the same operands as the scalar formula
//   det = alift (bdx cdy - cdx bdy) + blift (cdx ady - adx cdy) + clift (adx bdy - bdx ady),
// in the same order, so the same rounded values and the same error bound (Shewchuk's incircle permanent).
inline double incircle_pairs(v2 A, v2 B, v2 C, v2 D) {
  const v2 a = A - D, b = B - D, c = C - D;  // (adx, ady), (bdx, bdy), (cdx, cdy)
  const v2 bc = b * swapped(c);              // (bdx cdy, bdy cdx)
  const v2 ca = c * swapped(a);              // (cdx ady, cdy adx)
  const v2 ab = a * swapped(b);              // (adx bdy, ady bdx)
  const v2 aa = a * a, bb = b * b, cc = c * c;
  const v2 lift_ab = lanes_lo(aa, bb) + lanes_hi(aa, bb);   // (alift, blift)
  const v2 cross_ab = lanes_lo(bc, ca) - lanes_hi(bc, ca);  // (bdx cdy - cdx bdy, cdx ady - adx cdy)
  const v2 perm_ab = magnitude(lanes_lo(bc, ca)) + magnitude(lanes_hi(bc, ca));
  const double clift = cc[0] + cc[1];
  const v2 terms = lift_ab * cross_ab, perms = perm_ab * lift_ab;
  const double det = terms[0] + terms[1] + clift * (ab[0] - ab[1]);
  const v2 abs_ab = magnitude(ab);
  const double permanent = perms[0] + perms[1] + (abs_ab[0] + abs_ab[1]) * clift;
  const double bound = kIncircleBound * permanent;
  if (std::fabs(det) > bound) return det;  // as orient2d: no branch on the sign
  return incircle_exact(A[0], A[1], B[0], B[1], C[0], C[1], D[0], D[1]);
}

inline double incircle(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy) {
  return incircle_pairs(v2{ax, ay}, v2{bx, by}, v2{cx, cy}, v2{dx, dy});
}

// The same on points stored as two consecutive doubles (x, y): loaded as pairs.
using v2_unaligned = double __attribute__((vector_size(16), aligned(8), may_alias));
inline double incircle_at(const double* a, const double* b, const double* c, const double* d) {
  auto load = [](const double* u) -> v2 { return *reinterpret_cast<const v2_unaligned*>(u); };
  return incircle_pairs(load(a), load(b), load(c), load(d));
}

// Sign of (circumradius of a, b, c)^2 - R^2 for a non-degenerate triangle: > 0 exactly when r > R.
// r^2 = |ab|^2 |bc|^2 |ca|^2 / (4 D^2), D = orient2d determinant; compared without division.
// The exact sign, called only when the filter below cannot decide.
int circumradius_vs_exact(double ax, double ay, double bx, double by, double cx, double cy, double R);
inline int circumradius_vs(double ax, double ay, double bx, double by, double cx, double cy, double R) {
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
  return circumradius_vs_exact(ax, ay, bx, by, cx, cy, R);
}

}  // namespace hg::outline::pred
